#include "frame_budget.hpp"

#include <algorithm>
#include <array>
#include <utility>

namespace vifusion::cli {

void FrameBudget::add(const slam::FrameResult& result) {
  ++frames_;
  preprocess_.add(result.preprocess_ms);
  tracking_.add(result.tracking_ms);
  mapping_.add(result.mapping_ms);
  closure_.add(result.closure.ms);
  fusion_.add(result.map_stages.fusion_ms);
  maintenance_.add(result.map_stages.maintenance_ms);
  prediction_.add(result.map_stages.prediction_ms);
  reference_.add(result.map_stages.reference_ms);
}

nlohmann::json FrameBudget::wallJson() const {
  // Means over all frames, a frame without a closure attempt counting 0 ms.
  const auto per_frame = [&](const Stage& stage) { return frames_ > 0 ? stage.sum_ms / frames_ : 0.0; };
  return {{"preprocess", per_frame(preprocess_)},
          {"tracking", per_frame(tracking_)},
          {"mapping", per_frame(mapping_)},
          {"closure", per_frame(closure_)},
          {"total", per_frame(preprocess_) + per_frame(tracking_) + per_frame(mapping_)}};
}

nlohmann::json FrameBudget::gpuJson() const {
  if (prediction_.frames == 0) return nullptr;
  std::array<std::pair<const char*, double>, 4> stages = {{{"fusion", fusion_.mean()},
                                                           {"maintenance", maintenance_.mean()},
                                                           {"prediction", prediction_.mean()},
                                                           {"reference", reference_.mean()}}};
  nlohmann::json json;
  for (const auto& [name, ms] : stages) json[name] = ms;
  std::stable_sort(stages.begin(), stages.end(), [](const auto& a, const auto& b) { return a.second > b.second; });
  nlohmann::json ranking = nlohmann::json::array();
  for (const auto& stage : stages) ranking.push_back(stage.first);
  json["ranking"] = ranking;
  return json;
}

}  // namespace vifusion::cli
