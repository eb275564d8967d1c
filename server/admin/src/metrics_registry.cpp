// Registration: validates names, labels and bounds, and pre-renders the text render() will need.
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "exposition.h"
#include "family.h"
#include "throng/admin/metrics.h"

namespace throng::admin {
namespace {

[[noreturn]] void reject(std::string_view name, std::string_view why) {
  throw std::invalid_argument("metrics: " + std::string(name) + ": " + std::string(why));
}

std::string_view type_name(MetricType type) {
  switch (type) {
    case MetricType::counter: return "counter";
    case MetricType::gauge: return "gauge";
    case MetricType::histogram: return "histogram";
  }
  return "untyped";
}

// The sample names a family emits; two families clash if these overlap (a histogram "x" owns
// "x_bucket", "x_sum" and "x_count").
std::vector<std::string> sample_names(std::string_view name, MetricType type) {
  std::string n(name);
  if (type != MetricType::histogram) return {n};
  return {n, n + "_bucket", n + "_sum", n + "_count"};
}

void validate_name(std::string_view name) {
  if (!name.starts_with(MetricsRegistry::required_prefix)) reject(name, "metric names must start with \"throng_\"");
  // Colons are valid Prometheus but reserved for recording rules, so exporters must not use them.
  if (!exposition::valid_metric_name(name) || name.find(':') != std::string_view::npos) {
    reject(name, "metric names may only hold [a-zA-Z0-9_]");
  }
}

void validate_labels(std::string_view name, MetricType type, const Labels& labels) {
  for (std::size_t i = 0; i < labels.size(); ++i) {
    const std::string& key = labels[i].first;
    if (!exposition::valid_label_name(key)) reject(name, "invalid label name \"" + key + "\"");
    if (key.starts_with("__")) reject(name, "label names starting with \"__\" are reserved");
    if (type == MetricType::histogram && key == "le") reject(name, "histograms cannot use the label \"le\"");
    for (std::size_t j = 0; j < i; ++j) {
      if (labels[j].first == key) reject(name, "label \"" + key + "\" given twice");
    }
  }
}

void validate_bounds(std::string_view name, const std::vector<double>& bounds) {
  for (std::size_t i = 0; i < bounds.size(); ++i) {
    if (!std::isfinite(bounds[i])) reject(name, "histogram bounds must be finite (+Inf is implicit)");
    if (i > 0 && !(bounds[i - 1] < bounds[i])) reject(name, "histogram bounds must be strictly increasing");
  }
}

// `{a="x",b="y"` without the closing brace, so histogram buckets can append `,le="..."`.
std::string open_label_block(const Labels& labels) {
  std::string out;
  for (const auto& [key, value] : labels) {
    out += out.empty() ? "{" : ",";
    out += key;
    out += "=\"";
    exposition::append_escaped_label_value(out, value);
    out += '"';
  }
  return out;
}

std::vector<std::string> bucket_blocks(const std::string& open_block, const std::vector<double>& bounds) {
  std::vector<std::string> out;
  out.reserve(bounds.size() + 1);
  const std::string prefix = open_block.empty() ? "{le=\"" : open_block + ",le=\"";
  for (std::size_t i = 0; i <= bounds.size(); ++i) {
    std::string block = prefix;
    exposition::append_double(block, i < bounds.size() ? bounds[i] : INFINITY);
    block += "\"}";
    out.push_back(std::move(block));
  }
  return out;
}

}  // namespace

MetricsRegistry::MetricsRegistry() = default;
MetricsRegistry::~MetricsRegistry() = default;

// Caller holds mutex_. Finds the family or creates it; either way the new series must fit it.
MetricsRegistry::Family& MetricsRegistry::family_for(std::string_view name, std::string_view help, MetricType type,
                                                     const Labels& labels) {
  validate_name(name);
  if (help.empty()) reject(name, "help text must not be empty");
  validate_labels(name, type, labels);

  std::vector<std::string> label_names;
  for (const auto& label : labels) label_names.push_back(label.first);

  for (auto& family : families_) {
    if (family->name != name) continue;
    if (family->type != type) reject(name, "already registered as a " + std::string(type_name(family->type)));
    if (family->help != help) reject(name, "already registered with a different help text");
    if (family->label_names != label_names) reject(name, "every series of a family needs the same label names");
    for (const auto& series : family->series) {
      if (series.labels == labels) reject(name, "this label set is already registered");
    }
    return *family;
  }

  const auto new_names = sample_names(name, type);
  for (const auto& family : families_) {
    for (const auto& taken : sample_names(family->name, family->type)) {
      if (std::find(new_names.begin(), new_names.end(), taken) != new_names.end()) {
        reject(name, "clashes with the samples of " + family->name);
      }
    }
  }

  auto family = std::make_unique<Family>();
  family->name = std::string(name);
  family->help = std::string(help);
  family->type = type;
  family->label_names = std::move(label_names);
  family->header = "# HELP " + family->name + " ";
  exposition::append_escaped_help(family->header, help);
  family->header += "\n# TYPE " + family->name + " " + std::string(type_name(type)) + "\n";
  families_.push_back(std::move(family));
  return *families_.back();
}

Counter& MetricsRegistry::counter(std::string_view name, std::string_view help, const Labels& labels) {
  std::lock_guard lock(mutex_);
  Family& family = family_for(name, help, MetricType::counter, labels);
  Family::Series series;
  series.labels = labels;
  series.label_block = open_label_block(labels);
  if (!series.label_block.empty()) series.label_block += '}';
  series.counter = std::make_unique<Counter>();
  family.series.push_back(std::move(series));
  return *family.series.back().counter;
}

Gauge& MetricsRegistry::gauge(std::string_view name, std::string_view help, const Labels& labels) {
  std::lock_guard lock(mutex_);
  Family& family = family_for(name, help, MetricType::gauge, labels);
  Family::Series series;
  series.labels = labels;
  series.label_block = open_label_block(labels);
  if (!series.label_block.empty()) series.label_block += '}';
  series.gauge = std::make_unique<Gauge>();
  family.series.push_back(std::move(series));
  return *family.series.back().gauge;
}

Histogram& MetricsRegistry::histogram(std::string_view name, std::string_view help, std::vector<double> bounds,
                                      const Labels& labels) {
  std::lock_guard lock(mutex_);
  validate_bounds(name, bounds);
  Family& family = family_for(name, help, MetricType::histogram, labels);
  Family::Series series;
  series.labels = labels;
  series.label_block = open_label_block(labels);
  series.bucket_blocks = bucket_blocks(series.label_block, bounds);
  if (!series.label_block.empty()) series.label_block += '}';
  series.histogram = std::make_unique<Histogram>(std::move(bounds));
  family.series.push_back(std::move(series));
  return *family.series.back().histogram;
}

}  // namespace throng::admin
