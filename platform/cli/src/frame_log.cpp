#include "frame_log.hpp"

#include <cstdio>
#include <numbers>

#include "vifusion/core/atomic_file.hpp"
#include "vifusion/core/error.hpp"

namespace vifusion::cli {
namespace {
constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;
}  // namespace

void FrameLog::add(const slam::FrameResult& result) {
  rows_.push_back({result.t_ns,
                   result.tracking,
                   result.pose_sigma_m,
                   result.inertial && !result.imu_issue.has_value(),
                   result.icp_inliers,
                   result.icp_candidates,
                   result.rgb_inliers,
                   result.coverage,
                   result.used_reference_fill,
                   result.iterations,
                   result.surfels,
                   result.active_surfels,
                   result.map_evicted,
                   result.preprocess_ms,
                   result.tracking_ms,
                   result.mapping_ms,
                   result.map_stages,
                   result.imu_chi2,
                   result.vision_chi2,
                   result.vision_rejected,
                   static_cast<int>(result.closure.outcome),
                   static_cast<int>(result.closure.refusal),
                   1e3 * result.closure.constraint_error_after_m,
                   result.closure.registration.inliers,
                   result.closure.registration.mean_chi2,
                   1e3 * result.closure.registration.position_sigma_m,
                   result.closure.registration.rotation_sigma_rad * kDegreesPerRadian,
                   result.closure.ms,
                   1e3 * result.closure.registration.correction_m,
                   result.closure.registration.correction_rad * kDegreesPerRadian,
                   result.closure.registration.correction_chi2,
                   result.closure.registration.free_directions,
                   result.relocalised,
                   result.icp_energy,
                   result.place_agreement,
                   result.map_search_hypotheses,
                   result.map_search_verified,
                   result.map_search_cost,
                   result.map_search_inliers});
}

void FrameLog::addUnreadable(std::int64_t t_ns) {
  Row row;
  row.t_ns = t_ns;
  row.unreadable = true;
  rows_.push_back(row);
}

void FrameLog::write(const std::filesystem::path& path) const {
  printFileAtomically(path, [&](std::FILE* file) { print(file); });
}

void FrameLog::print(std::FILE* file) const {
  std::fprintf(
      file,
      "#t_ns,tracking,lost,pose_sigma_m,imu,icp_inliers,icp_candidates,rgb_inliers,coverage,fill,iterations,"
      "surfels,active_surfels,evicted,preprocess_ms,tracking_ms,"
      "mapping_ms,fusion_gpu_ms,maintenance_gpu_ms,prediction_gpu_ms,reference_gpu_ms,imu_chi2,vision_chi2,vision_"
      "rejected,closure,closure_refusal,closure_error_mm,closure_"
      "inliers,closure_mean_chi2,closure_sigma_mm,closure_sigma_deg,closure_ms,closure_correction_mm,closure_"
      "correction_deg,closure_"
      "chi2,closure_free_directions,relocalised,icp_energy,place_overlap,place_depth_agreeing,place_luma_ncc,map_"
      "search_hypotheses,map_search_"
      "verified,map_search_cost,map_search_inliers,unreadable\n");
  for (const Row& r : rows_) {
    std::fprintf(file,
                 "%lld,%d,%d,%.6g,%d,%.0f,%.0f,%.0f,%.4f,%d,%d,%u,%u,%u,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.3f,%.6g,%.6g,%"
                 "d,%d,%d,%.3f,%.0f,%.6g,%.3f,%"
                 ".4f,%.1f,%.3f,%.4f,%.4g,%d,%d,%.3f,%d,%d,%.3f,%d,%d,%.4f,%.3f,%d\n",
                 static_cast<long long>(r.t_ns), r.unreadable ? -1 : static_cast<int>(r.tracking),
                 r.tracking == slam::TrackingState::kLost ? 1 : 0, r.pose_sigma_m, r.imu ? 1 : 0, r.icp_inliers,
                 r.icp_candidates, r.rgb_inliers, r.coverage, r.fill ? 1 : 0, r.iterations, r.surfels, r.active_surfels,
                 r.evicted, r.preprocess_ms, r.tracking_ms, r.mapping_ms, r.map_stages.fusion_ms,
                 r.map_stages.maintenance_ms, r.map_stages.prediction_ms, r.map_stages.reference_ms, r.imu_chi2,
                 r.vision_chi2, r.vision_rejected ? 1 : 0, r.closure, r.closure_refusal, r.closure_error_mm,
                 r.closure_inliers, r.closure_mean_chi2, r.closure_sigma_mm, r.closure_sigma_deg, r.closure_ms,
                 r.closure_correction_mm, r.closure_correction_deg, r.closure_chi2, r.closure_free_directions,
                 r.relocalised ? 1 : 0, r.icp_energy, r.place_agreement.overlap, r.place_agreement.depth_agreeing,
                 r.place_agreement.luma_ncc, r.map_search_hypotheses, r.map_search_verified, r.map_search_cost,
                 r.map_search_inliers, r.unreadable ? 1 : 0);
  }
}

}  // namespace vifusion::cli
