// Parameter-table documents (parse_param_table: --params files, scenes' inline "params", match log
// headers). Bad input throws ConfigError naming the field. Input: JSON text.
#include <cstdint>
#include <string_view>

#include "throng/params/config_error.h"
#include "throng/params/param_table.h"
#include "throng/params/params_json.h"

using namespace throng;

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    (void)params::parse_param_table(std::string_view(reinterpret_cast<const char*>(data), size));
  } catch (const params::ConfigError&) {
  }
  return 0;
}
