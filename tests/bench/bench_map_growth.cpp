// Issue 19's "cost independent of map size": slam::Slam (default SlamOptions, rgbd mode, loop closure and
// relocalisation on, as `vifusion run`) over --replayed frames of sim:living_room_0 played forwards and
// backwards (bench_sequence.hpp: pingPongFrame, restamped at 30 Hz), so the map keeps growing — surfaces seen
// again after more than the active window are mapped again or reactivated by loop closure — while the view
// stays the same kind of view. Per frame it records the map's size and active range, the host's stage times
// and the map update's GPU stages; it reports the mean ms/frame over windows of --window frames and the
// acceptance ratio: the last window (ending at --replayed) against the window ending at frame --reference.
//
// --whole_map=1 asks Slam to visit the whole map on every frame (MapBuffers::visitWholeMapNextFrame), as every
// per-frame pass did before the active range: the A/B comparison in one binary.
//
//   bench_map_growth [--replayed=10000] [--reference=1000] [--window=100] [--csv=FILE] [--svg=FILE] [--whole_map=0]
//                    [--frames=1510] [--sizes=320x240] [--data_dir=DIR] [--vifusion=PATH]
//                    --benchmark_out=growth.json --benchmark_out_format=json
//
// Counters (one iteration = the whole replay):
//   frames, lost_frames, surfels_at_reference, surfels_at_end, active_surfels_mean (mean of the active range)
//   lost_at_reference, lost_at_end   lost frames in the two windows (the means below skip them)
//   ms_at_reference, ms_at_end   mean wall ms/frame of Slam::process over the tracked frames of the two windows
//   cpu_ms_at_reference, cpu_ms_at_end   the same as process CPU time (lavapipe's workers included): on a
//                                shared machine the comparison to trust
//   ratio, cpu_ratio             end / reference; the goal is ≤ 1.15
//   mapping_ms_at_reference, mapping_ms_at_end, closure_ms_at_reference, closure_ms_at_end
//   gpu_<stage>_ms_at_reference, gpu_<stage>_ms_at_end   slam::MapStageTimes means (absent without timestamps)
// --csv writes one row per frame (frame, surfels, active, wall and CPU ms, stages); --svg plots ms/frame
// against the surfel count.

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "bench_options.hpp"
#include "bench_sequence.hpp"
#include "growth_plot.hpp"
#include "single_entry_main.hpp"
#include "timing.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion::bench {
namespace {

constexpr int kProgressFrames = 500;

struct GrowthFlags {
  int replayed = 10'000;   ///< frames processed
  int reference = 1'000;   ///< the early window ends here
  int window = 100;        ///< frames per averaging window
  std::string csv;         ///< per-frame rows, when set
  std::string svg;         ///< the plot, when set
  bool whole_map = false;  ///< visit the whole map every frame (the cost before the active range)
};

GrowthFlags& flags() {
  static GrowthFlags instance;
  return instance;
}

int parsePositive(const std::string& flag, const std::string& value) {
  char* end = nullptr;
  const long parsed = std::strtol(value.c_str(), &end, 10);
  if (*end != '\0' || parsed <= 0 || parsed > 10'000'000) {
    throw Error(flag + ": expected a positive frame count, got '" + value + "'");
  }
  return static_cast<int>(parsed);
}

/// Takes this program's own flags out of argv; bench_options' and Google Benchmark's stay.
void parseGrowthFlags(int& argc, char** argv) {
  GrowthFlags& f = flags();
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const auto eq = arg.find('=');
    const std::string name = arg.substr(0, eq);
    const std::string value = eq == std::string::npos ? "" : arg.substr(eq + 1);
    if (name == "--replayed") {
      f.replayed = parsePositive(name, value);
    } else if (name == "--reference") {
      f.reference = parsePositive(name, value);
    } else if (name == "--window") {
      f.window = parsePositive(name, value);
    } else if (name == "--csv") {
      f.csv = value;
    } else if (name == "--svg") {
      f.svg = value;
    } else if (name == "--whole_map") {
      if (value != "0" && value != "1") throw Error("--whole_map: expected 0 or 1, got '" + value + "'");
      f.whole_map = value == "1";
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
  if (f.window > f.reference || f.reference > f.replayed) {
    throw Error("need --window ≤ --reference ≤ --replayed, got " + std::to_string(f.window) + ", " +
                std::to_string(f.reference) + ", " + std::to_string(f.replayed));
  }
}

/// The mean over frames [end − window, end) of `value(row)`, over the tracked rows where it is measured (≥ 0): a
/// lost frame is neither fused nor compacted, so it would make a window look cheaper than the map makes it.
template <typename Fn>
double windowMean(const std::vector<GrowthRow>& rows, int end, int window, Fn&& value) {
  double sum = 0.0;
  int count = 0;
  for (int i = std::max(0, end - window); i < end; ++i) {
    const GrowthRow& row = rows[static_cast<std::size_t>(i)];
    const double v = value(row);
    if (row.lost || v < 0.0) continue;
    sum += v;
    ++count;
  }
  return count > 0 ? sum / count : -1.0;
}

void writeCsv(const std::string& path, const std::vector<GrowthRow>& rows) {
  std::ofstream out(path);
  if (!out) throw Error(path + ": cannot be written");
  out << "frame,surfels,active_surfels,lost,wall_ms,cpu_ms,preprocess_ms,tracking_ms,mapping_ms,closure_ms,"
         "fusion_gpu_ms,maintenance_gpu_ms,prediction_gpu_ms,reference_gpu_ms\n";
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const GrowthRow& r = rows[i];
    out << i << ',' << r.surfels << ',' << r.active_surfels << ',' << (r.lost ? 1 : 0) << ',' << r.wall_ms << ','
        << r.cpu_ms << ',' << r.preprocess_ms << ',' << r.tracking_ms << ',' << r.mapping_ms << ',' << r.closure_ms
        << ',' << r.stages.fusion_ms << ',' << r.stages.maintenance_ms << ',' << r.stages.prediction_ms << ','
        << r.stages.reference_ms << '\n';
  }
  if (!out) throw Error(path + ": write failed");
}

void mapGrowth(benchmark::State& state, Size size) {
  const GrowthFlags& f = flags();
  const Sequence& sequence = sequenceFor(size);
  if (sequence.frames.size() < 2) throw Error("map growth: the sequence needs at least 2 frames");
  std::vector<GrowthRow> rows(static_cast<std::size_t>(f.replayed));
  const std::int64_t period_ns = secondsToNs(1.0 / kFrameRateHz);
  for (auto _ : state) {
    slam::Slam pipeline(context(), sequence.calibration, slam::SlamOptions{});
    RgbdFrame frame;
    for (int j = 0; j < f.replayed; ++j) {
      frame = sequence.frames[pingPongFrame(sequence.frames.size(), j)];
      frame.t_ns = j * period_ns;
      frame.index = j;
      if (f.whole_map) pipeline.map().visitWholeMapNextFrame(pipeline.arena());
      const double cpu_start = processCpuMs();
      const auto start = std::chrono::steady_clock::now();
      const slam::FrameResult result = pipeline.process(frame);
      GrowthRow& row = rows[static_cast<std::size_t>(j)];
      row.wall_ms = msSince(start);
      row.cpu_ms = processCpuMs() - cpu_start;
      row.surfels = result.surfels;
      row.active_surfels = result.active_surfels;
      row.lost = result.lost();
      row.preprocess_ms = result.preprocess_ms;
      row.tracking_ms = result.tracking_ms;
      row.mapping_ms = result.mapping_ms;
      row.closure_ms = result.closure.ms;
      row.stages = result.map_stages;
      if ((j + 1) % kProgressFrames == 0) {  // a full replay takes hours: say where it is (stderr)
        std::fprintf(stderr, "bench_map_growth: frame %d: %u surfels, %u active, %.1f ms\n", j + 1, row.surfels,
                     row.active_surfels, row.wall_ms);
      }
    }
  }
  const int end = f.replayed;
  const int reference = f.reference;
  const int w = f.window;
  const auto counter = [&](const char* name, auto&& value) {
    const double early = windowMean(rows, reference, w, value);
    const double late = windowMean(rows, end, w, value);
    if (early < 0.0 || late < 0.0) return;
    state.counters[std::string(name) + "_at_reference"] = early;
    state.counters[std::string(name) + "_at_end"] = late;
  };
  counter("ms", [](const GrowthRow& r) { return r.wall_ms; });
  counter("cpu_ms", [](const GrowthRow& r) { return r.cpu_ms; });
  counter("mapping_ms", [](const GrowthRow& r) { return r.mapping_ms; });
  counter("closure_ms", [](const GrowthRow& r) { return r.closure_ms; });
  counter("gpu_fusion_ms", [](const GrowthRow& r) { return r.stages.fusion_ms; });
  counter("gpu_maintenance_ms", [](const GrowthRow& r) { return r.stages.maintenance_ms; });
  counter("gpu_prediction_ms", [](const GrowthRow& r) { return r.stages.prediction_ms; });
  counter("gpu_reference_ms", [](const GrowthRow& r) { return r.stages.reference_ms; });
  state.counters["ratio"] = state.counters["ms_at_end"] / state.counters["ms_at_reference"];
  state.counters["cpu_ratio"] = state.counters["cpu_ms_at_end"] / state.counters["cpu_ms_at_reference"];
  double lost = 0.0, active = 0.0;
  for (const GrowthRow& r : rows) {
    lost += r.lost ? 1.0 : 0.0;
    active += r.active_surfels;
  }
  state.counters["frames"] = f.replayed;
  state.counters["lost_frames"] = lost;
  state.counters["surfels_at_reference"] = rows[static_cast<std::size_t>(reference - 1)].surfels;
  state.counters["surfels_at_end"] = rows.back().surfels;
  state.counters["active_surfels_mean"] = active / f.replayed;
  state.counters["whole_map"] = f.whole_map ? 1.0 : 0.0;
  const auto lost_in = [&](int window_end) {
    double n = 0.0;
    for (int i = std::max(0, window_end - w); i < window_end; ++i)
      n += rows[static_cast<std::size_t>(i)].lost ? 1.0 : 0.0;
    return n;
  };
  state.counters["lost_at_reference"] = lost_in(reference);
  state.counters["lost_at_end"] = lost_in(end);
  if (!f.csv.empty()) writeCsv(f.csv, rows);
  if (!f.svg.empty()) writeGrowthSvg(f.svg, rows, f.window, "sim:" + std::string(kPreset) + " " + size.name());
}

}  // namespace
}  // namespace vifusion::bench

int main(int argc, char** argv) {
  vifusion::bench::options().sizes = {{320, 240}};
  vifusion::bench::options().frames = 1510;  // the whole of living_room_0
  vifusion::bench::SingleEntry entry;
  entry.program = "bench_map_growth";
  entry.family = "map_growth";
  entry.parse_own_flags = vifusion::bench::parseGrowthFlags;
  entry.run = vifusion::bench::mapGrowth;
  entry.unit = benchmark::kMillisecond;
  entry.real_time = false;
  entry.sequence_note = ", played forwards and backwards";
  return vifusion::bench::runSingleEntry(argc, argv, entry);
}
