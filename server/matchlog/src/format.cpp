#include "throng/matchlog/format.h"

namespace throng::matchlog {

const char* to_string(RecordType t) {
  switch (t) {
    case RecordType::header: return "header";
    case RecordType::tick_block: return "tick block";
    case RecordType::index: return "index";
    case RecordType::gap: return "gap";
    case RecordType::end: return "end";
    case RecordType::keyframe: return "keyframe";
  }
  return "unknown";
}

bool is_known_record_type(std::uint8_t t) { return t >= 1 && t <= 6; }

}  // namespace throng::matchlog
