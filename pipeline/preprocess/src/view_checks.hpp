#pragma once
// Argument checks shared by the CPU references: a view whose size disagrees with the push-constant
// block would make the reference compute something other than the shader, so it is refused.

#include <stdexcept>
#include <string>

#include "vifusion/core/image.hpp"

namespace vifusion::preprocess::detail {

template <typename T>
void requireSize(const ImageView<T>& view, int width, int height, const char* function, const char* view_name) {
  if (view.empty() || view.width != width || view.height != height || view.stride < view.width) {
    throw std::invalid_argument(std::string(function) + ": " + view_name + " is " + std::to_string(view.width) +
                                "x" + std::to_string(view.height) + " (stride " + std::to_string(view.stride) +
                                "), expected " + std::to_string(width) + "x" + std::to_string(height));
  }
}

}  // namespace vifusion::preprocess::detail
