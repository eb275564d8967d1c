#include "throng/protocol/messages.h"

namespace throng::protocol {

const char* to_string(JoinResult r) {
  switch (r) {
    case JoinResult::accepted: return "accepted";
    case JoinResult::match_full: return "match_full";
    case JoinResult::bad_version: return "bad_version";
    case JoinResult::shutting_down: return "shutting_down";
    case JoinResult::bad_request: return "bad_request";
    case JoinResult::left: return "left";
    case JoinResult::foreign_participant: return "foreign_participant";
  }
  return "unknown";
}

}  // namespace throng::protocol
