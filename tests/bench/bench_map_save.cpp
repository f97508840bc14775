// Saving the map while mapping (issue 20: "Save during a run does not stall the SLAM thread longer than one frame
// period beyond the readback"). In one process, as vifusiond with map_file and map_save_period_s:
//   - slam::Slam (default SlamOptions, rgbd mode) maps the first --frames frames of sim:living_room_0 at --sizes,
//     played forwards and backwards (bench_sequence.hpp pingPongFrame) for --passes frames in all, as fast as it
//     goes (lavapipe's workers load both cores);
//   - the same frames three times: without saving (the baseline), saving every --save_every frames through
//     daemon::MapSaver, vifusiond's own saver: the SLAM thread captures the map (slam::captureMap, the readback)
//     and the saver's thread encodes, writes, syncs and renames the file under --out_dir while the frames go on.
//     A save still being written when the next is due waits for a later frame, as in vifusiond; and without
//     saving again.
// The runs process the same frames in the same order, so frame j's time in one is comparable with its time in
// the other: the difference on the frames that ran while a write was in progress is the write's cost to the SLAM
// thread (CPU and I/O contention; the thread itself never waits for the writer). A second run without saving
// gives the same difference's noise floor on the same frames (lavapipe's frame times vary from run to run).
//
//   bench_map_save [--passes=300] [--save_every=30] [--out_dir=DIR] [--frames=90] [--sizes=320x240]
//                  [--data_dir=DIR] [--vifusion=PATH] --benchmark_out=save.json --benchmark_out_format=json
//
// Counters (one iteration = the three runs):
//   frame_period_ms              the camera's frame period [ms] (the bound on the stall)
//   baseline_frame_ms_p50/_max   Slam::process per frame without saving [ms]
//   capture_ms_mean/_max         the SLAM thread's hold per save: the readback and the keyframe copy [ms], over
//                                the saves after the first
//   capture_ms_first             the first save's hold: on lavapipe it includes compiling the export kernel, which
//                                llvmpipe does at its first dispatch (a GPU driver does it when the pipeline is made)
//   write_ms_mean/_max           the saver thread's write per save [ms]
//   writing_frames               frames processed while a write was in progress
//   write_interference_ms_max    worst (frame time while writing − the same frame's baseline time) [ms]
//   write_interference_ms_mean   its mean over writing_frames [ms]
//   noise_ms_max, noise_ms_mean  the same differences between the two runs without saving, on the same frames [ms]
//   streaming_save_ms            slam::saveMap of the final map on the SLAM thread (the blocking way) [ms]
//   saves, surfels, file_mb      saves written, the last file's surfels and size [MB, 10⁶ bytes]

#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "bench_options.hpp"
#include "bench_sequence.hpp"
#include "single_entry_main.hpp"
#include "timing.hpp"
#include "vifusion/core/error.hpp"
#include "vifusion/daemon/map_saver.hpp"
#include "vifusion/daemon/shared_state.hpp"
#include "vifusion/slam/map_saving.hpp"
#include "vifusion/slam/slam.hpp"

namespace vifusion::bench {
namespace {

constexpr double kBytesPerMb = 1e6;

struct SaveFlags {
  int passes = 300;     ///< frames processed per run
  int save_every = 30;  ///< frames between saves (1 s at 30 Hz)
  std::string out_dir = VIFUSION_BENCH_SAVE_DIR;
};

SaveFlags& flags() {
  static SaveFlags f;
  return f;
}

/// Takes --passes, --save_every and --out_dir out of argv; bench_options' and Google Benchmark's flags stay.
void parseSaveFlags(int& argc, char** argv) {
  constexpr int kMaxFrames = 1'000'000;
  SaveFlags& f = flags();
  int kept = 1;
  for (int i = 1; i < argc; ++i) {
    std::string value;
    if (takeFlag(argv[i], "--passes", value)) {
      f.passes = parseIntFlag("--passes", value, 2, kMaxFrames);
    } else if (takeFlag(argv[i], "--save_every", value)) {
      f.save_every = parseIntFlag("--save_every", value, 1, kMaxFrames);
    } else if (takeFlag(argv[i], "--out_dir", value)) {
      f.out_dir = value;
    } else {
      argv[kept++] = argv[i];
    }
  }
  argc = kept;
}

double percentile(std::vector<double> values, double p) {
  if (values.empty()) return 0.0;
  std::sort(values.begin(), values.end());
  const auto rank = static_cast<std::size_t>(p * static_cast<double>(values.size() - 1) + 0.5);
  return values[std::min(rank, values.size() - 1)];
}

double mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (double v : values) sum += v;
  return values.empty() ? 0.0 : sum / static_cast<double>(values.size());
}

double maximum(const std::vector<double>& values) {
  return values.empty() ? 0.0 : *std::max_element(values.begin(), values.end());
}

struct RunTimes {
  std::vector<double> frame_ms;    ///< Slam::process per frame [ms]
  std::vector<bool> writing;       ///< a write was in progress when the frame started
  std::vector<double> capture_ms;  ///< per save
  std::vector<double> write_ms;    ///< per save
  std::uint64_t file_bytes = 0;
  std::uint32_t surfels = 0;
  double streaming_save_ms = 0.0;
};

/// One run over the frames; with `path` non-empty, saving every --save_every frames through a MapSaver.
RunTimes run(const Sequence& sequence, const std::string& path) {
  const SaveFlags& f = flags();
  slam::SlamOptions slam_options;
  slam::Slam slam(context(), sequence.calibration, slam_options);
  daemon::SharedState state(1, daemon::FrameSlot{}, 1);
  std::unique_ptr<daemon::MapSaver> saver;
  if (!path.empty()) {
    saver =
        std::make_unique<daemon::MapSaver>(path, slam_options.map.capacity, static_cast<std::size_t>(f.passes), state);
  }
  std::vector<mapfile::StampedPose> trajectory;
  trajectory.reserve(static_cast<std::size_t>(f.passes));
  RunTimes times;
  std::uint64_t saves_seen = 0;
  for (int j = 0; j < f.passes; ++j) {
    RgbdFrame frame = sequence.frames[pingPongFrame(sequence.frames.size(), j)];
    frame.t_ns = static_cast<std::int64_t>(j) * static_cast<std::int64_t>(1e9 / kFrameRateHz);
    frame.index = j;
    const bool writing = saver && !saver->idle();
    const auto start = std::chrono::steady_clock::now();
    const slam::FrameResult result = slam.process(frame);
    times.frame_ms.push_back(msSince(start));
    times.writing.push_back(writing);
    trajectory.push_back({result.t_ns, result.T_W_C});
    if (saver && state.map_saves.load() > saves_seen) {
      saves_seen = state.map_saves.load();
      times.write_ms.push_back(state.map_write_ms.load());
    }
    if (saver && j > 0 && j % f.save_every == 0 && saver->idle()) {
      slam::captureMap(slam, {slam_options.mode, &sequence.calibration, trajectory, std::nullopt}, saver->snapshot());
      times.capture_ms.push_back(saver->snapshot().capture_ms);
      saver->write(0);
    }
  }
  if (saver) {
    if (!saver->waitIdle()) throw Error("a save failed (see above)");
    if (state.map_saves.load() > saves_seen) times.write_ms.push_back(state.map_write_ms.load());
    times.file_bytes = state.map_file_bytes.load();
    const slam::MapSaveReport streamed =
        slam::saveMap(slam, {slam_options.mode, &sequence.calibration, trajectory, std::nullopt}, path);
    times.streaming_save_ms = streamed.elapsed_ms;
    times.surfels = streamed.surfels;
  }
  return times;
}

void saveWhileMapping(benchmark::State& state, Size size) {
  const SaveFlags& f = flags();
  const Sequence& sequence = sequenceFor(size);
  std::filesystem::create_directories(f.out_dir);
  const std::string path = (std::filesystem::path(f.out_dir) / ("map_" + size.name() + ".vifmap")).string();
  for (auto _ : state) {
    const RunTimes baseline = run(sequence, "");
    const RunTimes saving = run(sequence, path);
    const RunTimes repeat = run(sequence, "");
    std::vector<double> interference, noise;
    for (std::size_t j = 1; j < saving.frame_ms.size(); ++j) {  // frame 0 starts the map in all
      if (!saving.writing[j]) continue;
      interference.push_back(saving.frame_ms[j] - baseline.frame_ms[j]);
      noise.push_back(repeat.frame_ms[j] - baseline.frame_ms[j]);
    }
    const std::vector<double> baseline_frames(baseline.frame_ms.begin() + 1, baseline.frame_ms.end());
    auto& c = state.counters;
    c["frame_period_ms"] = 1e3 / kFrameRateHz;
    c["baseline_frame_ms_p50"] = percentile(baseline_frames, 0.5);
    c["baseline_frame_ms_max"] = maximum(baseline_frames);
    const std::vector<double> later_captures(saving.capture_ms.begin() + (saving.capture_ms.empty() ? 0 : 1),
                                             saving.capture_ms.end());
    c["capture_ms_first"] = saving.capture_ms.empty() ? 0.0 : saving.capture_ms.front();
    c["capture_ms_mean"] = mean(later_captures);
    c["capture_ms_max"] = maximum(later_captures);
    c["write_ms_mean"] = mean(saving.write_ms);
    c["write_ms_max"] = maximum(saving.write_ms);
    c["writing_frames"] = static_cast<double>(interference.size());
    c["write_interference_ms_max"] = maximum(interference);
    c["write_interference_ms_mean"] = mean(interference);
    c["noise_ms_max"] = maximum(noise);
    c["noise_ms_mean"] = mean(noise);
    c["streaming_save_ms"] = saving.streaming_save_ms;
    c["saves"] = static_cast<double>(saving.write_ms.size());
    c["surfels"] = saving.surfels;
    c["file_mb"] = static_cast<double>(saving.file_bytes) / kBytesPerMb;
    state.SetLabel(size.name() + " on " + context().features().device_name);
  }
}

}  // namespace
}  // namespace vifusion::bench

int main(int argc, char** argv) {
  vifusion::bench::options().sizes = {{320, 240}};  // --sizes overrides
  vifusion::bench::SingleEntry entry;
  entry.program = "bench_map_save";
  entry.family = "map_save";
  entry.parse_own_flags = vifusion::bench::parseSaveFlags;
  entry.run = vifusion::bench::saveWhileMapping;
  return vifusion::bench::runSingleEntry(argc, argv, entry);
}
