// The registration checks prometheus-cpp does not make (or makes without naming the metric): our
// name prefix, help text it would print unescaped, repeated or reserved label names, histogram
// bounds, and families whose samples would collide.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include "registry_state.h"
#include "throng/admin/metrics.h"

namespace throng::admin::validation {

// Throws std::invalid_argument naming the metric.
[[noreturn]] void reject(std::string_view name, std::string_view why);

void check_name(std::string_view name);
void check_help(std::string_view name, std::string_view help);
void check_labels(std::string_view name, MetricType type, const Labels& labels);
void check_bounds(std::string_view name, const std::vector<double>& bounds);

// The sample names a family emits; two families clash if these overlap (a histogram "x" owns
// "x_bucket", "x_sum" and "x_count").
std::vector<std::string> sample_names(std::string_view name, MetricType type);

}  // namespace throng::admin::validation
