#pragma once
// The ContactPairs debug channel's units: how a pair's push ratio and depths are quantized, how a
// message is checked on arrival, and its size on the wire.
//
//  - share_a: round(share * 65535), so a ratio survives to 1.5e-5 (a page shows "70/30").
//  - depth, push: 0.1 mm steps in 16 bits (saturate at 6.5535 m; a contact is never that deep).
//  - Wire size (XCDR1, 4-byte encapsulation included): 56 bytes + 14 per pair, + 4 of alignment
//    padding when the pair count is odd (contact_pairs_wire_bytes() is the serialized size the
//    writer counts, checked against the DDS serialization in tests/protocol; RTPS then pads the
//    payload to a multiple of 4, so a reader sees 2 bytes more for an odd count).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "throng/protocol/messages.h"

namespace throng::protocol {

inline constexpr double kShareScale = 65535.0;
inline constexpr double kContactUnitM = 1e-4;  // 0.1 mm

std::uint16_t quantize_share(double share);       // clamped to [0, 1] first; NaN -> 0
double dequantize_share(std::uint16_t q);         // in [0, 1]
std::uint16_t quantize_contact_m(double metres);  // clamped to [0, 65535 steps]; NaN -> 0
double dequantize_contact_m(std::uint16_t q);

// Appends one pair (the caller keeps pairs nearest-first).
void push_contact(ContactPairs& m, std::uint32_t a, std::uint32_t b, double share_a, double depth_m, double push_m);

// Why a received message cannot be used (arrays of different lengths, an id 0, more pairs than
// pairs_near), or nullopt. Clients check before drawing: nothing a peer sends is trusted.
std::optional<std::string> check_contact_pairs(const ContactPairs& m);

// Serialized payload size in XCDR1 (what the DDS sample carries, without RTPS headers).
std::size_t contact_pairs_wire_bytes(const ContactPairs& m);

}  // namespace throng::protocol
