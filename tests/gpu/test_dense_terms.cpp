// The dense tracking terms (ICP, photometric, the rotation-only pre-alignment) on real Kinect frames
// (7-Scenes 150 → 151 and 150 → 155): GPU normal equations against the CPU references at every level,
// and Gauss-Newton convergence to the true pose; the reference view's fill-in against its CPU reference.

#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <vector>

#include "gpu_test_environment.hpp"
#include "vifusion/core/so3.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/slam/reference_fill.hpp"
#include "vifusion/slam/rotation_prealignment.hpp"
#include "vifusion/test/seven_scenes_frame.hpp"
#include "vifusion/tracking/icp_cpu.hpp"
#include "vifusion/tracking/icp_term.hpp"
#include "vifusion/tracking/photometric_cpu.hpp"
#include "vifusion/tracking/photometric_term.hpp"
#include "vifusion/tracking/rotation_cpu.hpp"
#include "vifusion/tracking/rotation_term.hpp"

namespace vifusion {
namespace {

using preprocess::GradientPixel;
using preprocess::NormalPixel;
using preprocess::VertexPixel;
using test::GpuTest;

/// Copies of one frame's preprocessed maps at one level (readback buffers, so the CPU can read them).
struct FrameMaps {
  gpu::BufferId vertices, normals, intensity, gradients;
};

/// Preprocesses a reference and a current frame into their own buffers and runs both dense terms
/// between them, on the GPU and with the CPU references.
class TwoFrameFixture {
 public:
  TwoFrameFixture(gpu::GpuContext& context, const test::SevenScenesFrame& reference,
                  const test::SevenScenesFrame& current, const tracking::IcpOptions& icp_options = {})
      : context_(context), icp_options_(icp_options) {
    preprocess::PreprocessOptions options;
    options.camera = current.camera;
    stage_ = std::make_unique<preprocess::PreprocessStage>(context, plan_, options);
    std::vector<tracking::IcpLevelInputs> icp_inputs;
    std::vector<tracking::PhotometricLevelInputs> photometric_inputs;
    for (int l = 0; l < stage_->levels(); ++l) {
      reference_.push_back(declareMaps("reference", l));
      current_.push_back(declareMaps("current", l));
      const FrameMaps& ref = reference_.back();
      const FrameMaps& cur = current_.back();
      icp_inputs.push_back({cur.vertices, cur.normals, ref.vertices, ref.normals});
      photometric_inputs.push_back({cur.vertices, cur.intensity, ref.intensity, ref.gradients, ref.vertices});
    }
    icp_ = std::make_unique<tracking::IcpTerm>(context, plan_, stage_->levels(), icp_options_);
    photometric_ = std::make_unique<tracking::PhotometricTerm>(context, plan_, stage_->levels());
    rotation_ = std::make_unique<tracking::RotationTerm>(context, plan_, 1);
    std::vector<slam::ReferenceFillLevel> fill_levels;
    for (int l = 0; l < stage_->levels(); ++l) {
      fill_levels.push_back({stage_->camera(l), asLevel(current_[l]), asLevel(reference_[l])});
    }
    fill_ = std::make_unique<slam::ReferenceFill>(context, plan_, std::move(fill_levels));
    arena_ = gpu::MemoryArena::create(context, plan_);
    stage_->build(*arena_);
    icp_->build(*arena_, icp_inputs);
    photometric_->build(*arena_, photometric_inputs);
    const int coarsest = stage_->levels() - 1;
    const tracking::RotationInputs rotation_inputs{current_[coarsest].intensity, reference_[coarsest].intensity,
                                                   reference_[coarsest].gradients};
    rotation_->build(*arena_, std::span(&rotation_inputs, 1));
    fill_->build(*arena_);

    const auto preprocess_into = [&](const test::SevenScenesFrame& frame, const std::vector<FrameMaps>& targets) {
      auto sequence = gpu::CommandSequence::create(context, "preprocess+copy");
      sequence->record([&](gpu::CommandRecorder& recorder) {
        stage_->record(recorder);
        for (int l = 0; l < stage_->levels(); ++l) {
          const preprocess::LevelBuffers& level = stage_->level(l);
          copy(recorder, level.vertices, targets[l].vertices);
          copy(recorder, level.normals, targets[l].normals);
          copy(recorder, level.intensity, targets[l].intensity);
          copy(recorder, level.gradients, targets[l].gradients);
        }
        recorder.hostReadBarrier();
      });
      stage_->upload(frame.depth_mm.view(), frame.rgb.view());
      sequence->run();
    };
    preprocess_into(reference, reference_);
    preprocess_into(current, current_);
    rotation_sequence_ = gpu::CommandSequence::create(context, "rotation");
    rotation_sequence_->record([&](gpu::CommandRecorder& recorder) { rotation_->record(recorder, 0); });
    for (int l = 0; l < stage_->levels(); ++l) {
      icp_sequences_.push_back(gpu::CommandSequence::create(context, "icp.l" + std::to_string(l)));
      icp_sequences_.back()->record([&](gpu::CommandRecorder& recorder) { icp_->record(recorder, l); });
      photometric_sequences_.push_back(gpu::CommandSequence::create(context, "photometric.l" + std::to_string(l)));
      photometric_sequences_.back()->record([&](gpu::CommandRecorder& recorder) { photometric_->record(recorder, l); });
    }
  }

  NormalEquations6 icpGpu(int level, const SE3d& T_ref_cur) {
    icp_->setPose(level, T_ref_cur, stage_->camera(level));
    icp_sequences_[level]->run();
    return icp_->result(level);
  }

  NormalEquations6 icpCpu(int level, const SE3d& T_ref_cur) const {
    const PinholeCamera& camera = stage_->camera(level);
    return tracking::icpNormalEquationsCpu(
        image<VertexPixel>(current_[level].vertices, level), image<NormalPixel>(current_[level].normals, level),
        image<VertexPixel>(reference_[level].vertices, level), image<NormalPixel>(reference_[level].normals, level),
        tracking::IcpParams::make(T_ref_cur, camera, icp_options_));
  }

  NormalEquations6 photometricGpu(int level, const SE3d& T_ref_cur, bool use_reference_fill = false) {
    photometric_->setPose(level, T_ref_cur, stage_->camera(level), use_reference_fill);
    photometric_sequences_[level]->run();
    return photometric_->result(level);
  }

  NormalEquations6 photometricCpu(int level, const SE3d& T_ref_cur, bool use_reference_fill = false) const {
    const PinholeCamera& camera = stage_->camera(level);
    return tracking::photometricNormalEquationsCpu(
        image<VertexPixel>(current_[level].vertices, level), image<float>(current_[level].intensity, level),
        image<float>(reference_[level].intensity, level), image<GradientPixel>(reference_[level].gradients, level),
        image<VertexPixel>(reference_[level].vertices, level),
        tracking::PhotometricParams::make(T_ref_cur, camera, tracking::PhotometricOptions{}, level,
                                          use_reference_fill));
  }

  /// The rotation pre-alignment at the coarsest level (the reference frame as the previous one).
  NormalEquations6 rotationGpu(const Eigen::Quaterniond& q_ref_cur) {
    rotation_->setRotation(0, q_ref_cur, stage_->camera(levels() - 1));
    rotation_sequence_->run();
    return rotation_->result(0);
  }

  NormalEquations6 rotationCpu(const Eigen::Quaterniond& q_ref_cur) const {
    const int l = levels() - 1;
    return tracking::rotationNormalEquationsCpu(
        image<float>(current_[l].intensity, l), image<float>(reference_[l].intensity, l),
        image<GradientPixel>(reference_[l].gradients, l),
        tracking::RotationParams::make(q_ref_cur, stage_->camera(l), tracking::PhotometricOptions{}));
  }

  /// Runs the reference fill-in (current frame into the reference maps, in place).
  const slam::ReferenceFill& fill() {
    auto sequence = gpu::CommandSequence::create(context_, "reference fill");
    sequence->record([&](gpu::CommandRecorder& recorder) {
      fill_->recordCoverage(recorder);
      recorder.computeBarrier();
      fill_->recordFill(recorder);
      recorder.hostReadBarrier();
    });
    sequence->run();
    return *fill_;
  }

  int levels() const { return stage_->levels(); }
  const PinholeCamera& camera(int level) const { return stage_->camera(level); }
  template <typename T>
  ImageView<T> hostImage(gpu::BufferId id, int level) const {
    const PinholeCamera& camera = stage_->camera(level);
    return {arena_->buffer(id).hostSpan<T>().data(), camera.width, camera.height};
  }
  const FrameMaps& reference(int level) const { return reference_[level]; }
  const FrameMaps& current(int level) const { return current_[level]; }

 private:
  FrameMaps declareMaps(const std::string& frame, int level) {
    const preprocess::LevelBuffers& source = stage_->level(level);
    const auto mirror = [&](gpu::BufferId id, const char* what) {
      return plan_.addBuffer(frame + ".l" + std::to_string(level) + "." + what, plan_.buffers()[id.index].bytes,
                             gpu::MemoryUse::Readback);
    };
    return {mirror(source.vertices, "vertices"), mirror(source.normals, "normals"),
            mirror(source.intensity, "intensity"), mirror(source.gradients, "gradients")};
  }

  static preprocess::LevelBuffers asLevel(const FrameMaps& maps) {
    return {gpu::BufferId{}, maps.intensity, maps.vertices, maps.normals, maps.gradients};
  }

  void copy(gpu::CommandRecorder& recorder, gpu::BufferId from, gpu::BufferId to) const {
    recorder.copyBuffer(arena_->buffer(from), arena_->buffer(to), arena_->buffer(from).bytes);
  }

  template <typename T>
  ImageView<const T> image(gpu::BufferId id, int level) const {
    const PinholeCamera& camera = stage_->camera(level);
    return {arena_->buffer(id).hostSpan<const T>().data(), camera.width, camera.height};
  }

  gpu::GpuContext& context_;
  tracking::IcpOptions icp_options_;
  gpu::CapacityPlan plan_;
  std::unique_ptr<preprocess::PreprocessStage> stage_;
  std::unique_ptr<tracking::IcpTerm> icp_;
  std::unique_ptr<tracking::PhotometricTerm> photometric_;
  std::unique_ptr<tracking::RotationTerm> rotation_;
  std::unique_ptr<gpu::CommandSequence> rotation_sequence_;
  std::unique_ptr<slam::ReferenceFill> fill_;
  std::vector<FrameMaps> reference_, current_;
  std::unique_ptr<gpu::MemoryArena> arena_;
  std::vector<std::unique_ptr<gpu::CommandSequence>> icp_sequences_, photometric_sequences_;
};

TEST_F(GpuTest, IcpTermMatchesItsCpuReferenceAtEveryLevel) {
  const test::SevenScenesFrame reference = test::loadSevenScenesFrame(150);
  const test::SevenScenesFrame current = test::loadSevenScenesFrame(155);
  TwoFrameFixture icp(context(), reference, current);
  const SE3d T_ref_cur_true = reference.T_W_C.inverse() * current.T_W_C;
  for (const SE3d& T_ref_cur : {SE3d(), T_ref_cur_true}) {
    for (int l = 0; l < icp.levels(); ++l) {
      const NormalEquations6 gpu = icp.icpGpu(l, T_ref_cur);
      const NormalEquations6 cpu = icp.icpCpu(l, T_ref_cur);
      SCOPED_TRACE("level " + std::to_string(l));
      ASSERT_GT(cpu.inliers, 1000.0 / (1 << (2 * l)));
      // A pixel right at a gate may fall either way after float rounding: allow 0.1 % of inliers.
      EXPECT_NEAR(gpu.inliers, cpu.inliers, 1e-3 * cpu.inliers);
      EXPECT_LT((gpu.H - cpu.H).norm() / cpu.H.norm(), 2e-3);
      EXPECT_LT((gpu.b - cpu.b).norm() / cpu.b.norm(), 2e-2);
      EXPECT_EQ(gpu.weighted_squared_bound, 0.0) << "no systematic bound without a calibrated bias σ";
    }
  }
}

TEST_F(GpuTest, IcpTermsSystematicErrorBoundMatchesItsCpuReference) {
  const test::SevenScenesFrame reference = test::loadSevenScenesFrame(150);
  const test::SevenScenesFrame current = test::loadSevenScenesFrame(155);
  tracking::IcpOptions options;
  options.inverse_depth_bias_sigma_per_m = 2e-4f;  // a calibrated rig's σ_b
  TwoFrameFixture icp(context(), reference, current, options);
  // As model registration's renderings: each vertex's w is the depth its surfel was observed from, here the
  // reference seen from 1.5× farther than it now is and the current from where it is.
  constexpr float kReferenceObservedFarther = 1.5f;
  for (int l = 0; l < icp.levels(); ++l) {
    const ImageView<VertexPixel> reference_vertices = icp.hostImage<VertexPixel>(icp.reference(l).vertices, l);
    const ImageView<VertexPixel> current_vertices = icp.hostImage<VertexPixel>(icp.current(l).vertices, l);
    for (std::size_t i = 0; i < reference_vertices.pixelCount(); ++i) {
      VertexPixel& v = reference_vertices.data[i];
      if (v.z() > 0.0f) v.w() = kReferenceObservedFarther * v.z();
      VertexPixel& p = current_vertices.data[i];
      if (p.z() > 0.0f) p.w() = p.z();
    }
  }
  const SE3d T_ref_cur = reference.T_W_C.inverse() * current.T_W_C;
  for (int l = 0; l < icp.levels(); ++l) {
    SCOPED_TRACE("level " + std::to_string(l));
    const NormalEquations6 gpu = icp.icpGpu(l, T_ref_cur);
    const NormalEquations6 cpu = icp.icpCpu(l, T_ref_cur);
    // Each inlier's bound e = σ_b·|(1.5 z)² − z²| = σ_b·1.25 z² > 0.
    ASSERT_GT(cpu.weighted_squared_bound, 0.0);
    EXPECT_NEAR(gpu.weighted_squared_bound, cpu.weighted_squared_bound, 2e-3 * cpu.weighted_squared_bound);
    EXPECT_NEAR(gpu.inliers, cpu.inliers, 1e-3 * cpu.inliers);
  }
}

/// ElasticFusion's schedule (coarse to fine: 4, 5, 10 iterations) of plain Gauss-Newton steps.
SE3d alignCoarseToFine(TwoFrameFixture& icp, SE3d T_ref_cur) {
  const int iterations[3] = {10, 5, 4};
  for (int l = icp.levels() - 1; l >= 0; --l) {
    for (int i = 0; i < iterations[l]; ++i) {
      const NormalEquations6 ne = icp.icpGpu(l, T_ref_cur);
      T_ref_cur = SE3d::exp(ne.H.ldlt().solve(-ne.b)) * T_ref_cur;
    }
  }
  return T_ref_cur;
}

TEST_F(GpuTest, IcpGaussNewtonReturnsToTheTruePoseFromAnOffset) {
  // A frame against itself: the true pose is the identity; start 3 cm and 2.5° away.
  const test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  TwoFrameFixture icp(context(), frame, frame);
  Vector6d offset;
  offset << 0.02, -0.01, 0.02, 0.03, -0.02, 0.01;
  const SE3d estimate = alignCoarseToFine(icp, SE3d::exp(offset));
  EXPECT_LT(estimate.translation().norm(), 1e-4);
  EXPECT_LT(estimate.log().tail<3>().norm(), 0.01 * M_PI / 180.0);
}

TEST_F(GpuTest, IcpGaussNewtonTracksRealFramesAtLeastAsWellAsKinectFusion) {
  const test::SevenScenesFrame reference = test::loadSevenScenesFrame(150);
  for (int index : {151, 155}) {
    const test::SevenScenesFrame current = test::loadSevenScenesFrame(index);
    TwoFrameFixture icp(context(), reference, current);
    const SE3d T_ref_cur_true = reference.T_W_C.inverse() * current.T_W_C;
    const SE3d estimate = alignCoarseToFine(icp, SE3d());  // constant-position guess
    // 7-Scenes poses come from KinectFusion, not motion capture: the frame-to-frame optimum fits
    // the depth better than they do (lower cost, more inliers) and lies within a centimetre or so.
    const NormalEquations6 at_reference_pose = icp.icpGpu(0, T_ref_cur_true);
    const NormalEquations6 at_estimate = icp.icpGpu(0, estimate);
    EXPECT_LT(at_estimate.weighted_squared_residual / at_estimate.inliers,
              at_reference_pose.weighted_squared_residual / at_reference_pose.inliers);
    EXPECT_GE(at_estimate.inliers, at_reference_pose.inliers);
    const SE3d difference = T_ref_cur_true.inverse() * estimate;
    EXPECT_LT(difference.translation().norm(), 0.015) << "frame " << index;
    EXPECT_LT(difference.log().tail<3>().norm(), 0.5 * M_PI / 180.0) << "frame " << index;
  }
}

TEST_F(GpuTest, PhotometricTermMatchesItsCpuReferenceAtEveryLevel) {
  const test::SevenScenesFrame reference = test::loadSevenScenesFrame(150);
  const test::SevenScenesFrame current = test::loadSevenScenesFrame(155);
  TwoFrameFixture terms(context(), reference, current);
  const SE3d T_ref_cur_true = reference.T_W_C.inverse() * current.T_W_C;
  for (const SE3d& T_ref_cur : {SE3d(), T_ref_cur_true}) {
    for (int l = 0; l < terms.levels(); ++l) {
      const NormalEquations6 gpu = terms.photometricGpu(l, T_ref_cur);
      const NormalEquations6 cpu = terms.photometricCpu(l, T_ref_cur);
      SCOPED_TRACE("level " + std::to_string(l));
      ASSERT_GT(cpu.inliers, 1000.0 / (1 << (2 * l)));
      EXPECT_NEAR(gpu.inliers, cpu.inliers, 1e-3 * cpu.inliers);
      EXPECT_LT((gpu.H - cpu.H).norm() / cpu.H.norm(), 2e-3);
      EXPECT_LT((gpu.b - cpu.b).norm() / cpu.b.norm(), 2e-2);
    }
  }
}

TEST_F(GpuTest, PhotometricGaussNewtonReturnsToTheTruePoseFromAnOffset) {
  // A frame against itself (colour and depth need not be registered for this): identity is true.
  const test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  TwoFrameFixture terms(context(), frame, frame);
  Vector6d offset;
  offset << 0.01, -0.01, 0.01, 0.01, -0.015, 0.01;
  SE3d T_ref_cur = SE3d::exp(offset);
  const int iterations[3] = {10, 5, 4};
  for (int l = terms.levels() - 1; l >= 0; --l) {
    for (int i = 0; i < iterations[l]; ++i) {
      const NormalEquations6 ne = terms.photometricGpu(l, T_ref_cur);
      T_ref_cur = SE3d::exp(ne.H.ldlt().solve(-ne.b)) * T_ref_cur;
    }
  }
  EXPECT_LT(T_ref_cur.translation().norm(), 5e-4);
  EXPECT_LT(T_ref_cur.log().tail<3>().norm(), 0.05 * M_PI / 180.0);
}

TEST_F(GpuTest, RotationTermMatchesItsCpuReference) {
  const test::SevenScenesFrame reference = test::loadSevenScenesFrame(150);
  const test::SevenScenesFrame current = test::loadSevenScenesFrame(155);
  TwoFrameFixture terms(context(), reference, current);
  const Eigen::Quaterniond q_true = (reference.T_W_C.inverse() * current.T_W_C).quaternion();
  for (const Eigen::Quaterniond& q :
       {Eigen::Quaterniond::Identity(), q_true, expSO3(Eigen::Vector3d(0.03, -0.06, 0.02)) * q_true}) {
    const NormalEquations6 gpu = terms.rotationGpu(q);
    const NormalEquations6 cpu = terms.rotationCpu(q);
    ASSERT_GT(cpu.inliers, 5000.0) << "most of the 160 × 120 pixels have a gradient";
    EXPECT_EQ(cpu.H.topRows<3>().norm(), 0.0) << "the translation rows stay empty";
    EXPECT_NEAR(gpu.inliers, cpu.inliers, 1e-3 * cpu.inliers);
    EXPECT_NEAR(gpu.candidates, cpu.candidates, 0.0);
    EXPECT_LT((gpu.H - cpu.H).norm() / cpu.H.norm(), 2e-3);
    EXPECT_LT((gpu.b - cpu.b).norm() / cpu.b.norm(), 2e-2);
  }
}

// The pre-alignment's purpose: from the rotation of a fast pan's frame (5°, 10 px at 160 × 120) it must
// find the way back, where a constant-velocity guess would be that far off. At 160 × 120 alone ten steps
// get only to 2.8° (the images do not overlap enough for the linearisation); the coarse-to-fine pyramid
// of RotationPrealignment converges.
TEST_F(GpuTest, RotationPreAlignmentRecoversAFiveDegreePerFrameRotation) {
  const test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  gpu::CapacityPlan plan;
  preprocess::PreprocessOptions options;
  options.camera = frame.camera;
  preprocess::PreprocessStage stage(context(), plan, options);
  slam::RotationPrealignment prealignment(context(), plan, stage, tracking::PhotometricOptions{}, 10, 1e-5);
  const auto arena = gpu::MemoryArena::create(context(), plan);
  stage.build(*arena);
  prealignment.build(*arena);
  auto sequence = gpu::CommandSequence::create(context(), "preprocess");
  sequence->record([&](gpu::CommandRecorder& recorder) {
    prealignment.recordKeepPrevious(recorder);
    recorder.computeBarrier();
    stage.record(recorder);
    recorder.computeBarrier();
    prealignment.recordPyramid(recorder);
  });
  for (int i = 0; i < 2; ++i) {  // the same frame twice: the true rotation is the identity
    stage.upload(frame.depth_mm.view(), frame.rgb.view());
    sequence->run();
    prealignment.framePreprocessed();
  }
  for (const Eigen::Vector3d& axis : {Eigen::Vector3d(0.0, 1.0, 0.0), Eigen::Vector3d(1.0, 1.0, 0.3).normalized()}) {
    const Eigen::Quaterniond q = prealignment.align(expSO3(5.0 * M_PI / 180.0 * axis));
    EXPECT_LT(logSO3(q).norm(), 0.05 * M_PI / 180.0) << "axis " << axis.transpose();
  }
}

/// The reference maps of every level before the fill, as the fixture's host images hold them.
struct ReferenceMapsCopy {
  std::vector<std::vector<VertexPixel>> vertices;
  std::vector<std::vector<NormalPixel>> normals;
  std::vector<std::vector<float>> intensity;
};

/// A prediction with holes: the reference maps of every level with the left `share` of their columns
/// removed; returns them as they are then.
ReferenceMapsCopy removeLeftOfReference(TwoFrameFixture& maps, double share) {
  ReferenceMapsCopy before;
  for (int l = 0; l < maps.levels(); ++l) {
    auto vertices = maps.hostImage<VertexPixel>(maps.reference(l).vertices, l);
    auto normals = maps.hostImage<NormalPixel>(maps.reference(l).normals, l);
    auto intensity = maps.hostImage<float>(maps.reference(l).intensity, l);
    for (int v = 0; v < vertices.height; ++v) {
      for (int u = 0; u < static_cast<int>(share * vertices.width); ++u) {
        vertices(u, v).setZero();
        normals(u, v).setZero();
        intensity(u, v) = 0.0f;
      }
    }
    before.vertices.emplace_back(vertices.data, vertices.data + vertices.width * vertices.height);
    before.normals.emplace_back(normals.data, normals.data + normals.width * normals.height);
    before.intensity.emplace_back(intensity.data, intensity.data + intensity.width * intensity.height);
  }
  return before;
}

// Fill-in of the reference view: the prediction's holes get the frame's own vertices and normals marked with
// w = 0 (the photometric term's "fill", the ICP's "no model") and its level-0 intensity, and the prediction
// keeps what it has; pass 0 counts how
// much of the frame the prediction covered. The GPU against referenceCoverageCpu and referenceFillCpu at
// every level.
TEST_F(GpuTest, ReferenceFillGivesThePredictionsHolesTheFramesMapsForThePhotometricTerm) {
  const test::SevenScenesFrame reference = test::loadSevenScenesFrame(150);
  const test::SevenScenesFrame current = test::loadSevenScenesFrame(155);
  constexpr double kRemovedShare = 0.6;
  TwoFrameFixture maps(context(), reference, current);
  const ReferenceMapsCopy before = removeLeftOfReference(maps, kRemovedShare);
  const auto& vertices_before = before.vertices;
  const auto& normals_before = before.normals;
  const auto& intensity_before = before.intensity;
  const slam::ReferenceCoverage expected_coverage =
      slam::referenceCoverageCpu(maps.hostImage<const VertexPixel>(maps.current(0).vertices, 0),
                                 {vertices_before[0].data(), maps.camera(0).width, maps.camera(0).height});
  const slam::ReferenceFill& fill = maps.fill();
  EXPECT_EQ(fill.coverage().valid_pixels, expected_coverage.valid_pixels);
  EXPECT_EQ(fill.coverage().covered_pixels, expected_coverage.covered_pixels);
  EXPECT_GT(fill.coverage().share(), 0.2);
  EXPECT_LT(fill.coverage().share(), 0.5) << "60 % of the prediction was removed";
  for (int l = 0; l < maps.levels(); ++l) {
    SCOPED_TRACE("level " + std::to_string(l));
    const PinholeCamera& camera = maps.camera(l);
    std::vector<VertexPixel> vertices = vertices_before[l];
    std::vector<NormalPixel> normals = normals_before[l];
    std::vector<float> intensity = intensity_before[l];
    slam::referenceFillCpu(
        maps.hostImage<const VertexPixel>(maps.current(l).vertices, l),
        maps.hostImage<const NormalPixel>(maps.current(l).normals, l),
        maps.hostImage<const float>(maps.current(l).intensity, l), {vertices.data(), camera.width, camera.height},
        {normals.data(), camera.width, camera.height}, {intensity.data(), camera.width, camera.height}, l == 0);
    const auto gpu_vertices = maps.hostImage<const VertexPixel>(maps.reference(l).vertices, l);
    const auto gpu_normals = maps.hostImage<const NormalPixel>(maps.reference(l).normals, l);
    const auto gpu_intensity = maps.hostImage<const float>(maps.reference(l).intensity, l);
    int filled = 0, different = 0, kept = 0;
    for (int i = 0; i < camera.width * camera.height; ++i) {
      const bool was_predicted = vertices_before[l][i].z() > 0.0f;
      if (vertices[i].z() > 0.0f && !was_predicted) {
        ++filled;
        EXPECT_EQ(vertices[i].w(), slam::kFilledVertexW) << "a filled vertex is marked";
        EXPECT_EQ(normals[i].w(), 0.0f) << "a filled normal is not the ICP's";
      }
      if (was_predicted) kept += vertices[i] == vertices_before[l][i] && normals[i] == normals_before[l][i] ? 1 : 0;
      different += gpu_vertices.data[i] != vertices[i] || gpu_normals.data[i] != normals[i] ||
                           gpu_intensity.data[i] != intensity[i]
                       ? 1
                       : 0;
    }
    EXPECT_EQ(different, 0);
    EXPECT_GT(filled, camera.width * camera.height / 3) << "the frame fills most of the removed part";
    EXPECT_GT(kept, camera.width * camera.height / 4) << "the prediction keeps its own pixels";
  }
}

// The photometric term counts filled reference pixels only when asked (PhotometricParams::use_reference_fill):
// without, it sees exactly the prediction with its holes; with, it gains the filled part. The GPU against the
// CPU reference both ways, at every level.
TEST_F(GpuTest, PhotometricTermUsesTheFillOnlyWhenAsked) {
  const test::SevenScenesFrame reference = test::loadSevenScenesFrame(150);
  const test::SevenScenesFrame current = test::loadSevenScenesFrame(155);
  constexpr double kRemovedShare = 0.6;
  TwoFrameFixture terms(context(), reference, current);
  const SE3d T_ref_cur = reference.T_W_C.inverse() * current.T_W_C;
  removeLeftOfReference(terms, kRemovedShare);
  std::vector<NormalEquations6> with_holes;
  for (int l = 0; l < terms.levels(); ++l) with_holes.push_back(terms.photometricGpu(l, T_ref_cur));
  // The fill pass copies the current frame into the reference: the fixture's reference and current frames
  // differ, so the filled part is a different view than the removed one, which is all this test needs.
  terms.fill();
  for (int l = 0; l < terms.levels(); ++l) {
    SCOPED_TRACE("level " + std::to_string(l));
    const NormalEquations6 map_only = terms.photometricGpu(l, T_ref_cur, false);
    EXPECT_EQ(map_only.inliers, with_holes[l].inliers) << "the fill is invisible without use_reference_fill";
    EXPECT_EQ(map_only.H, with_holes[l].H);
    const NormalEquations6 with_fill = terms.photometricGpu(l, T_ref_cur, true);
    // How many: the fixture rebuilds neither the reference gradients nor the coarse intensities after the fill
    // (Slam does), so only "more" is this test's to say; the agreement below is what it checks.
    EXPECT_GT(with_fill.inliers, map_only.inliers) << "the filled 60 % adds pixels";
    for (const bool use_fill : {false, true}) {
      const NormalEquations6 gpu = terms.photometricGpu(l, T_ref_cur, use_fill);
      const NormalEquations6 cpu = terms.photometricCpu(l, T_ref_cur, use_fill);
      EXPECT_NEAR(gpu.inliers, cpu.inliers, 1e-3 * cpu.inliers) << "use_fill " << use_fill;
      EXPECT_LT((gpu.H - cpu.H).norm() / cpu.H.norm(), 2e-3) << "use_fill " << use_fill;
    }
  }
}

}  // namespace
}  // namespace vifusion
