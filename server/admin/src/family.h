// What the registry stores per metric family. Everything textual (the HELP/TYPE header, each
// series' label block, each histogram bucket's label block) is rendered once at registration, so a
// scrape only formats numbers.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "throng/admin/metrics.h"

namespace throng::admin {

struct MetricsRegistry::Family {
  struct Series {
    Labels labels;
    std::string label_block;                 // `{a="x",b="y"}`, or empty without labels
    std::vector<std::string> bucket_blocks;  // histogram only: `{a="x",le="0.5"}` per bound, then +Inf
    std::unique_ptr<Counter> counter;        // exactly one of the three is set, by the family type
    std::unique_ptr<Gauge> gauge;
    std::unique_ptr<Histogram> histogram;
  };

  std::string name;
  std::string help;
  MetricType type = MetricType::counter;
  std::vector<std::string> label_names;  // every series has these, in this order
  std::string header;                    // "# HELP ...\n# TYPE ...\n"
  std::vector<Series> series;            // registration order; the metrics themselves are heap-stable
};

}  // namespace throng::admin
