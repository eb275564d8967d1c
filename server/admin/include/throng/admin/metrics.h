// MetricsRegistry: the server's Prometheus metrics, registered once at start-up and rendered by the
// admin endpoint in text exposition format 0.0.4. Storage and rendering are prometheus-cpp's
// (prometheus::Registry, prometheus::TextSerializer); this facade adds the checks it does not make
// and keeps prometheus-cpp out of the callers' headers.
//
//   MetricsRegistry reg;
//   Counter& ticks = reg.counter("throng_ticks_total", "Simulation ticks run.");
//   Counter& nan = reg.counter("throng_commands_rejected_total", "Commands rejected, by reason.",
//                              {{"reason", "nan"}});
//   Histogram& tick = reg.histogram("throng_tick_seconds", "Tick duration.", {0.001, 0.005, 0.016});
//   ticks.inc(); tick.observe(0.004);   // tick thread: no allocation
//   std::string text = reg.render();    // admin thread
//
// Series sharing a name form one family (one # HELP / # TYPE block); they must agree on type, help
// and label names. Families render sorted by name and the series inside them by label values, so
// the output is deterministic and diffable; a series' labels render sorted by label name.
#pragma once

#include <memory>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "throng/admin/metric_types.h"

namespace throng::admin {

struct RegistryState;  // src/registry_state.h: prometheus-cpp's registry and our per-family records

// Label name/value pairs of one series (rendered sorted by name, whatever the order here).
using Labels = std::vector<std::pair<std::string, std::string>>;

class MetricsRegistry {
 public:
  MetricsRegistry();
  ~MetricsRegistry();
  MetricsRegistry(const MetricsRegistry&) = delete;
  MetricsRegistry& operator=(const MetricsRegistry&) = delete;

  // Each registers one series and returns a reference that stays valid for the registry's lifetime.
  // Throws std::invalid_argument when: the name does not start with "throng_" or is not a valid
  // Prometheus name; help is empty or holds a newline or backslash; a label name is invalid,
  // repeated, starts with "__" (or is "le" on a histogram); the family already exists with another
  // type, help or label names; the exact label set is already registered; histogram bounds are not
  // finite and strictly increasing. Thread-safe, but meant for start-up.
  Counter& counter(std::string_view name, std::string_view help, const Labels& labels = {});
  Gauge& gauge(std::string_view name, std::string_view help, const Labels& labels = {});
  Histogram& histogram(std::string_view name, std::string_view help, std::vector<double> bounds,
                       const Labels& labels = {});

  // Text exposition format 0.0.4 (what GET /metrics serves). Safe to call while other threads
  // update or register metrics; each histogram is copied whole under its lock, the whole text is
  // not a single snapshot. Series sorted by family name, then labels; numbers with 16 significant
  // digits; NaN spelled "Nan" (prometheus-cpp's TextSerializer).
  std::string render() const;
  void render_to(std::string& out) const;  // appends the text render() returns

  static constexpr std::string_view required_prefix = "throng_";

 private:
  std::unique_ptr<RegistryState> state_;
};

}  // namespace throng::admin
