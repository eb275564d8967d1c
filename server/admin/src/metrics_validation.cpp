#include "metrics_validation.h"

#include <cmath>
#include <stdexcept>

#include <prometheus/check_names.h>

namespace throng::admin::validation {

void reject(std::string_view name, std::string_view why) {
  throw std::invalid_argument("metrics: " + std::string(name) + ": " + std::string(why));
}

void check_name(std::string_view name) {
  if (!name.starts_with(MetricsRegistry::required_prefix)) reject(name, "metric names must start with \"throng_\"");
  // Colons are valid Prometheus but reserved for recording rules, so exporters must not use them.
  if (!prometheus::CheckMetricName(std::string(name)) || name.find(':') != std::string_view::npos) {
    reject(name, "metric names may only hold [a-zA-Z0-9_]");
  }
}

void check_help(std::string_view name, std::string_view help) {
  if (help.empty()) reject(name, "help text must not be empty");
  // prometheus-cpp's TextSerializer writes HELP verbatim: a newline would end the line early and a
  // backslash would start an escape the scraper misreads.
  if (help.find_first_of("\n\\") != std::string_view::npos) {
    reject(name, "help text must not hold a newline or backslash");
  }
}

void check_labels(std::string_view name, MetricType type, const Labels& labels) {
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const std::string& key = labels[i].first;
    // CheckLabelName also refuses the reserved "__" prefix.
    if (!prometheus::CheckLabelName(key)) reject(name, "invalid label name \"" + key + "\"");
    if (type == MetricType::histogram && key == "le") reject(name, "histograms cannot use the label \"le\"");
    // prometheus::Labels is a map: a repeated name would silently keep only one value.
    for (std::size_t j = 0; j < i; ++j) {
      if (labels[j].first == key) reject(name, "label \"" + key + "\" given twice");
    }
  }
}

void check_bounds(std::string_view name, const std::vector<double>& bounds) {
  // prometheus-cpp checks the order only once the family exists, and lets NaN and +Inf through.
  for (std::size_t i = 0; i < bounds.size(); ++i) {
    if (!std::isfinite(bounds[i])) reject(name, "histogram bounds must be finite (+Inf is implicit)");
    if (i > 0 && !(bounds[i - 1] < bounds[i])) reject(name, "histogram bounds must be strictly increasing");
  }
}

std::vector<std::string> sample_names(std::string_view name, MetricType type) {
  std::string n(name);
  if (type != MetricType::histogram) return {n};
  return {n, n + "_bucket", n + "_sum", n + "_count"};
}

}  // namespace throng::admin::validation
