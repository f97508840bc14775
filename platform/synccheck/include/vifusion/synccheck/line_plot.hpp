#pragma once
// Minimal PNG line plots for evaluation and sync reports (OpenCV drawing, no GUI): axes with round tick
// values, several named series, optional equal aspect for top views of trajectories.

#include <filesystem>
#include <string>
#include <vector>

namespace vifusion::synccheck {

struct PlotSeries {
  std::string name;
  std::vector<double> x;
  std::vector<double> y;
  unsigned char r = 0, g = 0, b = 0;  ///< colour
};

class LinePlot {
 public:
  LinePlot(std::string title, std::string x_label, std::string y_label)
      : title_(std::move(title)), x_label_(std::move(x_label)), y_label_(std::move(y_label)) {}

  void add(PlotSeries series) { series_.push_back(std::move(series)); }
  /// Same scale on both axes (top views), so shapes are not distorted.
  void setEqualAspect(bool equal) { equal_aspect_ = equal; }
  /// Writes a width × height PNG; throws vifusion::Error if it cannot be written.
  void save(const std::filesystem::path& path, int width = 900, int height = 650) const;

 private:
  std::string title_, x_label_, y_label_;
  std::vector<PlotSeries> series_;
  bool equal_aspect_ = false;
};

}  // namespace vifusion::synccheck
