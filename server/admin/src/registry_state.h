// What MetricsRegistry keeps: prometheus-cpp's registry, which owns the metrics and renders them,
// and per family what prometheus-cpp does not check (help, label names), plus the handles it
// hands out.
#pragma once

#include <deque>
#include <mutex>
#include <string>
#include <vector>

#include <prometheus/registry.h>

#include "throng/admin/metrics.h"

namespace throng::admin {

enum class MetricType { counter, gauge, histogram };

struct RegistryState {
  struct Family {
    std::string name;
    std::string help;
    MetricType type = MetricType::counter;
    std::vector<std::string> label_names;  // sorted, as prometheus-cpp renders them
  };

  // Serialises registrations; render() needs no lock of ours, prometheus-cpp locks its own storage.
  std::mutex mutex;
  std::vector<Family> families;
  prometheus::Registry registry;
  // Deques: a handle's address stays valid as more are added.
  std::deque<Counter> counters;
  std::deque<Gauge> gauges;
  std::deque<Histogram> histograms;
};

}  // namespace throng::admin
