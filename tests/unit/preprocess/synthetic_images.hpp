#pragma once
// Small helpers for building synthetic test images.

#include "vifusion/core/image.hpp"

namespace vifusion::preprocess::test {

/// Sets every pixel of `image` to value(x, y).
template <typename T, typename F>
void fillImage(Image<T>& image, F value) {
  for (int y = 0; y < image.height(); ++y) {
    for (int x = 0; x < image.width(); ++x) image(x, y) = value(x, y);
  }
}

}  // namespace vifusion::preprocess::test
