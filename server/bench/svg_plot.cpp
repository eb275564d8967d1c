#include "svg_plot.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/core.h>

namespace throng::bench {
namespace {

constexpr double kPanelW = 560, kPanelH = 460, kTitleH = 40;
constexpr double kLeft = 80, kRight = 24, kTop = 64, kBottom = 78;

std::string esc(const std::string& s) {
  std::string o;
  for (char c : s) {
    if (c == '&') o += "&amp;";
    else if (c == '<') o += "&lt;";
    else if (c == '>') o += "&gt;";
    else o += c;
  }
  return o;
}

std::string num(double v) {
  if (v == 0.0) return "0";
  return fmt::format("{:g}", v);
}

// One axis: data range -> pixel range, with its ticks.
struct Axis {
  bool log = false;
  double lo = 0.0, hi = 1.0;
  std::vector<double> major, minor;

  double f(double v) const { return log ? std::log10(v) : v; }
  double frac(double v) const {
    const double c = std::clamp(v, lo, hi);
    return (f(c) - f(lo)) / (f(hi) - f(lo));
  }
};

Axis make_axis(std::vector<double> values, bool log, bool from_zero) {
  Axis a;
  a.log = log;
  if (log) {
    double mn = std::numeric_limits<double>::infinity(), mx = 0.0;
    for (double v : values)
      if (v > 0.0 && std::isfinite(v)) mn = std::min(mn, v), mx = std::max(mx, v);
    if (!std::isfinite(mn)) mn = 1.0, mx = 10.0;
    const bool has_nonpositive = std::any_of(values.begin(), values.end(), [](double v) { return !(v > 0.0); });
    if (has_nonpositive) mn /= 10.0;  // room for the floor
    // A little room around the data; whole decades only when the data spans several anyway.
    a.lo = mn / 1.5;
    a.hi = mx * 1.5;
    const bool few_decades = std::log10(a.hi / a.lo) < 2.5;
    for (double d = std::pow(10.0, std::floor(std::log10(a.lo))); d <= a.hi; d *= 10.0) {
      for (int k = 1; k <= 9; ++k) {
        const double t = d * k;
        if (t < a.lo || t > a.hi) continue;
        const bool labelled = k == 1 || (few_decades && (k == 2 || k == 5));
        (labelled ? a.major : a.minor).push_back(t);
      }
    }
    return a;
  }
  double mn = std::numeric_limits<double>::infinity(), mx = -mn;
  for (double v : values)
    if (std::isfinite(v)) mn = std::min(mn, v), mx = std::max(mx, v);
  if (!std::isfinite(mn)) mn = 0.0, mx = 1.0;
  if (from_zero) mn = std::min(mn, 0.0), mx = std::max(mx, 0.0);
  if (mx <= mn) mx = mn + 1.0;
  // 5% room so markers and their labels at the extremes stay inside the frame.
  const double pad = 0.05 * (mx - mn);
  if (!(from_zero && mn == 0.0)) mn -= pad;
  mx += pad;
  const double raw = (mx - mn) / 5.0;
  const double mag = std::pow(10.0, std::floor(std::log10(raw)));
  const double n = raw / mag;
  const double step = (n < 1.5 ? 1.0 : n < 3.0 ? 2.0 : n < 7.0 ? 5.0 : 10.0) * mag;
  a.lo = std::floor(mn / step) * step;
  a.hi = std::ceil(mx / step) * step;
  for (double t = a.lo; t <= a.hi + step * 1e-6; t += step) a.major.push_back(std::abs(t) < step * 1e-9 ? 0.0 : t);
  return a;
}

std::string marker_svg(Marker m, double x, double y, const std::string& colour) {
  switch (m) {
    case Marker::square:
      return fmt::format(R"(<rect x="{:.1f}" y="{:.1f}" width="8" height="8" fill="{}"/>)", x - 4, y - 4, colour);
    case Marker::diamond:
      return fmt::format(R"(<path d="M {:.1f} {:.1f} l 5 5 l -5 5 l -5 -5 z" fill="{}"/>)", x, y - 5, colour);
    case Marker::circle:
      break;
  }
  return fmt::format(R"(<circle cx="{:.1f}" cy="{:.1f}" r="4" fill="{}"/>)", x, y, colour);
}

std::string render_panel(const Panel& p, double ox, double oy) {
  std::vector<double> xs, ys;
  for (const auto& s : p.series)
    for (const auto& pt : s.points) xs.push_back(pt.x), ys.push_back(pt.y);
  const Axis ax = make_axis(xs, p.log_x, p.x_from_zero);
  const Axis ay = make_axis(ys, p.log_y, p.y_from_zero);
  const double xl = ox + kLeft, xr = ox + kPanelW - kRight, yb = oy + kPanelH - kBottom, yt = oy + kTop;
  auto px = [&](double v) { return xl + ax.frac(v > 0.0 || !ax.log ? v : ax.lo) * (xr - xl); };
  auto py = [&](double v) { return yb - ay.frac(v > 0.0 || !ay.log ? v : ay.lo) * (yb - yt); };

  std::string o;
  o += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="15" font-weight="bold" text-anchor="middle">{}</text>)" "\n",
                   (xl + xr) / 2, oy + 24, esc(p.title));
  o += fmt::format(R"(<rect x="{:.1f}" y="{:.1f}" width="{:.1f}" height="{:.1f}" fill="white" stroke="#333"/>)" "\n",
                   xl, yt, xr - xl, yb - yt);
  for (double t : ax.minor)
    o += fmt::format(R"(<line x1="{0:.1f}" y1="{1:.1f}" x2="{0:.1f}" y2="{2:.1f}" stroke="#f0f0f0"/>)" "\n", px(t), yb, yt);
  for (double t : ay.minor)
    o += fmt::format(R"(<line x1="{1:.1f}" y1="{0:.1f}" x2="{2:.1f}" y2="{0:.1f}" stroke="#f0f0f0"/>)" "\n", py(t), xl, xr);
  for (double t : ax.major) {
    o += fmt::format(R"(<line x1="{0:.1f}" y1="{1:.1f}" x2="{0:.1f}" y2="{2:.1f}" stroke="#ddd"/>)" "\n", px(t), yb, yt);
    o += fmt::format(R"(<line x1="{0:.1f}" y1="{1:.1f}" x2="{0:.1f}" y2="{2:.1f}" stroke="#333"/>)" "\n", px(t), yb, yb + 5);
    o += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="11" text-anchor="middle">{}</text>)" "\n", px(t), yb + 18, num(t));
  }
  for (double t : ay.major) {
    o += fmt::format(R"(<line x1="{1:.1f}" y1="{0:.1f}" x2="{2:.1f}" y2="{0:.1f}" stroke="#ddd"/>)" "\n", py(t), xl, xr);
    o += fmt::format(R"(<line x1="{1:.1f}" y1="{0:.1f}" x2="{2:.1f}" y2="{0:.1f}" stroke="#333"/>)" "\n", py(t), xl - 5, xl);
    o += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="11" text-anchor="end">{}</text>)" "\n", xl - 8, py(t) + 4, num(t));
  }
  o += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="13" text-anchor="middle">{}</text>)" "\n", (xl + xr) / 2,
                   yb + 40, esc(p.x_label));
  o += fmt::format(R"svg(<text x="{0:.1f}" y="{1:.1f}" font-size="13" text-anchor="middle" transform="rotate(-90 {0:.1f} {1:.1f})">{2}</text>)svg" "\n",
                   ox + 22, (yb + yt) / 2, esc(p.y_label));
  if (!p.note.empty())
    o += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="10" fill="#555">{}</text>)" "\n", xl, yb + 62, esc(p.note));

  for (const auto& s : p.series) {
    if (s.line && s.points.size() > 1) {
      std::string d;
      for (const auto& pt : s.points) d += fmt::format("{}{:.1f},{:.1f}", d.empty() ? "" : " ", px(pt.x), py(pt.y));
      o += fmt::format(R"(<polyline points="{}" fill="none" stroke="{}" stroke-width="1.5"/>)" "\n", d, s.colour);
    }
    for (const auto& pt : s.points) {
      o += marker_svg(s.marker, px(pt.x), py(pt.y), s.colour) + "\n";
      if (!pt.label.empty())
        o += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="10" fill="{}">{}</text>)" "\n", px(pt.x) + 6,
                         py(pt.y) - 6, s.colour, esc(pt.label));
    }
  }
  // Legend: one row between the panel title and the plot, right-aligned, so it never hides data.
  double width = 0.0;
  for (const auto& s : p.series) width += 28.0 + 6.5 * double(s.name.size());
  double lx = xr - width;
  const double ly = yt - 8;
  for (const auto& s : p.series) {
    o += marker_svg(s.marker, lx + 6, ly - 4, s.colour);
    o += fmt::format(R"(<text x="{:.1f}" y="{:.1f}" font-size="11">{}</text>)" "\n", lx + 16, ly, esc(s.name));
    lx += 28.0 + 6.5 * double(s.name.size());
  }
  return o;
}

}  // namespace

std::string render_svg(const std::string& title, const std::vector<Panel>& panels) {
  const double width = kPanelW * double(std::max<std::size_t>(panels.size(), 1));
  const double height = kPanelH + kTitleH;
  std::string o = fmt::format(
      R"(<svg xmlns="http://www.w3.org/2000/svg" width="{0:.0f}" height="{1:.0f}" viewBox="0 0 {0:.0f} {1:.0f}" font-family="sans-serif">)" "\n",
      width, height);
  o += fmt::format(R"(<rect width="{:.0f}" height="{:.0f}" fill="#fafafa"/>)" "\n", width, height);
  o += fmt::format(R"(<text x="{:.1f}" y="26" font-size="18" font-weight="bold" text-anchor="middle">{}</text>)" "\n",
                   width / 2, esc(title));
  for (std::size_t i = 0; i < panels.size(); ++i) o += render_panel(panels[i], kPanelW * double(i), kTitleH);
  o += "</svg>\n";
  return o;
}

}  // namespace throng::bench
