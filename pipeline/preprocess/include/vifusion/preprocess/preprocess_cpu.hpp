#pragma once
// The whole preprocessing stage run by the CPU references, step for step like PreprocessStage:
// the yardstick for the GPU in benchmarks and the self-check. Images are allocated once.

#include <cstdint>
#include <vector>

#include "vifusion/core/image.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"

namespace vifusion::preprocess {

class PreprocessCpu {
 public:
  struct Level {
    Image<float> depth_m;
    Image<float> intensity;
    Image<VertexPixel> vertices;
    Image<NormalPixel> normals;
    Image<GradientPixel> gradients;
  };

  explicit PreprocessCpu(const PreprocessOptions& options);

  void setInput(ImageView<const std::uint16_t> depth_raw, ImageView<const Rgb8> rgb);
  void runStep(PreprocessStep step);
  void run();

  /// Raw depth registered to the colour camera; empty unless options.registersDepth().
  const Image<std::uint16_t>& registeredDepth() const { return registered_raw_; }
  const Image<float>& rawDepth() const { return raw_depth_m_; }
  const Image<VertexPixel>& filteredVertices() const { return filtered_vertices_; }
  const Level& level(int l) const { return levels_[l]; }

 private:
  PreprocessOptions options_;
  std::vector<PinholeCamera> cameras_;
  ImageView<const std::uint16_t> depth_raw_;
  ImageView<const Rgb8> rgb_;
  RegisterDepthParams registration_params_;
  Image<std::uint16_t> registered_raw_;
  Image<float> raw_depth_m_;
  Image<VertexPixel> filtered_vertices_;  ///< level 0, input of the level-0 normals
  std::vector<Level> levels_;
};

}  // namespace vifusion::preprocess
