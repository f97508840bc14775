#include "vifusion/eval/metrics.hpp"

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <numbers>
#include <optional>
#include <sstream>

#include "vifusion/core/error.hpp"
#include "vifusion/core/time.hpp"
#include "vifusion/eval/alignment.hpp"
#include "vifusion/eval/associate.hpp"

namespace vifusion::eval {
namespace {

std::vector<std::int64_t> stampsOf(const std::vector<StampedPose>& poses) {
  std::vector<std::int64_t> stamps_ns;
  stamps_ns.reserve(poses.size());
  for (const StampedPose& pose : poses) stamps_ns.push_back(pose.t_ns);
  return stamps_ns;
}

// numpy.median: the mean of the two middle values for an even count.
double median(std::vector<double> values) {
  const std::size_t mid = values.size() / 2;
  std::nth_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid), values.end());
  const double upper = values[mid];
  if (values.size() % 2 == 1) return upper;
  return 0.5 * (*std::max_element(values.begin(), values.begin() + static_cast<std::ptrdiff_t>(mid)) + upper);
}

double rms(const std::vector<double>& values) {
  double sum_sq = 0.0;
  for (const double v : values) sum_sq += v * v;
  return std::sqrt(sum_sq / static_cast<double>(values.size()));
}

double mean(const std::vector<double>& values) {
  double sum = 0.0;
  for (const double v : values) sum += v;
  return sum / static_cast<double>(values.size());
}

// evaluate_rpe.py's find_closest_index, ported line by line: a binary search that remembers the best
// index it visits. For a stamp exactly halfway between two others it returns whichever the search
// path met first; porting it (rather than using lower_bound) keeps such ties identical to the script.
std::size_t findClosestIndex(const std::vector<std::int64_t>& stamps_ns, std::int64_t t_ns) {
  std::size_t beginning = 0;
  std::size_t end = stamps_ns.size();
  std::int64_t difference_ns = std::llabs(stamps_ns[0] - t_ns);
  std::size_t best = 0;
  while (beginning < end) {
    const std::size_t middle = (end + beginning) / 2;
    if (std::llabs(stamps_ns[middle] - t_ns) < difference_ns) {
      difference_ns = std::llabs(stamps_ns[middle] - t_ns);
      best = middle;
    }
    if (stamps_ns[middle] == t_ns) return middle;
    if (stamps_ns[middle] > t_ns) {
      end = middle;
    } else {
      beginning = middle + 1;
    }
  }
  return best;
}

// Rotation angle [rad] of a relative pose. Equal to evaluate_rpe.py's arccos((tr R − 1)/2), but the
// atan2 form keeps full precision for the small angles a 1 s drift produces, where arccos near 1 loses
// half the digits.
double rotationAngleRad(const SE3d& T) {
  const Eigen::Quaterniond& q = T.quaternion();
  return 2.0 * std::atan2(q.vec().norm(), std::abs(q.w()));
}

void requireStrictlyIncreasing(const std::vector<std::int64_t>& stamps_ns, const char* name) {
  for (std::size_t k = 1; k < stamps_ns.size(); ++k) {
    if (stamps_ns[k] <= stamps_ns[k - 1]) {
      throw Error(std::string("rpe: ") + name + " stamps must strictly increase; index " + std::to_string(k) +
                  " does not");
    }
  }
}

}  // namespace

namespace {

/// ATE over the associated pairs with the alignment `given`, or alignRigid's when it is empty.
AteResult ateAligned(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est, double max_difference_s,
                     const std::optional<SE3d>& given) {
  const std::vector<Match> matches = associate(stampsOf(gt), stampsOf(est), secondsToNs(max_difference_s));
  if (matches.size() < 3) {
    std::ostringstream message;
    message << "ate: only " << matches.size() << " stamp pairs within " << max_difference_s * 1e3
            << " ms (need 3 to align)";
    if (!gt.empty() && !est.empty()) {
      message << std::fixed << std::setprecision(3) << "; ground truth spans [" << nsToSeconds(gt.front().t_ns) << ", "
              << nsToSeconds(gt.back().t_ns) << "] s, estimate spans [" << nsToSeconds(est.front().t_ns) << ", "
              << nsToSeconds(est.back().t_ns) << "] s";
    }
    throw Error(message.str());
  }

  std::vector<Eigen::Vector3d> p_est;
  std::vector<Eigen::Vector3d> p_gt;
  AteResult result;
  for (const Match& m : matches) {
    p_gt.push_back(gt[m.index_a].T_world_body.translation());
    p_est.push_back(est[m.index_b].T_world_body.translation());
    result.gt_index.push_back(m.index_a);
    result.est_index.push_back(m.index_b);
  }

  result.pairs = matches.size();
  result.T_gt_est = given ? *given : alignRigid(p_est, p_gt);
  std::vector<double>& errors_m = result.errors_m;
  for (std::size_t i = 0; i < p_est.size(); ++i) errors_m.push_back((result.T_gt_est * p_est[i] - p_gt[i]).norm());

  result.rmse_m = rms(errors_m);
  result.mean_m = mean(errors_m);
  result.median_m = median(errors_m);
  double sum_sq_dev = 0.0;
  for (const double e : errors_m) sum_sq_dev += (e - result.mean_m) * (e - result.mean_m);
  result.std_m = std::sqrt(sum_sq_dev / static_cast<double>(errors_m.size()));
  result.min_m = *std::min_element(errors_m.begin(), errors_m.end());
  result.max_m = *std::max_element(errors_m.begin(), errors_m.end());
  return result;
}

}  // namespace

AteResult ate(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est, double max_difference_s) {
  return ateAligned(gt, est, max_difference_s, std::nullopt);
}

AteResult ateInFrame(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est, const SE3d& T_gt_est,
                     double max_difference_s) {
  return ateAligned(gt, est, max_difference_s, T_gt_est);
}

RpeResult rpe(const std::vector<StampedPose>& gt, const std::vector<StampedPose>& est, double delta_s) {
  if (gt.size() < 2 || est.size() < 2) throw Error("rpe: both trajectories need at least 2 poses");
  const std::vector<std::int64_t> stamps_gt_ns = stampsOf(gt);
  const std::vector<std::int64_t> stamps_est_ns = stampsOf(est);
  requireStrictlyIncreasing(stamps_gt_ns, "ground-truth");
  requireStrictlyIncreasing(stamps_est_ns, "estimate");
  const std::int64_t delta_ns = secondsToNs(delta_s);

  // Twice the median GT period, kept in integer ns: for an even count the median is (a + b) / 2,
  // so twice it is a + b exactly.
  std::vector<std::int64_t> periods_ns;
  for (std::size_t k = 1; k < stamps_gt_ns.size(); ++k) periods_ns.push_back(stamps_gt_ns[k] - stamps_gt_ns[k - 1]);
  std::sort(periods_ns.begin(), periods_ns.end());
  const std::size_t mid = periods_ns.size() / 2;
  const std::int64_t max_gt_offset_ns =
      periods_ns.size() % 2 == 1 ? 2 * periods_ns[mid] : periods_ns[mid - 1] + periods_ns[mid];

  std::vector<double> trans_errors_m;
  std::vector<double> rot_errors_rad;
  for (std::size_t i = 0; i < est.size(); ++i) {
    const std::size_t j = findClosestIndex(stamps_est_ns, stamps_est_ns[i] + delta_ns);
    if (j == est.size() - 1) continue;  // evaluate_rpe.py's end-of-trajectory test; see metrics.hpp.

    const std::size_t gt_i = findClosestIndex(stamps_gt_ns, stamps_est_ns[i]);
    const std::size_t gt_j = findClosestIndex(stamps_gt_ns, stamps_est_ns[j]);
    if (std::llabs(stamps_gt_ns[gt_i] - stamps_est_ns[i]) > max_gt_offset_ns ||
        std::llabs(stamps_gt_ns[gt_j] - stamps_est_ns[j]) > max_gt_offset_ns) {
      continue;
    }

    const SE3d& P_i = est[i].T_world_body;
    const SE3d& P_j = est[j].T_world_body;
    const SE3d& Q_i = gt[gt_i].T_world_body;
    const SE3d& Q_j = gt[gt_j].T_world_body;
    const SE3d E = (P_j.inverse() * P_i).inverse() * (Q_j.inverse() * Q_i);
    trans_errors_m.push_back(E.translation().norm());
    rot_errors_rad.push_back(rotationAngleRad(E));
  }
  if (trans_errors_m.size() < 2) {
    throw Error("rpe: only " + std::to_string(trans_errors_m.size()) + " pose pairs " +
                std::to_string(delta_ns / kNsPerMillisecond) +
                " ms apart have ground truth nearby (need 2); do the trajectories overlap?");
  }

  constexpr double kDegPerRad = 180.0 / std::numbers::pi;
  RpeResult result;
  result.pairs = trans_errors_m.size();
  result.trans_rmse_m = rms(trans_errors_m);
  result.trans_mean_m = mean(trans_errors_m);
  result.rot_rmse_deg = rms(rot_errors_rad) * kDegPerRad;
  result.rot_mean_deg = mean(rot_errors_rad) * kDegPerRad;
  return result;
}

}  // namespace vifusion::eval
