#pragma once
// Snapshot pose encoding: quantization and the structure-of-arrays packing of Snapshot.
//
// Per object 9 bytes: a 16-bit id code, x/y/z as 16-bit offsets in `unit_mm` steps, yaw in 8 bits;
// 7 bytes when every pose of the snapshot has the same height (see z below).
//  - id codes: ids are written in ascending order as deltas from the previous id (the first from
//    0). A delta in 1..65535 is one code; anything else is the escape code 0 followed by the id's
//    high and low 16 bits. Sorted crowds give one code per object.
//  - x, y: round((v - origin) / unit) as int16, so the interest area must fit within
//    +-32767 units of the origin (+-32.7 m at 1 mm). The encoder refuses (returns false) rather
//    than wrap.
//  - z: round(z / unit) as int16 (absolute height, +-32.7 m at 1 mm). When two or more poses all
//    have the same quantized height, z holds that one value instead of n copies: a crowd standing
//    on flat ground mostly shares one height, and this saves 2 of the 9 bytes a pose costs. A
//    decoder accepts z with one element per pose, or exactly one element for any number >= 1.
//  - yaw: round(yaw * 256 / 2pi) mod 256, a step of 1.41 degrees.
// Round-trip error: at most unit/2 per axis, at most pi/256 rad in yaw (tests/protocol).
#include <cstddef>
#include <cstdint>
#include <optional>
#include <span>
#include <stdexcept>
#include <vector>

#include "throng/protocol/messages.h"

namespace throng::protocol {

struct Pose {
  std::uint32_t id = 0;
  double x = 0, y = 0, z = 0, yaw = 0;
};

inline constexpr std::size_t kPoseWireBytes = 9;        // with its own height
inline constexpr std::size_t kSharedZPoseWireBytes = 7;  // when the snapshot's poses share one height
inline constexpr double kPi = 3.14159265358979323846;

class DecodeError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// Quantizes v relative to origin_mm in unit_mm steps; nullopt when it does not fit in int16 or v
// is not finite.
std::optional<std::int16_t> quantize_offset(double v_m, std::int32_t origin_mm, std::uint16_t unit_mm);
double dequantize_offset(std::int16_t q, std::int32_t origin_mm, std::uint16_t unit_mm);
std::uint8_t quantize_yaw(double yaw_rad);
double dequantize_yaw(std::uint8_t q);  // in (-pi, pi]

// Metres the offsets can reach either side of the origin at this unit.
inline double offset_range_m(std::uint16_t unit_mm) { return 32767.0 * unit_mm / 1000.0; }

// Sets snap.origin_*/unit_mm and fills the pose arrays (clears them first). Poses must be sorted
// by id with no duplicates, else std::invalid_argument. Returns false (and leaves the arrays
// empty) when a pose does not fit the origin/unit range or is not finite. Writes one shared z
// when two or more poses have the same quantized height (see z above).
bool encode_poses(std::span<const Pose> poses, std::int32_t origin_x_mm, std::int32_t origin_y_mm,
                  std::uint16_t unit_mm, Snapshot& snap);

// Appends the decoded poses to out. Throws DecodeError on malformed input (array lengths that
// disagree — z may also hold one shared value —, a truncated escape, ids not ascending, unit 0).
void decode_poses(const Snapshot& snap, std::vector<Pose>& out);

// Replaces z (one height per pose) by the single shared value when there are two or more poses
// and all heights are equal; the encoder and the server's snapshot builder both end with it.
void share_equal_heights(Snapshot& snap);

// Serialized size of the snapshot's payload in XCDR1 (what the DDS sample carries, without the
// RTPS headers): used for the bytes-published metric and the wire-size report.
std::size_t snapshot_wire_bytes(const Snapshot& snap);

}  // namespace throng::protocol
