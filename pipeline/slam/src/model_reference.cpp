#include "vifusion/slam/model_reference.hpp"

#include <utility>

namespace vifusion::slam {

void recordPredictionAsReference(gpu::CommandRecorder& recorder, const gpu::MemoryArena& arena,
                                 const map::ModelPrediction& prediction, const DenseTracker& tracker) {
  for (int l = 0; l < prediction.levels(); ++l) {
    const map::ModelLevelBuffers& model = prediction.level(l);
    const preprocess::LevelBuffers& reference = tracker.reference(l);
    for (auto [from, to] :
         {std::pair{model.vertices, reference.vertices}, std::pair{model.normals, reference.normals}}) {
      recorder.copyBuffer(arena.buffer(from), arena.buffer(to), arena.buffer(from).bytes);
    }
  }
  const gpu::GpuBuffer& model_intensity = arena.buffer(prediction.level(0).intensity);
  recorder.copyBuffer(model_intensity, arena.buffer(tracker.reference(0).intensity), model_intensity.bytes);
}

}  // namespace vifusion::slam
