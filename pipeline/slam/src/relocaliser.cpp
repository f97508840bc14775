#include "vifusion/slam/relocaliser.hpp"

#include <algorithm>

#include "vifusion/core/error.hpp"

namespace vifusion::slam {

void RelocalisationOptions::validate() const {
  ferns.validate();
  distance_field.validate();
  search.validate();
  if (fern_image_width < 1) throw Error("relocalisation option 'fern_image_width' must be ≥ 1");
}

namespace {

/// `options` with the downsample factor for width × height (RelocalisationOptions::fern_image_width).
RelocalisationOptions forFrameSize(RelocalisationOptions options, int width, int height) {
  options.validate();
  int factor = std::max(1, width / options.fern_image_width);
  while (factor > 1 && (width % factor != 0 || height % factor != 0)) --factor;
  options.ferns.downsample_factor = factor;
  return options;
}

}  // namespace

Relocaliser::Relocaliser(const RelocalisationOptions& options, int width, int height)
    : options_(forFrameSize(options, width, height)),
      database_(options_.ferns, width, height),
      frame_(database_.makeFrame()),
      last_tracked_(options_.ferns.num_ferns) {}

void Relocaliser::replaceDatabase(loop::FernDatabase database) {
  if (database.inputWidth() != database_.inputWidth() || database.inputHeight() != database_.inputHeight()) {
    throw Error("relocalisation: the saved keyframes are of " + std::to_string(database.inputWidth()) + "x" +
                std::to_string(database.inputHeight()) + " frames, this camera's are " +
                std::to_string(database_.inputWidth()) + "x" + std::to_string(database_.inputHeight()));
  }
  database_ = std::move(database);
  options_.ferns = database_.options();
  frame_ = database_.makeFrame();
  last_tracked_ = loop::FernCodes(options_.ferns.num_ferns);
}

void Relocaliser::encode(const RgbdFrame& frame) { database_.encode(frame, frame_); }

void Relocaliser::offer(const SE3d& T_W_C, std::int64_t t_ns, std::uint32_t frame_index) {
  database_.addIfNovel(frame_, T_W_C, t_ns, frame_index);
  last_tracked_ = frame_.codes;  // same size: no allocation
}

bool Relocaliser::looksLikeLastTracked() const {
  if (frame_.codes.validCount() < database_.minValidFerns() || last_tracked_.validCount() < database_.minValidFerns()) {
    return false;
  }
  return loop::fernDissimilarity(frame_.codes, last_tracked_) <= options_.ferns.keyframe_threshold;
}

loop::KeyframeAgreement Relocaliser::agreement(const PlaceCandidate& place, const SE3d& T_W_C,
                                               const PinholeCamera& camera, double depth_gate_m) const {
  const loop::FernKeyframe keyframe = database_.keyframe(place.keyframe);
  return loop::keyframeAgreement(frame_.image, keyframe, place.T_W_C.inverse() * T_W_C, camera,
                                 options_.ferns.downsample_factor, depth_gate_m);
}

std::optional<PlaceCandidate> Relocaliser::candidate() {
  const loop::FernMatch match = database_.nearest(frame_.codes);
  if (!match.found() || match.dissimilarity > options_.ferns.keyframe_threshold) return std::nullopt;
  const loop::FernKeyframe keyframe = database_.keyframe(match.keyframe);
  return PlaceCandidate{match.keyframe, keyframe.T_W_C, keyframe.frame_index, match.dissimilarity};
}

}  // namespace vifusion::slam
