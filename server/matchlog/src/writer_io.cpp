// Durable writes, record framing and block bodies shared by the writer's parts (writer_io.h).
#include "writer_io.h"

#include <unistd.h>

#include <cerrno>
#include <cstring>

#include <zstd.h>

#include "throng/core/byte_io.h"
#include "throng/matchlog/crc32c.h"

namespace throng::matchlog::detail {

std::string write_all(int fd, const std::uint8_t* p, std::size_t n) {
  while (n > 0) {
    const ssize_t w = ::write(fd, p, n);
    if (w < 0) {
      if (errno == EINTR) continue;
      return std::strerror(errno);
    }
    p += w;
    n -= static_cast<std::size_t>(w);
  }
  return {};
}

std::string read_all_at(int fd, std::uint8_t* p, std::size_t n, std::uint64_t offset) {
  while (n > 0) {
    const ssize_t r = ::pread(fd, p, n, static_cast<off_t>(offset));
    if (r < 0) {
      if (errno == EINTR) continue;
      return std::strerror(errno);
    }
    if (r == 0) return "the file ends early";
    p += r;
    n -= static_cast<std::size_t>(r);
    offset += static_cast<std::uint64_t>(r);
  }
  return {};
}

void frame_record(RecordType type, const std::vector<std::uint8_t>& payload, std::vector<std::uint8_t>& out) {
  const std::size_t start = out.size();
  ByteWriter(out).put<std::uint32_t>(static_cast<std::uint32_t>(payload.size()));
  ByteWriter(out).put<std::uint8_t>(static_cast<std::uint8_t>(type));
  out.insert(out.end(), payload.begin(), payload.end());
  ByteWriter(out).put<std::uint32_t>(crc32c(out.data() + start, out.size() - start));
}

void append_body(void* zctx, int zstd_level, const std::vector<std::uint8_t>& raw, std::vector<std::uint8_t>& scratch,
                 std::vector<std::uint8_t>& payload) {
  BlockCodec codec = BlockCodec::raw;
  if (zctx != nullptr) {
    scratch.resize(ZSTD_compressBound(raw.size()));
    const std::size_t n =
        ZSTD_compressCCtx(static_cast<ZSTD_CCtx*>(zctx), scratch.data(), scratch.size(), raw.data(), raw.size(), zstd_level);
    if (!ZSTD_isError(n) && n < raw.size()) {  // stored raw when zstd does not make it smaller
      scratch.resize(n);
      codec = BlockCodec::zstd;
    }
  }
  ByteWriter(payload).put<std::uint8_t>(static_cast<std::uint8_t>(codec));
  ByteWriter(payload).put<std::uint32_t>(static_cast<std::uint32_t>(raw.size()));
  const std::vector<std::uint8_t>& body = codec == BlockCodec::zstd ? scratch : raw;
  payload.insert(payload.end(), body.begin(), body.end());
}

}  // namespace throng::matchlog::detail
