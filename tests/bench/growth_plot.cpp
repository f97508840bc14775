#include "growth_plot.hpp"

#include <algorithm>
#include <cstdio>
#include <fstream>

#include "vifusion/core/error.hpp"

namespace vifusion::bench {
namespace {

constexpr double kWidth = 720.0, kHeight = 440.0;
constexpr double kLeft = 70.0, kRight = 20.0, kTop = 40.0, kBottom = 50.0;
constexpr int kTicks = 5;
constexpr double kMillion = 1e6;

struct WindowPoint {
  double surfels_m = 0.0;  ///< mean surfel count [millions]
  double active_m = 0.0;   ///< mean active range [millions]
  double wall_ms = 0.0;
  double cpu_ms = 0.0;
};

std::string format(double value) {
  char text[32];
  std::snprintf(text, sizeof(text), "%.3g", value);
  return text;
}

}  // namespace

void writeGrowthSvg(const std::string& path, const std::vector<GrowthRow>& rows, int window, const std::string& title) {
  std::vector<WindowPoint> points;
  for (std::size_t start = 0; start + static_cast<std::size_t>(window) <= rows.size(); start += window) {
    WindowPoint p;
    for (std::size_t i = start; i < start + static_cast<std::size_t>(window); ++i) {
      p.surfels_m += rows[i].surfels / kMillion;
      p.active_m += rows[i].active_surfels / kMillion;
      p.wall_ms += rows[i].wall_ms;
      p.cpu_ms += rows[i].cpu_ms;
    }
    p.surfels_m /= window;
    p.active_m /= window;
    p.wall_ms /= window;
    p.cpu_ms /= window;
    points.push_back(p);
  }
  double max_x = 1e-3, max_y = 1e-3;
  for (const WindowPoint& p : points) {
    max_x = std::max({max_x, p.surfels_m});
    max_y = std::max({max_y, p.wall_ms, p.cpu_ms});
  }
  max_y *= 1.1;
  const double plot_w = kWidth - kLeft - kRight, plot_h = kHeight - kTop - kBottom;
  const auto x_of = [&](double v) { return kLeft + plot_w * v / max_x; };
  const auto y_of = [&](double v) { return kTop + plot_h * (1.0 - v / max_y); };

  std::ofstream out(path);
  if (!out) throw Error(path + ": cannot be written");
  out << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kWidth << "' height='" << kHeight
      << "' font-family='sans-serif' font-size='12'>\n<rect width='100%' height='100%' fill='white'/>\n";
  out << "<text x='" << kLeft << "' y='22' font-size='14'>" << title << ": ms/frame per " << window
      << "-frame window against the map's size</text>\n";
  out << "<line x1='" << kLeft << "' y1='" << y_of(0) << "' x2='" << x_of(max_x) << "' y2='" << y_of(0)
      << "' stroke='black'/>\n<line x1='" << kLeft << "' y1='" << y_of(0) << "' x2='" << kLeft << "' y2='" << kTop
      << "' stroke='black'/>\n";
  for (int t = 0; t <= kTicks; ++t) {
    const double xv = max_x * t / kTicks, yv = max_y * t / kTicks;
    out << "<text x='" << x_of(xv) << "' y='" << y_of(0) + 16 << "' text-anchor='middle'>" << format(xv)
        << "</text>\n<text x='" << kLeft - 6 << "' y='" << y_of(yv) + 4 << "' text-anchor='end'>" << format(yv)
        << "</text>\n";
  }
  out << "<text x='" << kLeft + plot_w / 2 << "' y='" << kHeight - 12
      << "' text-anchor='middle'>surfels in the map [millions]</text>\n<text x='16' y='" << kTop + plot_h / 2
      << "' transform='rotate(-90 16 " << kTop + plot_h / 2 << ")' text-anchor='middle'>ms per frame</text>\n";
  for (const WindowPoint& p : points) {
    out << "<circle cx='" << x_of(p.surfels_m) << "' cy='" << y_of(p.wall_ms) << "' r='3' fill='#1f77b4'/>"
        << "<circle cx='" << x_of(p.surfels_m) << "' cy='" << y_of(p.cpu_ms) << "' r='3' fill='#ff7f0e'/>\n";
  }
  out << "<text x='" << kWidth - kRight - 220 << "' y='" << kTop + 10
      << "' fill='#1f77b4'>● wall time</text>\n<text x='" << kWidth - kRight - 220 << "' y='" << kTop + 26
      << "' fill='#ff7f0e'>● process CPU time (2 cores)</text>\n</svg>\n";
  if (!out) throw Error(path + ": write failed");
}

}  // namespace vifusion::bench
