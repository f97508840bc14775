#pragma once
// The keyframe database of the randomised-fern place recognition (global loop closure and relocalisation,
// DESIGN.md §4.5). Per frame the caller encodes the frame, queries for an old keyframe that looks like it
// (a candidate, which it then verifies by registering the frame against the keyframe's stored small image),
// and offers the frame as a keyframe, which is stored only if it looks unlike every keyframe so far.
//
// A per-fern inverted index (for each fern and code, the keyframes that have that code) makes a query cost
// O(ferns × matching keyframes) instead of O(ferns × keyframes). All memory, keyframe images included, is
// allocated at construction for options.capacity keyframes; encode, query and addIfNovel allocate nothing.
// Not thread-safe: queries use scratch owned by the database (one SLAM thread owns it).

#include <cstdint>
#include <span>
#include <vector>

#include "vifusion/core/image.hpp"
#include "vifusion/core/se3.hpp"
#include "vifusion/core/sensor_data.hpp"
#include "vifusion/loop/fern_encoder.hpp"
#include "vifusion/loop/fern_image.hpp"
#include "vifusion/loop/fern_options.hpp"

namespace vifusion::loop {

/// An encoded frame: its downsampled image and its codes. Made once by FernDatabase::makeFrame() and
/// refilled by encode() every frame.
struct FernFrame {
  FernImage image;
  FernCodes codes;
};

/// The best keyframe for a query. Ties in dissimilarity go to the lowest id (the oldest keyframe).
struct FernMatch {
  static constexpr std::int32_t kNone = -1;
  std::int32_t keyframe = kNone;  ///< keyframe id in [0, size()), or kNone when there was no candidate
  double dissimilarity = 1.0;     ///< fernDissimilarity() to that keyframe, in [0, 1]; 1 when none
  bool found() const { return keyframe != kNone; }
};

/// What addIfNovel() did with a frame.
enum class FernAddOutcome {
  kAdded,        ///< stored as keyframe `keyframe`
  kSimilar,      ///< an existing keyframe (`keyframe`) is within keyframe_threshold: not novel
  kFull,         ///< novel, but the database is at capacity: refused and counted in fullRefusals()
  kTooFewValid,  ///< fewer valid ferns than min_valid_fraction · num_ferns (no depth): not comparable
};

struct FernAddResult {
  FernAddOutcome outcome = FernAddOutcome::kTooFewValid;
  /// kAdded: the new keyframe's id; kSimilar, kFull: the nearest existing keyframe; otherwise FernMatch::kNone.
  std::int32_t keyframe = FernMatch::kNone;
  /// Smallest dissimilarity to the keyframes stored before this call (1 when there were none).
  double min_dissimilarity = 1.0;
  bool added() const { return outcome == FernAddOutcome::kAdded; }
};

/// Read-only view of a stored keyframe; valid until reset() or the database's destruction.
struct FernKeyframe {
  SE3d T_W_C;                           ///< camera pose in the map world W when it was stored (or after setPose)
  std::int64_t t_ns = 0;                ///< time of the frame [ns]
  std::uint32_t frame_index = 0;        ///< the frame's index in the sequence
  std::span<const std::uint8_t> codes;  ///< one code per fern, kInvalidFernCode where invalid
  int valid_count = 0;                  ///< number of valid codes
  ImageView<const Rgb8> rgb;            ///< downsampled colour, for verification
  ImageView<const float> depth_m;       ///< downsampled depth [m], 0 = invalid, for verification
};

class FernDatabase {
 public:
  /// Draws the fern tests and allocates everything for options.capacity keyframes.
  /// @param[in] input_width, input_height  size of the frames that will be encoded [pixels]; multiples of
  ///            options.downsample_factor
  /// @throws vifusion::Error naming the bad option or size
  FernDatabase(const FernOptions& options, int input_width, int input_height);

  /// A frame buffer of the right sizes (allocates; call at start-up).
  FernFrame makeFrame() const;

  /// Downsamples and encodes a registered frame into `out` (from makeFrame()). Allocates nothing.
  /// @throws vifusion::Error when the frame's size differs from the one given at construction
  void encode(const RgbdFrame& frame, FernFrame& out) const;

  /// The most similar keyframe among all stored ones. None when the codes have fewer valid ferns than
  /// min_valid_fraction · num_ferns, or the database is empty.
  FernMatch nearest(const FernCodes& codes);

  /// The most similar keyframe among those at least min_frame_gap frames older than the current frame
  /// (frame_index + min_frame_gap ≤ current_frame_index): recent keyframes would match the current view
  /// without closing a loop. ElasticFusion uses a gap of 300 frames for global loop closure; relocalisation
  /// may use 0. Same validity rule as nearest().
  FernMatch query(const FernCodes& codes, std::uint32_t current_frame_index, std::uint32_t min_frame_gap);

  /// Stores the frame as a keyframe when its smallest dissimilarity to the stored keyframes exceeds
  /// keyframe_threshold, there is room, and enough ferns are valid; the result says which happened.
  /// The caller adds only while tracking is good (the pose is stored as given).
  FernAddResult addIfNovel(const FernFrame& frame, const SE3d& T_W_C, std::int64_t t_ns, std::uint32_t frame_index);

  /// Stores a keyframe of a saved map as it was saved, without the novelty rule (a loaded database holds
  /// exactly the keyframes it held when it was saved). @returns its id
  /// @throws vifusion::Error when the codes or image do not fit this database or it is full
  std::int32_t restore(const FernFrame& frame, const SE3d& T_W_C, std::int64_t t_ns, std::uint32_t frame_index);

  /// Replaces a keyframe's pose (after a map deformation moved it). id in [0, size()).
  void setPose(std::int32_t id, const SE3d& T_W_C);

  /// Keyframe `id` in [0, size()); ids are given in insertion order and never reused until reset().
  FernKeyframe keyframe(std::int32_t id) const;

  /// Drops every keyframe and the refusal count; keeps the memory and the fern tests.
  void reset();

  int size() const { return size_; }
  int capacity() const { return options_.capacity; }
  int inputWidth() const { return input_width_; }    ///< width of the frames it encodes [px]
  int inputHeight() const { return input_height_; }  ///< height of the frames it encodes [px]
  bool full() const { return size_ == options_.capacity; }
  /// Novel frames refused because the database was full, since construction or reset(). Non-zero means
  /// places explored since the database filled cannot be recognised: a health metric, not an error.
  std::uint64_t fullRefusals() const { return full_refusals_; }
  /// Smallest number of valid ferns for a frame to be added or queried.
  int minValidFerns() const { return min_valid_ferns_; }
  const FernOptions& options() const { return options_; }
  const FernEncoder& encoder() const { return encoder_; }

 private:
  template <typename Eligible>
  FernMatch best(const FernCodes& codes, Eligible eligible);
  void checkCodes(const FernCodes& codes) const;
  void checkImage(const FernImage& image) const;
  /// Stores the frame in the next slot and indexes its codes. @returns its id
  std::int32_t store(const FernFrame& frame, const SE3d& T_W_C, std::int64_t t_ns, std::uint32_t frame_index);

  FernOptions options_;
  int input_width_;
  int input_height_;
  FernEncoder encoder_;
  int num_ferns_;
  int min_valid_ferns_;
  std::size_t pixels_;  ///< pixels of one downsampled image

  int size_ = 0;
  std::uint64_t full_refusals_ = 0;

  // Keyframe slots [0, capacity), filled in order.
  std::vector<SE3d> T_W_C_;
  std::vector<std::int64_t> t_ns_;
  std::vector<std::uint32_t> frame_index_;
  std::vector<int> valid_count_;
  std::vector<std::uint8_t> codes_;  ///< capacity × num_ferns
  std::vector<Rgb8> rgb_;            ///< capacity × pixels_
  std::vector<float> depth_m_;       ///< capacity × pixels_

  // Inverted index: one singly linked list per (fern, code), newest first. head_[fern·kFernCodeCount + code]
  // is the first keyframe, next_[fern·capacity + keyframe] the following one; -1 ends a list. Keyed by fern
  // first so that walking one fern's lists stays within a capacity-sized stretch of memory.
  std::vector<std::int32_t> head_;
  std::vector<std::int32_t> next_;
  std::vector<std::uint32_t> co_occurrences_;  ///< query scratch, per keyframe
};

}  // namespace vifusion::loop
