// The ContactPairs debug channel as a client receives it: check_contact_pairs (the only gate
// before a client draws the pairs), then what the viewer makes of an accepted message
// (contacts_json). Input: one ContactPairs in fuzz_bytes.h's layout.
#include <cstdint>
#include <cstdlib>

#include "fuzz_bytes.h"
#include "throng/protocol/contacts.h"
#include "throng/view/gateway.h"

using namespace throng;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  fuzz::In in(data, size);
  const protocol::ContactPairs c = fuzz::read_contacts(in);
  if (protocol::check_contact_pairs(c)) return 0;  // refused with a reason: nothing else reads it
  (void)protocol::contact_pairs_wire_bytes(c);
  const std::string json = view::contacts_json(c);
  if (json.empty()) std::abort();
  return 0;
}
