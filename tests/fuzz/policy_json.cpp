// Push-policy documents (parse_push_policy: --policy files, scenes' inline "policy", and the
// operator's ParamUpdate.policy_json sent over the network at run time). Bad input throws
// ConfigError naming the field. Input: JSON text.
#include <cstdint>
#include <string_view>

#include "throng/params/config_error.h"
#include "throng/params/params_json.h"
#include "throng/params/push_policy.h"

using namespace throng;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)params::parse_push_policy(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const params::ConfigError&) {
  }
  return 0;
}
