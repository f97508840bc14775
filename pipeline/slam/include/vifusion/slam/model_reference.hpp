#pragma once
// The surfel map's prediction becomes the tracker's reference view: the predicted vertex and normal
// maps of every level and the level-0 intensity are copied into DenseTracker::reference(l) (the coarser
// intensities and all gradients follow from DenseTracker::recordReferenceIntensity). One function for
// Slam's per-frame sequence and the benchmark's per-step pipeline, so both do the same work.

#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/gpu/memory_arena.hpp"
#include "vifusion/map/model_prediction.hpp"
#include "vifusion/slam/dense_tracker.hpp"

namespace vifusion::slam {

/// Records the copies; the caller adds the barrier its next step needs.
void recordPredictionAsReference(gpu::CommandRecorder& recorder, const gpu::MemoryArena& arena,
                                 const map::ModelPrediction& prediction, const DenseTracker& tracker);

}  // namespace vifusion::slam
