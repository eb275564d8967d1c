// render(): text exposition format 0.0.4, families and series in registration order.
#include "exposition.h"
#include "family.h"
#include "throng/admin/metrics.h"

namespace throng::admin {
namespace {

void append_sample(std::string& out, std::string_view name, std::string_view suffix, std::string_view label_block) {
  out += name;
  out += suffix;
  out += label_block;
  out += ' ';
}

void render_histogram(std::string& out, std::string_view name, const Histogram& h,
                      const std::vector<std::string>& bucket_blocks, std::string_view label_block) {
  // Buckets are cumulative; summing our slots in one pass keeps every bucket >= the one before and
  // makes _count equal the +Inf bucket even while observe() runs concurrently.
  std::uint64_t cumulative = 0;
  for (std::size_t i = 0; i < bucket_blocks.size(); ++i) {
    cumulative += h.slot_count(i);
    append_sample(out, name, "_bucket", bucket_blocks[i]);
    exposition::append_uint(out, cumulative);
    out += '\n';
  }
  append_sample(out, name, "_sum", label_block);
  exposition::append_double(out, h.sum());
  out += '\n';
  append_sample(out, name, "_count", label_block);
  exposition::append_uint(out, cumulative);
  out += '\n';
}

}  // namespace

std::string MetricsRegistry::render() const {
  std::string out;
  render_to(out);
  return out;
}

void MetricsRegistry::render_to(std::string& out) const {
  std::lock_guard lock(mutex_);
  for (const auto& family : families_) {
    if (family->series.empty()) continue;
    out += family->header;
    for (const auto& series : family->series) {
      switch (family->type) {
        case MetricType::counter:
          append_sample(out, family->name, "", series.label_block);
          exposition::append_uint(out, series.counter->value());
          out += '\n';
          break;
        case MetricType::gauge:
          append_sample(out, family->name, "", series.label_block);
          exposition::append_double(out, series.gauge->value());
          out += '\n';
          break;
        case MetricType::histogram:
          render_histogram(out, family->name, *series.histogram, series.bucket_blocks, series.label_block);
          break;
      }
    }
  }
}

}  // namespace throng::admin
