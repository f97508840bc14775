#include "vifusion/loop/fern_database.hpp"

#include <algorithm>
#include <cmath>
#include <string>

#include "vifusion/core/error.hpp"

namespace vifusion::loop {
namespace {

int downsampledSize(int input, int factor, const char* what) {
  if (input < 1 || input % factor != 0) {
    throw Error(std::string("fern database: input ") + what + " " + std::to_string(input) +
                " must be a positive multiple of downsample_factor " + std::to_string(factor));
  }
  return input / factor;
}

FernOptions validated(const FernOptions& options) {
  options.validate();
  return options;
}

}  // namespace

FernDatabase::FernDatabase(const FernOptions& options, int input_width, int input_height)
    : options_(validated(options)),
      input_width_(input_width),
      input_height_(input_height),
      encoder_(options_, downsampledSize(input_width, options_.downsample_factor, "width"),
               downsampledSize(input_height, options_.downsample_factor, "height")),
      num_ferns_(options_.num_ferns),
      min_valid_ferns_(std::max(1, static_cast<int>(std::ceil(options_.min_valid_fraction * options_.num_ferns)))),
      pixels_(static_cast<std::size_t>(encoder_.width()) * static_cast<std::size_t>(encoder_.height())) {
  const auto capacity = static_cast<std::size_t>(options_.capacity);
  const auto ferns = static_cast<std::size_t>(num_ferns_);
  T_W_C_.resize(capacity);
  t_ns_.resize(capacity);
  frame_index_.resize(capacity);
  valid_count_.resize(capacity);
  codes_.resize(capacity * ferns);
  rgb_.resize(capacity * pixels_);
  depth_m_.resize(capacity * pixels_);
  head_.assign(ferns * kFernCodeCount, -1);
  next_.assign(ferns * capacity, -1);
  co_occurrences_.assign(capacity, 0);
}

FernFrame FernDatabase::makeFrame() const {
  return FernFrame{FernImage(encoder_.width(), encoder_.height()), FernCodes(num_ferns_)};
}

void FernDatabase::encode(const RgbdFrame& frame, FernFrame& out) const {
  if (frame.rgb.width() != input_width_ || frame.rgb.height() != input_height_) {
    throw Error("fern database: frame " + std::to_string(frame.index) + " is " + std::to_string(frame.rgb.width()) +
                "×" + std::to_string(frame.rgb.height()) + ", the database was made for " +
                std::to_string(input_width_) + "×" + std::to_string(input_height_));
  }
  downsampleForFerns(frame, options_.downsample_factor, options_.max_depth_m, out.image);
  encoder_.encode(out.image, out.codes);
}

void FernDatabase::checkCodes(const FernCodes& codes) const {
  if (codes.size() != num_ferns_) {
    throw Error("fern database: codes of " + std::to_string(codes.size()) + " ferns, the database has " +
                std::to_string(num_ferns_));
  }
}

template <typename Eligible>
FernMatch FernDatabase::best(const FernCodes& codes, Eligible eligible) {
  checkCodes(codes);
  const int query_valid = codes.validCount();
  if (query_valid < min_valid_ferns_ || size_ == 0) return {};

  // Co-occurrences with every keyframe through the inverted index: only keyframes sharing a code are touched.
  std::fill_n(co_occurrences_.begin(), size_, 0u);
  const auto capacity = static_cast<std::size_t>(options_.capacity);
  for (int f = 0; f < num_ferns_; ++f) {
    if (!codes.isValid(f)) continue;
    const std::int32_t* next = next_.data() + static_cast<std::size_t>(f) * capacity;
    for (std::int32_t k = head_[static_cast<std::size_t>(f) * kFernCodeCount + codes.code(f)]; k >= 0; k = next[k]) {
      ++co_occurrences_[static_cast<std::size_t>(k)];
    }
  }

  // Same arithmetic as fernDissimilarity(), so the index and the definition agree exactly.
  FernMatch match;
  for (std::int32_t k = 0; k < size_; ++k) {
    if (!eligible(k)) continue;
    const int n = std::min(query_valid, valid_count_[static_cast<std::size_t>(k)]);
    const int co = static_cast<int>(co_occurrences_[static_cast<std::size_t>(k)]);
    const double d = static_cast<double>(n - co) / static_cast<double>(n);
    if (!match.found() || d < match.dissimilarity) match = FernMatch{k, d};
  }
  return match;
}

FernMatch FernDatabase::nearest(const FernCodes& codes) {
  return best(codes, [](std::int32_t) { return true; });
}

FernMatch FernDatabase::query(const FernCodes& codes, std::uint32_t current_frame_index, std::uint32_t min_frame_gap) {
  const std::uint64_t current = current_frame_index;
  return best(codes, [&](std::int32_t k) {
    return std::uint64_t{frame_index_[static_cast<std::size_t>(k)]} + min_frame_gap <= current;
  });
}

FernAddResult FernDatabase::addIfNovel(const FernFrame& frame, const SE3d& T_W_C, std::int64_t t_ns,
                                       std::uint32_t frame_index) {
  checkCodes(frame.codes);
  checkImage(frame.image);
  if (frame.codes.validCount() < min_valid_ferns_) return {FernAddOutcome::kTooFewValid, FernMatch::kNone, 1.0};

  const FernMatch match = nearest(frame.codes);
  if (match.found() && match.dissimilarity <= options_.keyframe_threshold) {
    return {FernAddOutcome::kSimilar, match.keyframe, match.dissimilarity};
  }
  if (full()) {
    ++full_refusals_;
    return {FernAddOutcome::kFull, match.keyframe, match.dissimilarity};
  }

  return {FernAddOutcome::kAdded, store(frame, T_W_C, t_ns, frame_index), match.dissimilarity};
}

std::int32_t FernDatabase::store(const FernFrame& frame, const SE3d& T_W_C, std::int64_t t_ns,
                                 std::uint32_t frame_index) {
  const std::int32_t id = size_;
  const auto slot = static_cast<std::size_t>(id);
  const auto ferns = static_cast<std::size_t>(num_ferns_);
  T_W_C_[slot] = T_W_C;
  t_ns_[slot] = t_ns;
  frame_index_[slot] = frame_index;
  valid_count_[slot] = frame.codes.validCount();
  std::copy_n(frame.codes.data(), ferns, codes_.begin() + static_cast<std::ptrdiff_t>(slot * ferns));
  std::copy_n(frame.image.rgb.data(), pixels_, rgb_.begin() + static_cast<std::ptrdiff_t>(slot * pixels_));
  std::copy_n(frame.image.depth_m.data(), pixels_, depth_m_.begin() + static_cast<std::ptrdiff_t>(slot * pixels_));
  const auto capacity = static_cast<std::size_t>(options_.capacity);
  for (std::size_t f = 0; f < ferns; ++f) {
    if (!frame.codes.isValid(static_cast<int>(f))) continue;
    std::int32_t& head = head_[f * kFernCodeCount + frame.codes.code(static_cast<int>(f))];
    next_[f * capacity + slot] = head;
    head = id;
  }
  ++size_;
  return id;
}

std::int32_t FernDatabase::restore(const FernFrame& frame, const SE3d& T_W_C, std::int64_t t_ns,
                                   std::uint32_t frame_index) {
  checkCodes(frame.codes);
  checkImage(frame.image);
  if (full()) throw Error("fern database: full (" + std::to_string(options_.capacity) + " keyframes) while restoring");
  return store(frame, T_W_C, t_ns, frame_index);
}

void FernDatabase::checkImage(const FernImage& image) const {
  if (image.width() != encoder_.width() || image.height() != encoder_.height()) {
    throw Error("fern database: keyframe image " + std::to_string(image.width()) + "×" +
                std::to_string(image.height()) + ", expected " + std::to_string(encoder_.width()) + "×" +
                std::to_string(encoder_.height()));
  }
}

void FernDatabase::setPose(std::int32_t id, const SE3d& T_W_C) {
  if (id < 0 || id >= size_) {
    throw Error("fern database: no keyframe " + std::to_string(id) + " (" + std::to_string(size_) + " stored)");
  }
  T_W_C_[static_cast<std::size_t>(id)] = T_W_C;
}

FernKeyframe FernDatabase::keyframe(std::int32_t id) const {
  if (id < 0 || id >= size_) {
    throw Error("fern database: no keyframe " + std::to_string(id) + " (" + std::to_string(size_) + " stored)");
  }
  const auto slot = static_cast<std::size_t>(id);
  const auto ferns = static_cast<std::size_t>(num_ferns_);
  FernKeyframe kf;
  kf.T_W_C = T_W_C_[slot];
  kf.t_ns = t_ns_[slot];
  kf.frame_index = frame_index_[slot];
  kf.codes = std::span<const std::uint8_t>(codes_.data() + slot * ferns, ferns);
  kf.valid_count = valid_count_[slot];
  kf.rgb = ImageView<const Rgb8>(rgb_.data() + slot * pixels_, encoder_.width(), encoder_.height());
  kf.depth_m = ImageView<const float>(depth_m_.data() + slot * pixels_, encoder_.width(), encoder_.height());
  return kf;
}

void FernDatabase::reset() {
  size_ = 0;
  full_refusals_ = 0;
  std::fill(head_.begin(), head_.end(), -1);
}

}  // namespace vifusion::loop
