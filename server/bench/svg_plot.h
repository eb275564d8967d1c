#pragma once
// A tiny hand-written SVG chart writer: side-by-side panels of scatter/line series with linear or
// log axes, ticks, labels, legend and title. Enough for the sweep plot without a plotting
// dependency (and the output diffs as text).
#include <string>
#include <vector>

namespace throng::bench {

struct PlotPoint {
  double x = 0.0;
  double y = 0.0;
  std::string label;  // drawn next to the point ("K=4"); empty = none
};

enum class Marker { circle, square, diamond };

struct Series {
  std::string name;
  std::string colour;  // any SVG colour
  Marker marker = Marker::circle;
  bool line = true;    // connect the points in the given order
  std::vector<PlotPoint> points;
};

struct Panel {
  std::string title;
  std::string x_label;
  std::string y_label;
  bool log_x = false;
  bool log_y = false;
  bool x_from_zero = false;  // linear axes: include 0
  bool y_from_zero = false;
  std::string note;          // small text under the plot area (e.g. how zeros are drawn)
  std::vector<Series> series;
};

// Log axes cannot show values <= 0: such points are drawn at the axis floor (one decade under the
// smallest positive value) and the panel's note should say so.
std::string render_svg(const std::string& title, const std::vector<Panel>& panels);

}  // namespace throng::bench
