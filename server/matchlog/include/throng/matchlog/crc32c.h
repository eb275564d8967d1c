#pragma once
// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78), the checksum of every match-log record.
// SSE4.2's crc32 instruction when the CPU has it (checked at run time), else a slicing-by-8
// table, so the same binary runs on every x86-64 and ARM machine. crc32c("123456789") == 0xE3069283.
#include <cstddef>
#include <cstdint>
#include <span>
#include <string_view>

namespace throng::matchlog {

// Continues a running CRC: crc32c_update(crc32c_update(0, a), b) == crc32c(a followed by b).
std::uint32_t crc32c_update(std::uint32_t crc, const void* data, std::size_t size);

namespace detail {
// The table version alone (what crc32c_update uses without SSE4.2), for tests.
std::uint32_t crc32c_update_table(std::uint32_t crc, const void* data, std::size_t size);
}  // namespace detail

inline std::uint32_t crc32c(const void* data, std::size_t size) { return crc32c_update(0, data, size); }
inline std::uint32_t crc32c(std::span<const std::uint8_t> bytes) { return crc32c(bytes.data(), bytes.size()); }
inline std::uint32_t crc32c(std::string_view text) { return crc32c(text.data(), text.size()); }

}  // namespace throng::matchlog
