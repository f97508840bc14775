#pragma once
// Options of the randomised-fern place recognition (Glocker et al., "Real-time RGB-D camera relocalization via
// randomized ferns for keyframe encoding", TVCG 2015; the scheme ElasticFusion uses for global loop closure and
// relocalisation). A frame is block-averaged to a small image; each fern looks at one pixel of it and makes
// kFernTests binary tests (R, G, B and depth against thresholds), giving a 4-bit code. Frames are compared by
// how many ferns give the same code. Everything that sizes memory is here, so the database allocates once.

#include <cstdint>

namespace vifusion::loop {

/// Binary tests per fern: red, green and blue against a threshold in [0, 255], depth against a threshold in
/// [min_depth_m, max_depth_m]. Fixed: a fern's code is these 4 bits, so a code takes kFernCodeCount values.
inline constexpr int kFernTests = 4;
/// Distinct valid codes of one fern (2^kFernTests).
inline constexpr int kFernCodeCount = 1 << kFernTests;

struct FernOptions {
  /// Number of ferns, i.e. of pixels sampled per frame and of codes per frame (ElasticFusion: 500). More ferns
  /// give a finer dissimilarity at a proportional cost in encode and query time and in memory. [1, 65535].
  int num_ferns = 500;
  /// The input is averaged over factor × factor blocks before encoding (8: 640×480 → 80×60). Averaging makes
  /// the codes robust to noise and small shifts of the view; the input's width and height must be multiples
  /// of it. [1, 64].
  int downsample_factor = 8;
  /// Depth thresholds are drawn uniformly from [min_depth_m, max_depth_m] [m]. Input depth beyond
  /// max_depth_m counts as missing, as in the pipeline's depth gate: it is the noisiest depth and the map
  /// does not hold it. 0 < min_depth_m < max_depth_m.
  float min_depth_m = 0.4f;
  float max_depth_m = 4.0f;
  /// A frame becomes a keyframe when its smallest dissimilarity to every stored keyframe exceeds this, i.e.
  /// when more than this fraction of the ferns comparable with its nearest keyframe give a different code
  /// (fernDissimilarity() defines it). 0.3095 is ElasticFusion's value, which is defined for the same
  /// dissimilarity. Lower adds more keyframes (denser coverage, fuller database). [0, 1).
  double keyframe_threshold = 0.3095;
  /// Smallest fraction of num_ferns that must have a valid code (depth present) for a frame to be added or
  /// queried. The dissimilarity divides by the smaller valid count of the two frames, so a frame with only a
  /// handful of valid ferns would look similar to almost anything. (0, 1].
  double min_valid_fraction = 0.1;
  /// Maximum number of keyframes, fixed at construction. When the database is full, a novel frame is refused
  /// and counted (FernDatabase::fullRefusals()), never stored over an older keyframe: keyframes are added
  /// for novel views only, so their number grows with the explored area, not with time, and the oldest
  /// keyframes are the start and home of the run, the places a long mission most needs to close loops and
  /// relocalise against; replacing them would also reuse ids the caller may still be verifying against.
  /// Memory per keyframe ≈ 7·(W/f)·(H/f) bytes of image + 5·num_ferns bytes of codes and index.
  /// [1, 1'000'000].
  int capacity = 2000;
  /// Seed of the fern tests (pixel positions and thresholds). The same seed, num_ferns, depth range and
  /// downsampled size draw the same tests on every platform (splitmix64 and integer arithmetic only), so runs
  /// are reproducible and a saved database stays usable with its seed. ElasticFusion seeds with the clock.
  std::uint64_t seed = 0;

  /// @throws vifusion::Error naming the first field that is out of its range above.
  void validate() const;
};

}  // namespace vifusion::loop
