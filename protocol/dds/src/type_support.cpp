#include "type_support.h"

namespace throng::protocol::dds_detail {

std::size_t& last_serialized_bytes() {
  thread_local std::size_t bytes = 0;
  return bytes;
}

std::size_t& last_deserialized_bytes() {
  thread_local std::size_t bytes = 0;
  return bytes;
}

}  // namespace throng::protocol::dds_detail
