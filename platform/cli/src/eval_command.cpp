#include "eval_command.hpp"

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <optional>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/datasets/ground_truth_states.hpp"
#include "vifusion/eval/alignment.hpp"
#include "vifusion/eval/camera_tilt.hpp"
#include "vifusion/eval/metrics.hpp"
#include "vifusion/eval/ply_points.hpp"
#include "vifusion/eval/reconstruction_error.hpp"
#include "vifusion/eval/state_csv.hpp"
#include "vifusion/eval/state_errors.hpp"
#include "vifusion/eval/trajectory_io.hpp"
#include "vifusion/scene/living_room.hpp"
#include "vifusion/synccheck/line_plot.hpp"

namespace vifusion::cli {
namespace {

using nlohmann::json;
using synccheck::LinePlot;
using synccheck::PlotSeries;

/// The two world axes that span the horizontal plane, for a top view.
std::pair<int, int> horizontalAxes(const std::string& up) { return up == "z" ? std::pair{0, 1} : std::pair{0, 2}; }

void plotTrajectories(const std::filesystem::path& dir, const std::vector<eval::StampedPose>& gt,
                      const std::vector<eval::StampedPose>& est, const eval::AteResult& ate, const std::string& up) {
  const auto [a, b] = horizontalAxes(up);
  PlotSeries gt_series{"ground truth", {}, {}, 30, 30, 30};
  for (const eval::StampedPose& pose : gt) {
    gt_series.x.push_back(pose.T_world_body.translation()[a]);
    gt_series.y.push_back(pose.T_world_body.translation()[b]);
  }
  PlotSeries est_series{"estimate (aligned)", {}, {}, 220, 60, 40};
  for (const eval::StampedPose& pose : est) {
    const Eigen::Vector3d p = ate.T_gt_est * pose.T_world_body.translation();
    est_series.x.push_back(p[a]);
    est_series.y.push_back(p[b]);
  }
  const std::string axis_a(1, static_cast<char>('x' + a)), axis_b(1, static_cast<char>('x' + b));
  LinePlot top("Top view, ATE RMSE " + std::to_string(ate.rmse_m * 1e3).substr(0, 6) + " mm", axis_a + " [m]",
               axis_b + " [m]");
  top.setEqualAspect(true);
  top.add(std::move(gt_series));
  top.add(std::move(est_series));
  top.save(dir / "trajectory_top.png");

  // Position error against the distance travelled along the ground truth.
  PlotSeries error{"position error", {}, {}, 40, 90, 200};
  double travelled_m = 0.0;
  std::size_t previous = ate.gt_index.empty() ? 0 : ate.gt_index.front();
  for (std::size_t i = 0; i < ate.errors_m.size(); ++i) {
    for (std::size_t k = previous + 1; k <= ate.gt_index[i]; ++k) {
      travelled_m += (gt[k].T_world_body.translation() - gt[k - 1].T_world_body.translation()).norm();
    }
    previous = ate.gt_index[i];
    error.x.push_back(travelled_m);
    error.y.push_back(ate.errors_m[i] * 1e3);
  }
  LinePlot errors("Position error after alignment", "distance travelled [m]", "error [mm]");
  errors.add(std::move(error));
  errors.save(dir / "position_error.png");
}

void plotStateErrors(const std::filesystem::path& dir, const eval::StateErrors& errors) {
  PlotSeries velocity{"velocity [cm/s]", {}, {}, 40, 90, 200};
  PlotSeries gyro{"gyro bias [mrad/s]", {}, {}, 220, 60, 40};
  PlotSeries accel{"accel bias [cm/s^2]", {}, {}, 40, 160, 60};
  PlotSeries gravity{"gravity direction [deg]", {}, {}, 120, 40, 160};
  const int64_t t0_ns = errors.series.front().t_ns;
  for (const eval::StateErrorSample& s : errors.series) {
    const double t_s = nsToSeconds(s.t_ns - t0_ns);
    for (PlotSeries* series : {&velocity, &gyro, &accel, &gravity}) series->x.push_back(t_s);
    velocity.y.push_back(s.velocity_mps * 1e2);
    gyro.y.push_back(s.gyro_bias_rad_s * 1e3);
    accel.y.push_back(s.accel_bias_mps2 * 1e2);
    gravity.y.push_back(s.gravity_deg);
  }
  LinePlot velocity_plot("Velocity error", "time [s]", "error");
  velocity_plot.add(std::move(velocity));
  velocity_plot.save(dir / "velocity_error.png");
  LinePlot bias_plot("IMU bias errors", "time [s]", "error");
  bias_plot.add(std::move(gyro));
  bias_plot.add(std::move(accel));
  bias_plot.save(dir / "bias_error.png");
  LinePlot gravity_plot("Gravity direction error", "time [s]", "error");
  gravity_plot.add(std::move(gravity));
  gravity_plot.save(dir / "gravity_error.png");
}

}  // namespace

int runEval(const EvalOptions& options) {
  if (options.up != "y" && options.up != "z") throw Error("--up must be 'y' or 'z', got '" + options.up + "'");
  const std::vector<eval::StampedPose> gt = eval::readTum(options.gt);
  const std::vector<eval::StampedPose> est = eval::readTum(options.est);
  const eval::AteResult ate = eval::ate(gt, est, options.max_difference_s);
  json report;
  report["ate"] = {{"rmse_m", ate.rmse_m}, {"mean_m", ate.mean_m}, {"median_m", ate.median_m}, {"std_m", ate.std_m},
                   {"min_m", ate.min_m},   {"max_m", ate.max_m},   {"pairs", ate.pairs}};
  if (!options.gt_origin.empty()) {
    // The estimate's W is the first camera of the run that built the map: its ground-truth pose is W's.
    const std::vector<eval::StampedPose> origin = eval::readTum(options.gt_origin);
    if (origin.empty()) throw Error(options.gt_origin + ": no poses (--gt-origin)");
    const eval::AteResult in_frame = eval::ateInFrame(gt, est, origin.front().T_world_body, options.max_difference_s);
    report["ate_in_origin_frame"] = {{"rmse_m", in_frame.rmse_m}, {"max_m", in_frame.max_m}, {"pairs", in_frame.pairs}};
  }
  // A run shorter than two RPE steps has no relative error to report; that is not a failure of the
  // run, so the report says why instead of exiting.
  const double span_s = est.empty() ? 0.0 : nsToSeconds(est.back().t_ns - est.front().t_ns);
  if (span_s < 2.0 * options.rpe_delta_s) {
    report["rpe"] = {{"delta_s", options.rpe_delta_s}, {"skipped", "estimate spans less than two RPE steps"}};
  } else {
    const eval::RpeResult rpe = eval::rpe(gt, est, options.rpe_delta_s);
    report["rpe"] = {{"delta_s", options.rpe_delta_s},   {"trans_rmse_m", rpe.trans_rmse_m},
                     {"trans_mean_m", rpe.trans_mean_m}, {"rot_rmse_deg", rpe.rot_rmse_deg},
                     {"rot_mean_deg", rpe.rot_mean_deg}, {"pairs", rpe.pairs}};
  }

  // Velocities, gravity and the map are rotated into the ground truth's world by the alignment of the
  // associated POSES (eval::alignPoses), not by ATE's position-only alignment, whose rotation a short or
  // straight trajectory leaves undetermined (measured: 15° of spurious gravity error over 2 s).
  std::vector<SE3d> est_poses, gt_poses;
  for (std::size_t i = 0; i < ate.pairs; ++i) {
    est_poses.push_back(est[ate.est_index[i]].T_world_body);
    gt_poses.push_back(gt[ate.gt_index[i]].T_world_body);
  }
  const SE3d T_gt_est = eval::alignPoses(est_poses, gt_poses);

  std::optional<eval::StateErrors> state_errors;
  if (!options.states.empty()) {
    const std::filesystem::path gt_states =
        options.gt_states.empty() ? std::filesystem::path(options.gt).parent_path() / "groundtruth_states.csv"
                                  : std::filesystem::path(options.gt_states);
    const Eigen::Vector3d g_gt_W = options.up == "z" ? Eigen::Vector3d(0, 0, -9.81) : Eigen::Vector3d(0, -9.81, 0);
    const std::vector<eval::EstimatedState> states = eval::readEstimatedStates(options.states);
    state_errors =
        eval::stateErrors(datasets::readGroundTruthStates(gt_states), states, T_gt_est.rotationMatrix(), g_gt_W);
    report["states"] = {{"velocity_rms_mps", state_errors->velocity_rms_mps},
                        {"velocity_rms_after_5s_mps", state_errors->velocity_rms_after_5s_mps},
                        {"gyro_bias_max_after_15s_rad_s", state_errors->gyro_bias_max_after_15s},
                        {"accel_bias_max_after_15s_mps2", state_errors->accel_bias_max_after_15s},
                        {"gyro_bias_final_rad_s", state_errors->gyro_bias_final_rad_s},
                        {"accel_bias_final_mps2", state_errors->accel_bias_final_mps2},
                        {"gravity_rms_deg", state_errors->gravity_rms_deg},
                        {"gravity_final_deg", state_errors->gravity_final_deg},
                        {"samples", state_errors->series.size()}};
    const eval::CameraTilt tilt =
        eval::cameraTilt(gt, est, ate.gt_index, ate.est_index, states, g_gt_W, secondsToNs(options.max_difference_s));
    report["camera_tilt"] = {{"rms_deg", tilt.rms_deg},
                             {"max_deg", tilt.max_deg},
                             {"final_deg", tilt.final_deg},
                             {"samples", tilt.series.size()}};
  }

  if (!options.map.empty()) {
    // The true surface is the simulator's analytic living room, in the ground truth's world.
    const scene::LivingRoom room;
    const eval::ReconstructionError error =
        eval::reconstructionError(eval::readPlyPositions(options.map), T_gt_est,
                                  [&](const Eigen::Vector3d& p_W) { return room.distanceToSurface(p_W); });
    report["reconstruction"] = {{"mean_m", error.mean_m},
                                {"median_m", error.median_m},
                                {"rms_m", error.rms_m},
                                {"within_1cm", error.within_1cm},
                                {"points", error.points}};
  }

  if (!options.plots_dir.empty()) {
    std::filesystem::create_directories(options.plots_dir);
    plotTrajectories(options.plots_dir, gt, est, ate, options.up);
    if (state_errors) plotStateErrors(options.plots_dir, *state_errors);
  }
  std::printf("%s\n", report.dump().c_str());
  return 0;
}

}  // namespace vifusion::cli
