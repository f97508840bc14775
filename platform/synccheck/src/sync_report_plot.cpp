#include <algorithm>
#include <array>
#include <cstdint>
#include <limits>

#include "vifusion/core/time.hpp"
#include "vifusion/synccheck/line_plot.hpp"
#include "vifusion/synccheck/sync_report.hpp"

namespace vifusion::synccheck {
namespace {

constexpr double kNsPerMs = static_cast<double>(kNsPerMillisecond);

struct Rgb {
  unsigned char r, g, b;
};
// One colour per stream, in SyncReport::streams' order (distinguishable for colour-blind readers too:
// blue, orange, green, purple).
constexpr std::array<Rgb, 4> kStreamColours{{{40, 90, 200}, {230, 130, 20}, {40, 160, 60}, {130, 50, 160}}};

}  // namespace

void SyncReport::savePlot(const std::filesystem::path& path) const {
  // One time origin for every stream: the earliest sample of any.
  std::int64_t origin_ns = std::numeric_limits<std::int64_t>::max();
  for (const StreamStats& s : streams) {
    for (std::int64_t t : s.t_ns) origin_ns = std::min(origin_ns, t);
  }
  LinePlot plot("Timestamp offsets (a - b) over time", "time [s]", "offset [ms]");
  for (std::size_t k = 0; k < streams.size(); ++k) {
    const StreamStats& s = streams[k];
    const Rgb colour = kStreamColours[k % kStreamColours.size()];
    PlotSeries series{s.name, {}, {}, colour.r, colour.g, colour.b};
    series.x.reserve(s.count);
    series.y.reserve(s.count);
    for (std::size_t i = 0; i < s.t_ns.size() && i < s.offset_ns.size(); ++i) {
      series.x.push_back(nsToSeconds(s.t_ns[i] - origin_ns));
      series.y.push_back(s.offset_ns[i] / kNsPerMs);
    }
    plot.add(std::move(series));
  }
  plot.save(path);
}

}  // namespace vifusion::synccheck
