#pragma once
// Randomised ferns: the tests (drawn once from a seed) and the encoding of a downsampled frame into one 4-bit
// code per fern, plus the dissimilarity of two encoded frames. The database (fern_database.hpp) indexes these
// codes; this header is what a saved database needs to reproduce: the same seed and options give the same
// tests, bit for bit, on every platform.

#include <cstdint>
#include <vector>

#include "vifusion/loop/fern_image.hpp"
#include "vifusion/loop/fern_options.hpp"

namespace vifusion::loop {

/// splitmix64 (Steele, Lea, Flood 2014; Vigna's reference code): a 64-bit generator whose output is fixed by
/// its definition, unlike std::uniform_int_distribution, whose mapping is implementation-defined. Used to
/// draw the fern tests so that a seed means the same tests everywhere.
class SplitMix64 {
 public:
  explicit SplitMix64(std::uint64_t seed) : state_(seed) {}
  std::uint64_t next();
  /// Uniform integer in [0, n), n in [1, 2^32): the high 32 bits scaled by n (bias below 2^-32·n).
  std::uint32_t uniformBelow(std::uint32_t n);
  /// Uniform double in [0, 1) from the high 53 bits.
  double uniformUnit();

 private:
  std::uint64_t state_;
};

/// One fern: a pixel of the downsampled image and its kFernTests thresholds. Code bit 0: R > red,
/// bit 1: G > green, bit 2: B > blue, bit 3: depth_m > depth_m_threshold.
struct Fern {
  int x = 0;  ///< column in the downsampled image [pixels]
  int y = 0;  ///< row in the downsampled image [pixels]
  std::uint8_t red = 0;
  std::uint8_t green = 0;
  std::uint8_t blue = 0;
  float depth_m_threshold = 0.0f;  ///< [m], in [min_depth_m, max_depth_m]
  bool operator==(const Fern&) const = default;
};

/// The codes of one frame, one per fern: a value in [0, kFernCodeCount) or kInvalidFernCode where the fern's
/// pixel has no depth (the depth test cannot be made, and colour alone would match unrelated places).
inline constexpr std::uint8_t kInvalidFernCode = 0xFF;

class FernCodes {
 public:
  FernCodes() = default;
  /// All num_ferns codes invalid (the only allocation).
  explicit FernCodes(int num_ferns) : codes_(static_cast<std::size_t>(num_ferns), kInvalidFernCode) {}

  int size() const { return static_cast<int>(codes_.size()); }
  std::uint8_t code(int fern) const { return codes_[static_cast<std::size_t>(fern)]; }
  bool isValid(int fern) const { return code(fern) != kInvalidFernCode; }
  /// Number of valid codes, kept up to date by set().
  int validCount() const { return valid_count_; }
  /// Sets one code: a value in [0, kFernCodeCount) or kInvalidFernCode (anything else is stored as invalid).
  void set(int fern, std::uint8_t code);
  const std::uint8_t* data() const { return codes_.data(); }
  bool operator==(const FernCodes&) const = default;

 private:
  std::vector<std::uint8_t> codes_;
  int valid_count_ = 0;
};

/// Dissimilarity of two encodings of the same ferns, in [0, 1] (ElasticFusion's definition):
///   n  = min(a.validCount(), b.validCount())
///   co = number of ferns whose codes are valid in a and equal in a and b (an invalid code never matches)
///   D  = (n − co) / n, and D = 1 when n = 0 (nothing to compare).
/// 0: every fern valid in the sparser frame agrees. Dividing by the smaller count means a fern that only one
/// frame can see does not count against the pair, so partial depth loss does not break recognition.
/// Both must have the same size.
double fernDissimilarity(const FernCodes& a, const FernCodes& b);

/// The fern tests for one downsampled size, drawn at construction from options.seed. Per fern, in order:
/// x = uniformBelow(width), y = uniformBelow(height), red, green, blue = uniformBelow(256),
/// depth_m_threshold = float(min_depth_m + uniformUnit()·(max_depth_m − min_depth_m)).
class FernEncoder {
 public:
  /// @param[in] width, height  size of the downsampled image (the input's size / downsample_factor), ≥ 1
  /// @throws vifusion::Error on invalid options or size
  FernEncoder(const FernOptions& options, int width, int height);

  /// Codes of a downsampled frame into `out` (sized numFerns()). Allocates nothing.
  /// @throws vifusion::Error when the image or codes have another size than the encoder's
  void encode(const FernImage& image, FernCodes& out) const;

  int numFerns() const { return static_cast<int>(ferns_.size()); }
  int width() const { return width_; }
  int height() const { return height_; }
  const std::vector<Fern>& ferns() const { return ferns_; }

 private:
  int width_;
  int height_;
  std::vector<Fern> ferns_;
};

}  // namespace vifusion::loop
