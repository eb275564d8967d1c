// The match log's header record (JSON: build, match id, the whole scene, the match config, writer
// settings) as the reader decodes it. Input: the record's JSON text. Bad input throws LogError.
#include <cstdint>
#include <string>

#include "throng/matchlog/format.h"
#include "throng/matchlog/log_header.h"

using namespace throng;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  try {
    const matchlog::LogHeader h = matchlog::header_from_json_text(text);
    (void)matchlog::header_to_json_text(h);
  } catch (const matchlog::LogError&) {
  }
  return 0;
}
