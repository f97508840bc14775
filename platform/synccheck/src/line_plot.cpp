#include "vifusion/synccheck/line_plot.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>
#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include "vifusion/core/error.hpp"

namespace vifusion::synccheck {
namespace {

/// Tick spacing of 1, 2 or 5 × 10^k giving about `target` intervals over `range`.
double niceStep(double range, int target) {
  const double raw = range / target;
  const double magnitude = std::pow(10.0, std::floor(std::log10(raw)));
  for (double factor : {1.0, 2.0, 5.0, 10.0}) {
    if (raw <= factor * magnitude) return factor * magnitude;
  }
  return 10.0 * magnitude;
}

std::string tickLabel(double value, double step) {
  char text[32];
  const int decimals = std::max(0, static_cast<int>(-std::floor(std::log10(step))));
  std::snprintf(text, sizeof(text), "%.*f", decimals, std::abs(value) < 1e-12 ? 0.0 : value);
  return text;
}

}  // namespace

void LinePlot::save(const std::filesystem::path& path, int width, int height) const {
  double x_min = std::numeric_limits<double>::infinity(), x_max = -x_min, y_min = x_min, y_max = -x_min;
  for (const PlotSeries& s : series_) {
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (!std::isfinite(s.x[i]) || !std::isfinite(s.y[i])) continue;
      x_min = std::min(x_min, s.x[i]);
      x_max = std::max(x_max, s.x[i]);
      y_min = std::min(y_min, s.y[i]);
      y_max = std::max(y_max, s.y[i]);
    }
  }
  if (!std::isfinite(x_min)) x_min = 0.0, x_max = 1.0, y_min = 0.0, y_max = 1.0;
  if (x_max - x_min < 1e-12) x_max = x_min + 1.0;
  if (y_max - y_min < 1e-12) y_max = y_min + 1.0;

  const int left = 90, right = 30, top = 50, bottom = 70;
  const double plot_w = width - left - right;
  const double plot_h = height - top - bottom;
  if (equal_aspect_) {  // widen the tighter axis so one metre is as long on both
    const double scale = std::max((x_max - x_min) / plot_w, (y_max - y_min) / plot_h);
    const double x_mid = 0.5 * (x_min + x_max), y_mid = 0.5 * (y_min + y_max);
    x_min = x_mid - 0.5 * scale * plot_w, x_max = x_mid + 0.5 * scale * plot_w;
    y_min = y_mid - 0.5 * scale * plot_h, y_max = y_mid + 0.5 * scale * plot_h;
  }
  const auto to_pixel = [&](double x, double y) {
    return cv::Point2d(left + (x - x_min) / (x_max - x_min) * plot_w, top + (y_max - y) / (y_max - y_min) * plot_h);
  };

  cv::Mat image(height, width, CV_8UC3, cv::Scalar(255, 255, 255));
  const cv::Scalar grid(225, 225, 225), ink(40, 40, 40);
  const int font = cv::FONT_HERSHEY_SIMPLEX;
  const double x_step = niceStep(x_max - x_min, 8), y_step = niceStep(y_max - y_min, 6);
  for (double x = std::ceil(x_min / x_step) * x_step; x <= x_max + 1e-9 * x_step; x += x_step) {
    cv::line(image, to_pixel(x, y_min), to_pixel(x, y_max), grid, 1);
    cv::putText(image, tickLabel(x, x_step), to_pixel(x, y_min) + cv::Point2d(-15, 22), font, 0.45, ink, 1,
                cv::LINE_AA);
  }
  for (double y = std::ceil(y_min / y_step) * y_step; y <= y_max + 1e-9 * y_step; y += y_step) {
    cv::line(image, to_pixel(x_min, y), to_pixel(x_max, y), grid, 1);
    cv::putText(image, tickLabel(y, y_step), to_pixel(x_min, y) + cv::Point2d(-80, 5), font, 0.45, ink, 1, cv::LINE_AA);
  }
  cv::rectangle(image, to_pixel(x_min, y_max), to_pixel(x_max, y_min), ink, 1);
  cv::putText(image, title_, cv::Point(left, 22), font, 0.7, ink, 2, cv::LINE_AA);
  cv::putText(image, x_label_, cv::Point(left + static_cast<int>(plot_w / 2) - 60, height - 20), font, 0.55, ink, 1,
              cv::LINE_AA);
  cv::putText(image, y_label_, cv::Point(8, top - 6), font, 0.55, ink, 1, cv::LINE_AA);

  int legend_y = top + 22;
  for (const PlotSeries& s : series_) {
    const cv::Scalar colour(s.b, s.g, s.r);
    std::vector<cv::Point> points;
    for (std::size_t i = 0; i < s.x.size() && i < s.y.size(); ++i) {
      if (std::isfinite(s.x[i]) && std::isfinite(s.y[i])) points.push_back(to_pixel(s.x[i], s.y[i]));
    }
    if (points.size() == 1) cv::circle(image, points[0], 3, colour, cv::FILLED);
    cv::polylines(image, points, false, colour, 2, cv::LINE_AA);
    cv::line(image, cv::Point(width - right - 200, legend_y - 5), cv::Point(width - right - 170, legend_y - 5), colour,
             3);
    cv::putText(image, s.name, cv::Point(width - right - 162, legend_y), font, 0.5, ink, 1, cv::LINE_AA);
    legend_y += 22;
  }
  if (!cv::imwrite(path.string(), image)) throw Error(path.string() + ": cannot write the plot");
}

}  // namespace vifusion::synccheck
