// render(): prometheus-cpp's TextSerializer over its registry, in a stable order.
#include <algorithm>
#include <vector>

#include <prometheus/text_serializer.h>

#include "registry_state.h"
#include "throng/admin/metrics.h"

namespace throng::admin {

std::string MetricsRegistry::render() const {
  std::string out;
  render_to(out);
  return out;
}

void MetricsRegistry::render_to(std::string& out) const {
  std::vector<prometheus::MetricFamily> families = state_->registry.Collect();
  // Collect() groups families by type and yields a family's series in hash order: sort both, so two
  // scrapes of the same registry diff line by line.
  std::sort(families.begin(), families.end(), [](const auto& a, const auto& b) { return a.name < b.name; });
  for (auto& family : families) {
    std::sort(family.metric.begin(), family.metric.end(),
              [](const auto& a, const auto& b) { return a.label < b.label; });
  }
  out += prometheus::TextSerializer().Serialize(families);
}

}  // namespace throng::admin
