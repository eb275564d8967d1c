// Registration: our checks first (so a rejected series leaves no trace), then the series goes into
// prometheus-cpp's registry and the caller gets a handle onto it.
#include <algorithm>
#include <optional>
#include <string>

#include <prometheus/counter.h>
#include <prometheus/family.h>
#include <prometheus/gauge.h>
#include <prometheus/histogram.h>

#include "metrics_validation.h"
#include "registry_state.h"
#include "throng/admin/metrics.h"

namespace throng::admin {
namespace {

using validation::reject;

std::string_view type_name(MetricType type) {
  switch (type) {
    case MetricType::counter: return "counter";
    case MetricType::gauge: return "gauge";
    case MetricType::histogram: return "histogram";
  }
  return "untyped";
}

// Caller holds state.mutex. Throws unless the series fits its family; returns the family's record
// when the family is new (to keep once the series is in), nothing when it exists already.
// prometheus-cpp would merge a family registered again with another help text or label names, and
// would throw for another type without naming the metric.
std::optional<RegistryState::Family> admit(const RegistryState& state, std::string_view name,
                                                    std::string_view help, MetricType type, const Labels& labels) {
  validation::check_name(name);
  validation::check_help(name, help);
  validation::check_labels(name, type, labels);

  std::vector<std::string> label_names;
  for (const auto& label : labels) label_names.push_back(label.first);
  std::sort(label_names.begin(), label_names.end());

  for (const auto& family : state.families) {
    if (family.name != name) continue;
    if (family.type != type) reject(name, "already registered as a " + std::string(type_name(family.type)));
    if (family.help != help) reject(name, "already registered with a different help text");
    if (family.label_names != label_names) reject(name, "every series of a family needs the same label names");
    return std::nullopt;
  }

  const auto new_names = validation::sample_names(name, type);
  for (const auto& family : state.families) {
    for (const auto& taken : validation::sample_names(family.name, family.type)) {
      if (std::find(new_names.begin(), new_names.end(), taken) != new_names.end()) {
        reject(name, "clashes with the samples of " + family.name);
      }
    }
  }
  return RegistryState::Family{std::string(name), std::string(help), type, std::move(label_names)};
}

// Caller holds state.mutex. `args` are the metric's constructor arguments (a histogram's bounds).
template <class Metric, class... Args>
Metric& add_series(RegistryState& state, prometheus::detail::Builder<Metric> builder, std::string_view name,
                   std::string_view help, MetricType type, const Labels& labels, Args&&... args) {
  auto new_family = admit(state, name, help, type, labels);
  // With the registry's default InsertBehavior::Merge, registering an existing name returns its family.
  prometheus::Family<Metric>& family = builder.Name(std::string(name)).Help(std::string(help)).Register(state.registry);
  const prometheus::Labels series_labels(labels.begin(), labels.end());
  // Family::Add would hand back the existing series instead of refusing it.
  if (family.Has(series_labels)) reject(name, "this label set is already registered");
  Metric& metric = family.Add(series_labels, std::forward<Args>(args)...);
  if (new_family) state.families.push_back(std::move(*new_family));
  return metric;
}

}  // namespace

MetricsRegistry::MetricsRegistry() : state_(std::make_unique<RegistryState>()) {}
MetricsRegistry::~MetricsRegistry() = default;

Counter& MetricsRegistry::counter(std::string_view name, std::string_view help, const Labels& labels) {
  std::lock_guard lock(state_->mutex);
  auto& metric = add_series(*state_, prometheus::BuildCounter(), name, help, MetricType::counter, labels);
  return state_->counters.emplace_back(metric);
}

Gauge& MetricsRegistry::gauge(std::string_view name, std::string_view help, const Labels& labels) {
  std::lock_guard lock(state_->mutex);
  auto& metric = add_series(*state_, prometheus::BuildGauge(), name, help, MetricType::gauge, labels);
  return state_->gauges.emplace_back(metric);
}

Histogram& MetricsRegistry::histogram(std::string_view name, std::string_view help, std::vector<double> bounds,
                                      const Labels& labels) {
  std::lock_guard lock(state_->mutex);
  validation::check_bounds(name, bounds);
  auto& metric = add_series(*state_, prometheus::BuildHistogram(), name, help, MetricType::histogram, labels, bounds);
  return state_->histograms.emplace_back(metric);
}

}  // namespace throng::admin
