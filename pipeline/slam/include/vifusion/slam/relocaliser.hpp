#pragma once
// Relocalisation by place recognition (ElasticFusion's, DESIGN.md §4.5): while tracking holds, frames that look
// unlike every stored keyframe are kept in a randomised-fern database (loop/fern_database.hpp) with their pose;
// when RGB-D tracking is lost and the recovery's own guesses (the last tracked pose, the continued motion) fail,
// the lost frame is looked up there, and the nearest keyframe's pose becomes a third guess, which the caller
// verifies by tracking the frame against the map rendered at that pose with the tests of a frame that ends a
// loss (Slam::relocalise, DenseTracker::explainsFrame). Nothing is fused
// while lost, so a wrong guess that fails verification costs time, not map.
//
// A keyframe's pose is the map's at the time it was stored; a loop closure moves the map, so the caller moves
// the keyframes with it (moveKeyframes). Everything is allocated at construction (the database's capacity);
// encode, offer and candidate allocate nothing. One SLAM thread owns it.

#include <cstdint>
#include <optional>

#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/loop/fern_database.hpp"
#include "vifusion/loop/fern_options.hpp"
#include "vifusion/loop/global_place_search.hpp"
#include "vifusion/loop/keyframe_agreement.hpp"

namespace vifusion::slam {

struct RelocalisationOptions {
  /// Off: a lost RGB-D run recovers only from its own guesses (and the database is not allocated).
  bool enabled = true;
  /// The keyframe database. A lost frame is matched to its nearest keyframe only within the database's own
  /// keyframe_threshold: a view that close to a keyframe is, by the rule that stores keyframes, the same place.
  /// Its downsample_factor is replaced by the one fern_image_width gives.
  loop::FernOptions ferns;
  /// The ferns see the frame block-averaged to about this width [px] whatever the camera's resolution
  /// (ElasticFusion: 640×480 by 8, 80×60): the largest factor that divides width and height and leaves the image
  /// at least this wide, so a 160×120 run recognises places from the same 80×60 image as a 640×480 one rather
  /// than from 20×15. ≥ 1.
  int fern_image_width = 80;
  /// Entering a saved map in the inertial modes (Slam::loadMap): when no keyframe recognises a frame, search the
  /// whole map for it (loop/global_place_search.hpp) — a camera that enters along another path sees the map's
  /// surfaces from where no keyframe was taken. Off: keyframes only.
  bool map_search = true;
  loop::DistanceFieldOptions distance_field;
  loop::GlobalSearchOptions search;

  /// Throws vifusion::Error naming the field out of range.
  void validate() const;
};

/// A recognised place: the keyframe the lost frame looks like.
struct PlaceCandidate {
  std::int32_t keyframe = loop::FernMatch::kNone;
  SE3d T_W_C;                     ///< its pose in the map world (moved by every closure since)
  std::uint32_t frame_index = 0;  ///< the frame it was stored at
  double dissimilarity = 1.0;     ///< loop::fernDissimilarity to the lost frame, in [0, 1]
};

class Relocaliser {
 public:
  /// Allocates the database for frames of width × height (multiples of ferns.downsample_factor). Throws
  /// vifusion::Error naming the option or size that is wrong.
  Relocaliser(const RelocalisationOptions& options, int width, int height);

  /// Encodes this frame's images (every frame: a tracked one may be offered, a lost one looked up). No allocation.
  void encode(const RgbdFrame& frame);
  /// After a tracked frame: stores the encoded frame with its pose when it is novel (FernDatabase::addIfNovel).
  void offer(const SE3d& T_W_C, std::int64_t t_ns, std::uint32_t frame_index);
  /// For a lost frame: the nearest keyframe within the keyframe threshold, if any.
  std::optional<PlaceCandidate> candidate();
  /// Whether this frame looks like the last tracked (offered) one, within the keyframe threshold: the recovery's
  /// guesses assume the camera came back to that view (Slam::trackRgbd), and from a guess seconds old a frame
  /// that sees elsewhere can still find a few of its surfaces within the tracker's bounds and pass its tests
  /// (tests/bench/README.md, "Relocalisation"). False before any frame was offered.
  bool looksLikeLastTracked() const;
  /// Moves every keyframe's pose by `deform` (a callable SE3d(const SE3d& T_W_C, std::uint32_t frame), the map's
  /// deformation at an accepted loop closure).
  template <class Deform>
  void moveKeyframes(const Deform& deform) {
    for (std::int32_t id = 0; id < database_.size(); ++id) {
      const loop::FernKeyframe keyframe = database_.keyframe(id);
      database_.setPose(id, deform(keyframe.T_W_C, keyframe.frame_index));
    }
  }
  int keyframes() const { return database_.size(); }
  /// Replaces the keyframes (and the ferns, drawn again from the saved seed) with a saved map's
  /// (mapfile/map_sections.hpp), before the first frame. Allocates. @throws vifusion::Error when the saved
  /// database was made for frames of another size
  void replaceDatabase(loop::FernDatabase database);
  /// How this frame, placed at T_W_C, agrees with the keyframe of `place` image to image
  /// (loop/keyframe_agreement.hpp). No allocation.
  loop::KeyframeAgreement agreement(const PlaceCandidate& place, const SE3d& T_W_C, const PinholeCamera& camera,
                                    double depth_gate_m) const;
  /// Drops every keyframe (a load that failed half-way).
  void reset() { database_.reset(); }
  /// The block image of the last encoded frame (what the map search places, loop/global_place_search.hpp).
  const loop::FernImage& frameImage() const { return frame_.image; }
  /// The keyframes and their ferns (what a saved map keeps: mapfile/map_sections.hpp).
  const loop::FernDatabase& database() const { return database_; }
  /// The block-averaging factor fern_image_width chose for this frame size.
  int downsampleFactor() const { return options_.ferns.downsample_factor; }
  /// Novel frames refused because the database was full (FernDatabase::fullRefusals).
  std::uint64_t fullRefusals() const { return database_.fullRefusals(); }

 private:
  RelocalisationOptions options_;
  loop::FernDatabase database_;
  loop::FernFrame frame_;
  loop::FernCodes last_tracked_;  ///< the codes of the last offered frame
};

}  // namespace vifusion::slam
