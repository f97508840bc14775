#include "step_pipeline.hpp"

#include <string>

#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/slam/model_reference.hpp"
#include "bench_options.hpp"

namespace vifusion::bench {

StepPipeline::StepPipeline(const RigCalibration& calibration, const slam::SlamOptions& options)
    : tracker_options(options.tracker) {
  gpu::GpuContext& ctx = context();
  const PinholeCamera& camera = calibration.camera;
  tracker = std::make_unique<slam::DenseTracker>(ctx, plan, calibration, tracker_options);
  const preprocess::PreprocessStage& stage = tracker->preprocessing();
  const int levels = tracker_options.levels;
  map = std::make_unique<map::MapBuffers>(plan, options.map, camera);
  fusion = std::make_unique<map::SurfelFusion>(ctx, plan, *map, camera, options.fusion);
  maintenance = std::make_unique<map::MapMaintenance>(ctx, plan, *map, camera, options.maintenance);
  map::PredictionOptions prediction_options = options.prediction;
  prediction_options.levels = levels;
  prediction = std::make_unique<map::ModelPrediction>(ctx, plan, *map, camera, prediction_options);
  exporter = std::make_unique<map::MapExport>(ctx, plan, *map);
  splat_ids_readback = plan.addBuffer("bench.splat_ids", plan.buffers()[prediction->splatIds().index].bytes,
                                      gpu::MemoryUse::Readback);

  Terms& t = terms;
  const auto mirror = [&](gpu::BufferId source, gpu::MemoryUse use, const char* suffix) {
    const gpu::BufferRequest& request = plan.buffers()[source.index];
    const gpu::BufferId copy = t.plan.addBuffer(request.name + suffix, request.bytes, use);
    if (use == gpu::MemoryUse::DeviceLocal) t.copies.push_back({source, copy});
    return copy;
  };
  const auto device = gpu::MemoryUse::DeviceLocal;
  for (int l = 0; l < levels; ++l) {
    const preprocess::LevelBuffers& cur = stage.level(l);
    const preprocess::LevelBuffers& ref = tracker->reference(l);
    const gpu::BufferId cur_vertices = mirror(cur.vertices, device, ".bench");
    const gpu::BufferId ref_vertices = mirror(ref.vertices, device, ".bench");
    t.icp_inputs.push_back({cur_vertices, mirror(cur.normals, device, ".bench"), ref_vertices,
                            mirror(ref.normals, device, ".bench")});
    t.photometric_inputs.push_back({cur_vertices, mirror(cur.intensity, device, ".bench"),
                                    mirror(ref.intensity, device, ".bench"), mirror(ref.gradients, device, ".bench"),
                                    ref_vertices});
  }
  const auto readback = gpu::MemoryUse::Readback;
  const preprocess::LevelBuffers& cur0 = stage.level(0);
  const preprocess::LevelBuffers& ref0 = tracker->reference(0);
  t.cur_vertices = mirror(cur0.vertices, readback, ".readback");
  t.cur_normals = mirror(cur0.normals, readback, ".readback");
  t.cur_intensity = mirror(cur0.intensity, readback, ".readback");
  t.ref_vertices = mirror(ref0.vertices, readback, ".readback");
  t.ref_normals = mirror(ref0.normals, readback, ".readback");
  t.ref_intensity = mirror(ref0.intensity, readback, ".readback");
  t.ref_gradients = mirror(ref0.gradients, readback, ".readback");
  t.icp = std::make_unique<tracking::IcpTerm>(ctx, t.plan, levels, tracker_options.icp);
  t.photometric = std::make_unique<tracking::PhotometricTerm>(ctx, t.plan, levels, tracker_options.photometric);

  arena = gpu::MemoryArena::create(ctx, plan);
  tracker->build(*arena);
  fusion->build(*arena, map::FusionInputs::fromPreprocess(stage));
  maintenance->build(*arena);
  prediction->build(*arena);
  exporter->build(*arena);
  map->reset(*arena);
  splat_ids_copy = gpu::CommandSequence::create(ctx, "bench.splat_ids_copy");
  splat_ids_copy->record([&](gpu::CommandRecorder& recorder) {
    recorder.copyBuffer(arena->buffer(prediction->splatIds()), arena->buffer(splat_ids_readback),
                        arena->buffer(splat_ids_readback).bytes);
    recorder.hostReadBarrier();
  });
  t.arena = gpu::MemoryArena::create(ctx, t.plan);
  t.icp->build(*t.arena, t.icp_inputs);
  t.photometric->build(*t.arena, t.photometric_inputs);

  for (const preprocess::PreprocessStep step : preprocess::kAllPreprocessSteps) {
    preprocess_steps.push_back(gpu::CommandSequence::create(ctx, std::string("bench.pre.") + preprocess::preprocessStepName(step)));
    preprocess_steps.back()->record([&](gpu::CommandRecorder& recorder) { stage.recordStep(recorder, step); });
  }
  for (int parity = 0; parity < 2; ++parity) {
    for (const map::FusionStep step : map::kAllFusionSteps) {
      fusion_steps[parity].push_back(gpu::CommandSequence::create(ctx, std::string("bench.fusion.") + map::fusionStepName(step)));
      fusion_steps[parity].back()->record([&](gpu::CommandRecorder& recorder) { fusion->recordStep(recorder, step, parity); });
    }
    cleanup[parity] = gpu::CommandSequence::create(ctx, "bench.cleanup");
    cleanup[parity]->record([&](gpu::CommandRecorder& recorder) {
      maintenance->recordCleanup(recorder, parity);
      recorder.computeBarrier();
    });
    compaction[parity] = gpu::CommandSequence::create(ctx, "bench.compaction");
    compaction[parity]->record([&](gpu::CommandRecorder& recorder) {
      maintenance->recordCompaction(recorder, parity);
      recorder.hostReadBarrier();
    });
    predict[parity] = gpu::CommandSequence::create(ctx, "bench.predict");
    predict[parity]->record([&](gpu::CommandRecorder& recorder) {
      prediction->record(recorder, parity);
      recorder.hostReadBarrier();
    });
  }
  // As Slam::recordMapUpdate: predicted maps → reference view, then its intensity pyramid and gradients.
  reference_copy = gpu::CommandSequence::create(ctx, "bench.reference_copy");
  reference_copy->record([&](gpu::CommandRecorder& recorder) {
    slam::recordPredictionAsReference(recorder, *arena, *prediction, *tracker);
    recorder.hostReadBarrier();
  });
  reference_gradients = gpu::CommandSequence::create(ctx, "bench.reference_gradients");
  reference_gradients->record([&](gpu::CommandRecorder& recorder) {
    tracker->recordReferenceIntensity(recorder);
    recorder.hostReadBarrier();
  });

  for (int l = 0; l < levels; ++l) {
    t.icp_levels.push_back(gpu::CommandSequence::create(ctx, "bench.icp.l" + std::to_string(l)));
    t.icp_levels.back()->record([&](gpu::CommandRecorder& recorder) { t.icp->record(recorder, l); });
    t.photometric_levels.push_back(gpu::CommandSequence::create(ctx, "bench.photometric.l" + std::to_string(l)));
    t.photometric_levels.back()->record([&](gpu::CommandRecorder& recorder) { t.photometric->record(recorder, l); });
  }
  t.refresh = gpu::CommandSequence::create(ctx, "bench.terms_refresh");
  t.refresh->record([&](gpu::CommandRecorder& recorder) {
    for (auto [from, to] : t.copies) recorder.copyBuffer(arena->buffer(from), t.arena->buffer(to), arena->buffer(from).bytes);
    recorder.computeBarrier();
  });
  t.level0_readback = gpu::CommandSequence::create(ctx, "bench.level0_readback");
  t.level0_readback->record([&](gpu::CommandRecorder& recorder) {
    const tracking::IcpLevelInputs& icp0 = t.icp_inputs[0];
    const tracking::PhotometricLevelInputs& photometric0 = t.photometric_inputs[0];
    for (auto [from, to] : {std::pair{icp0.current_vertices, t.cur_vertices}, std::pair{icp0.current_normals, t.cur_normals},
                            std::pair{photometric0.current_intensity, t.cur_intensity},
                            std::pair{icp0.model_vertices, t.ref_vertices}, std::pair{icp0.model_normals, t.ref_normals},
                            std::pair{photometric0.reference_intensity, t.ref_intensity},
                            std::pair{photometric0.reference_gradients, t.ref_gradients}}) {
      recorder.copyBuffer(t.arena->buffer(from), t.arena->buffer(to), t.arena->buffer(from).bytes);
    }
    recorder.hostReadBarrier();
  });
}

}  // namespace vifusion::bench
