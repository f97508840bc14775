#pragma once
// Row-major image views over caller-owned memory and an owning image that allocates once.
// Views carry no ownership, so a GPU-mapped buffer, a decoded PNG and a test fixture all look
// alike to the CPU references and the readers.

#include <cassert>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace vifusion {

/// One RGB888 pixel, bytes in memory order R, G, B (tightly packed, so an RGB image is its bytes).
struct Rgb8 {
  std::uint8_t r = 0;
  std::uint8_t g = 0;
  std::uint8_t b = 0;
  bool operator==(const Rgb8&) const = default;
};
static_assert(sizeof(Rgb8) == 3 && alignof(Rgb8) == 1, "RGB888 images must be tightly packed");

/// A width × height grid of T, rows `stride` elements apart (stride ≥ width).
template <typename T>
struct ImageView {
  T* data = nullptr;
  int width = 0;
  int height = 0;
  std::ptrdiff_t stride = 0;  ///< elements between the starts of consecutive rows

  ImageView() = default;
  ImageView(T* data_, int width_, int height_, std::ptrdiff_t stride_ = 0)
      : data(data_), width(width_), height(height_), stride(stride_ > 0 ? stride_ : width_) {}

  /// Views of non-const T convert to views of const T.
  operator ImageView<const T>() const { return {data, width, height, stride}; }

  T& operator()(int x, int y) const {
    assert(x >= 0 && x < width && y >= 0 && y < height);
    return data[y * stride + x];
  }
  T* row(int y) const { return data + y * stride; }
  bool contains(int x, int y) const { return x >= 0 && x < width && y >= 0 && y < height; }
  std::size_t pixelCount() const { return static_cast<std::size_t>(width) * static_cast<std::size_t>(height); }
  bool empty() const { return data == nullptr || width <= 0 || height <= 0; }
};

/// Owning, tightly packed image. Allocates in the constructor and in resize(), never elsewhere.
template <typename T>
class Image {
 public:
  Image() = default;
  Image(int width, int height, const T& fill = T{}) { resize(width, height, fill); }

  void resize(int width, int height, const T& fill = T{}) {
    width_ = width;
    height_ = height;
    pixels_.assign(static_cast<std::size_t>(width) * static_cast<std::size_t>(height), fill);
  }

  ImageView<T> view() { return {pixels_.data(), width_, height_, width_}; }
  ImageView<const T> view() const { return {pixels_.data(), width_, height_, width_}; }
  T& operator()(int x, int y) { return view()(x, y); }
  const T& operator()(int x, int y) const { return view()(x, y); }

  int width() const { return width_; }
  int height() const { return height_; }
  T* data() { return pixels_.data(); }
  const T* data() const { return pixels_.data(); }
  std::size_t pixelCount() const { return pixels_.size(); }

 private:
  int width_ = 0;
  int height_ = 0;
  std::vector<T> pixels_;
};

}  // namespace vifusion
