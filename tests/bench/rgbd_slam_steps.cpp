#include "rgbd_slam_steps.hpp"

#include <Eigen/Cholesky>
#include <algorithm>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "bench_sequence.hpp"
#include "native_loops.hpp"
#include "step_pipeline.hpp"
#include "timing.hpp"
#include "vifusion/core/image.hpp"
#include "vifusion/map/prediction_cpu.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"

namespace vifusion::bench {
namespace {

/// DenseTracker::track's Gauss-Newton loop with each term's submission timed on its own
/// (ms_track_<term>_l<level>, summed over the frame's iterations; gn_iterations_l<level>).
/// Returns T_ref_cur.
SE3d trackTimed(StepPipeline& p, const SE3d& guess, StepTimes& t) {
  const slam::TrackerOptions& o = p.tracker_options;
  SE3d T_ref_cur = guess;
  for (int l = o.levels - 1; l >= 0; --l) {
    const std::string level = "_l" + std::to_string(l);
    const PinholeCamera& camera = p.tracker->camera(l);
    for (int i = 0; i < o.iterations[l]; ++i) {
      p.terms.icp->setPose(l, T_ref_cur, camera);
      t.time("ms_track_icp" + level, [&] { p.terms.icp_levels[l]->run(); });
      NormalEquations6 system = p.terms.icp->result(l);
      if (o.use_photometric) {
        p.terms.photometric->setPose(l, T_ref_cur, camera);
        t.time("ms_track_photometric" + level, [&] { p.terms.photometric_levels[l]->run(); });
        system += p.terms.photometric->result(l);
      }
      t.add("gn_iterations" + level, 1.0);
      const Eigen::LDLT<Eigen::Matrix<double, 6, 6>> ldlt(system.H);
      if (ldlt.info() != Eigen::Success || system.inliers < 6.0) return T_ref_cur;
      const Vector6d delta = ldlt.solve(-system.b);
      if (!delta.allFinite()) return T_ref_cur;
      T_ref_cur = SE3d::exp(delta) * T_ref_cur;
      if (stepWithinUncertainty(delta, system.H, o.converged_step_chi2)) break;
    }
  }
  return T_ref_cur;
}

/// One level-0 evaluation of each dense term at T_ref_cur on the GPU and as native loops on 1 and 2
/// threads over read-back copies of the same buffers (medians of 3), and the natives' inlier count
/// relative to the GPU's (1 = the same work).
void compareNative(StepPipeline& p, const SE3d& T_ref_cur, StepTimes& t) {
  const PinholeCamera& camera = p.tracker->camera(0);
  const int pixels = camera.width * camera.height;
  p.terms.level0_readback->run();
  using preprocess::GradientPixel;
  using preprocess::NormalPixel;
  using preprocess::VertexPixel;

  p.terms.icp->setPose(0, T_ref_cur, camera);
  t.add("gpu_icp_l0_ms", medianMs(3, [&] { p.terms.icp_levels[0]->run(); }));
  const NormalEquations6 gpu_icp = p.terms.icp->result(0);
  const tracking::IcpParams icp_params = tracking::IcpParams::make(T_ref_cur, camera, p.tracker_options.icp);
  const auto icp_loop = [&](int begin, int end, bench::NativeSums& sums) {
    bench::icpNative(p.host<VertexPixel>(p.terms.cur_vertices), p.host<NormalPixel>(p.terms.cur_normals),
                     p.host<VertexPixel>(p.terms.ref_vertices), p.host<NormalPixel>(p.terms.ref_normals), icp_params,
                     begin, end, sums);
  };
  bench::NativeSums native{};
  t.add("native_icp_l0_ms_1t", medianMs(3, [&] { native = bench::runSplit(pixels, 1, icp_loop); }));
  t.add("native_icp_l0_ms_2t", medianMs(3, [&] { native = bench::runSplit(pixels, 2, icp_loop); }));
  t.add("native_icp_l0_inliers_vs_gpu", gpu_icp.inliers > 0.0 ? native[28] / gpu_icp.inliers : 0.0);

  if (!p.tracker_options.use_photometric) return;
  p.terms.photometric->setPose(0, T_ref_cur, camera);
  t.add("gpu_photometric_l0_ms", medianMs(3, [&] { p.terms.photometric_levels[0]->run(); }));
  const NormalEquations6 gpu_photometric = p.terms.photometric->result(0);
  const tracking::PhotometricParams photometric_params =
      tracking::PhotometricParams::make(T_ref_cur, camera, p.tracker_options.photometric);
  const auto photometric_loop = [&](int begin, int end, bench::NativeSums& sums) {
    bench::photometricNative(p.host<VertexPixel>(p.terms.cur_vertices), p.host<float>(p.terms.cur_intensity),
                             p.host<float>(p.terms.ref_intensity), p.host<GradientPixel>(p.terms.ref_gradients),
                             p.host<VertexPixel>(p.terms.ref_vertices), photometric_params, begin, end, sums);
  };
  t.add("native_photometric_l0_ms_1t", medianMs(3, [&] { native = bench::runSplit(pixels, 1, photometric_loop); }));
  t.add("native_photometric_l0_ms_2t", medianMs(3, [&] { native = bench::runSplit(pixels, 2, photometric_loop); }));
  t.add("native_photometric_l0_inliers_vs_gpu",
        gpu_photometric.inliers > 0.0 ? native[28] / gpu_photometric.inliers : 0.0);
}

/// The model prediction (the third kernel by time) against a native loop: the CPU references
/// splatModelCpu + resolveModelCpu + subsampleModelCpu, plain float loops over the same surfels
/// (read back first, untimed) doing the same splat, resolve and subsampling on one thread.
/// gpu_prediction_ms re-runs the just-recorded prediction (idempotent); native_prediction_ids_vs_gpu
/// is the fraction of pixels whose winning surfel agrees (1 = the same work).
struct NativePrediction {
  std::vector<map::Surfel> surfels;
  std::vector<Image<std::uint32_t>> scratch;  ///< depth bits, ids
  std::vector<Image<Eigen::Vector4f>> vertices, normals;
  std::vector<Image<float>> intensity;
};

void comparePrediction(StepPipeline& p, int parity, const SE3d& T_C_W, std::uint32_t frame, NativePrediction& n,
                       StepTimes& t) {
  t.add("gpu_prediction_ms", medianMs(3, [&] { p.predict[parity]->run(); }));
  p.splat_ids_copy->run();
  p.exporter->read(n.surfels);
  const map::PredictionParams params = p.prediction->makeParams(T_C_W, frame);
  if (n.scratch.empty()) {
    for (int k = 0; k < 2; ++k) n.scratch.emplace_back(params.view.width, params.view.height, 0u);
    for (int l = 0; l < p.prediction->levels(); ++l) {
      const PinholeCamera& camera = p.prediction->camera(l);
      n.vertices.emplace_back(camera.width, camera.height, Eigen::Vector4f::Zero());
      n.normals.emplace_back(camera.width, camera.height, Eigen::Vector4f::Zero());
      n.intensity.emplace_back(camera.width, camera.height, 0.0f);
    }
  }
  t.add("native_prediction_ms_1t", medianMs(3, [&] {
          map::splatModelCpu(n.surfels, params, n.scratch[0].view(), n.scratch[1].view());
          map::resolveModelCpu(n.surfels, params, std::as_const(n.scratch[1]).view(), n.vertices[0].view(),
                               n.normals[0].view(), n.intensity[0].view());
          for (int l = 1; l < p.prediction->levels(); ++l) {
            map::subsampleModelCpu(std::as_const(n.vertices[0]).view(), std::as_const(n.normals[0]).view(),
                                   std::as_const(n.intensity[0]).view(), l, n.vertices[l].view(), n.normals[l].view(),
                                   n.intensity[l].view());
          }
        }));
  const std::span<const std::uint32_t> gpu_ids = p.arena->buffer(p.splat_ids_readback).hostSpan<const std::uint32_t>();
  const std::uint32_t* cpu_ids = n.scratch[1].data();
  std::size_t same = 0;
  for (std::size_t i = 0; i < gpu_ids.size(); ++i) same += gpu_ids[i] == cpu_ids[i] ? 1 : 0;
  t.add("native_prediction_ids_vs_gpu", double(same) / double(gpu_ids.size()));
  t.add("native_prediction_frames", 1.0);
}

}  // namespace

void rgbdSlamSteps(benchmark::State& state, Size size) {
  const Sequence& sequence = sequenceFor(size);
  slam::SlamOptions slam_options;
  slam_options.tracker.use_photometric = options().photometric;
  StepPipeline p(sequence.calibration, slam_options);
  const preprocess::PreprocessStage& stage = p.tracker->preprocessing();
  const SE3d T_C0_world = sequence.ground_truth.front().T_world_body.inverse();
  const auto T_W_C_at = [&](std::size_t i) { return T_C0_world * sequence.ground_truth[i].T_world_body; };
  StepTimes times;
  NativePrediction native_prediction;
  std::size_t next = 0;
  const auto frame = [&](bool timed) {
    const RgbdFrame& rgbd = sequence.frames[next];
    const SE3d T_W_C = T_W_C_at(next);
    const SE3d T_C_W = T_W_C.inverse();
    const auto frame_index = static_cast<std::uint32_t>(next);
    StepTimes warm_up;
    StepTimes& t = timed ? times : warm_up;
    t.time("ms_upload", [&] { stage.upload(rgbd.depth.view(), rgbd.rgb.view()); });
    for (std::size_t s = 0; s < p.preprocess_steps.size(); ++s) {
      t.time(std::string("ms_pre_") + preprocess::preprocessStepName(preprocess::kAllPreprocessSteps[s]),
             [&] { p.preprocess_steps[s]->run(); });
    }
    if (next > 0) {  // the reference view is the prediction at the previous frame's pose
      const SE3d guess = next > 1 ? T_W_C_at(next - 2).inverse() * T_W_C_at(next - 1) : SE3d();
      p.terms.refresh->run();
      const SE3d T_ref_cur = trackTimed(p, guess, t);
      if (timed) compareNative(p, T_ref_cur, t);
    }
    ++next;
    const int parity = p.map->current();
    p.fusion->setFrame(T_W_C, frame_index);
    p.maintenance->setView(T_C_W, frame_index);
    p.prediction->setView(T_C_W, frame_index);
    for (std::size_t s = 0; s < p.fusion_steps[parity].size(); ++s) {
      t.time(std::string("ms_fusion_") + map::fusionStepName(map::kAllFusionSteps[s]),
             [&] { p.fusion_steps[parity][s]->run(); });
    }
    t.time("ms_map_cleanup", [&] { p.cleanup[parity]->run(); });
    t.time("ms_map_compaction", [&] { p.compaction[parity]->run(); });
    p.map->flip();
    t.time("ms_map_prediction", [&] { p.predict[parity ^ 1]->run(); });
    // Every 10th frame (the map read-back is slow), and always in short runs.
    if (timed && (frame_index % 10 == 9 || options().frames < 20)) {
      comparePrediction(p, parity ^ 1, T_C_W, frame_index, native_prediction, t);
    }
    t.time("ms_reference_copy", [&] { p.reference_copy->run(); });
    t.time("ms_reference_gradients", [&] { p.reference_gradients->run(); });
  };
  frame(false);  // as in rgbd_slam: frame 0 is the warm-up
  for (auto _ : state) frame(true);
  const double timed = static_cast<double>(next - 1);
  for (const auto& [name, total] : times.totals()) state.counters[name] = total / timed;
  // Per-evaluation costs of the terms and their ratios to the native loops (same pose, same buffers).
  auto& c = state.counters;
  for (const char* term : {"icp", "photometric"}) {
    const std::string gpu = std::string("gpu_") + term + "_l0_ms";
    if (c.find(gpu) == c.end()) continue;
    for (const char* threads : {"1t", "2t"}) {
      const std::string native = std::string("native_") + term + "_l0_ms_" + threads;
      c[std::string("ratio_") + term + "_l0_" + threads] = double(c[gpu]) / double(c[native]);
    }
    // The same work in CPU time: robust to other load on a shared machine (wall time is not).
    c[std::string("ratio_cpu_") + term + "_l0"] =
        double(c["cpu_" + gpu]) / double(c[std::string("cpu_native_") + term + "_l0_ms_1t"]);
  }
  // The prediction comparison ran on some frames only: per comparison, not per frame (the loop
  // above divided by the frames; native_prediction_frames is now the share of frames compared).
  if (const double compared = c["native_prediction_frames"]; compared > 0.0) {
    for (const char* name : {"gpu_prediction_ms", "cpu_gpu_prediction_ms", "native_prediction_ms_1t",
                             "cpu_native_prediction_ms_1t", "native_prediction_ids_vs_gpu"}) {
      c[name] = double(c[name]) / compared;
    }
    c["ratio_prediction_1t"] = double(c["gpu_prediction_ms"]) / double(c["native_prediction_ms_1t"]);
    c["ratio_cpu_prediction"] = double(c["cpu_gpu_prediction_ms"]) / double(c["cpu_native_prediction_ms_1t"]);
  }
  c.erase("native_prediction_frames");
  c["surfels"] = p.map->readState(*p.arena).surfel_count;
  state.SetLabel(context().features().device_name);
}

}  // namespace vifusion::bench
