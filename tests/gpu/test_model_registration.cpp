// Local loop closure's model-to-model registration (slam/model_registration.hpp) on real 7-Scenes depth: two
// preprocessed frames stand in for the active and inactive renderings. The same view against itself is the
// identity and accepted; two views 5 frames apart register to the KinectFusion poses' relative motion; a
// view against an unrelated one is refused by name; a layer off by the calibration's depth-bias error is no
// evidence of drift once σ_b is known, while real drift stays evidence; one off by more than the depth noise is
// ambiguous; and the options' validation.

#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <string>
#include <vector>

#include "gpu_test_environment.hpp"
#include "vifusion/gpu/command_sequence.hpp"
#include "vifusion/preprocess/preprocess_stage.hpp"
#include "vifusion/slam/model_registration.hpp"
#include "vifusion/test/expect_error.hpp"
#include "vifusion/test/seven_scenes_frame.hpp"

namespace vifusion {
namespace {

/// One preprocessing stage whose level maps are copied into an "inactive" and an "active" set of buffers.
class RegistrationRig {
 public:
  RegistrationRig(gpu::GpuContext& context, const test::SevenScenesFrame& inactive,
                  const test::SevenScenesFrame& active, const slam::RegistrationOptions& options = {},
                  const tracking::IcpOptions& icp = {}, float inactive_observed_farther = 1.0f) {
    preprocess::PreprocessOptions preprocess_options;
    preprocess_options.camera = active.camera;
    stage_ = std::make_unique<preprocess::PreprocessStage>(context, plan_, preprocess_options);
    const int levels = stage_->levels();
    for (int l = 0; l < levels; ++l) {
      for (const char* role : {"inactive", "active"}) {
        // Host-visible: the vertices' w is set as a rendering's below.
        const auto mirror = [&](gpu::BufferId id, const char* what) {
          return plan_.addBuffer(std::string("test.") + role + ".l" + std::to_string(l) + "." + what,
                                 plan_.buffers()[id.index].bytes, gpu::MemoryUse::Readback);
        };
        (role[0] == 'i' ? inactive_ : active_)
            .push_back({mirror(stage_->level(l).vertices, "vertices"), mirror(stage_->level(l).normals, "normals")});
      }
    }
    registration_ = std::make_unique<slam::ModelRegistration>(context, plan_, levels, icp,
                                                              preprocess_options.metric.max_depth_m, options);
    arena_ = gpu::MemoryArena::create(context, plan_);
    stage_->build(*arena_);
    std::vector<slam::RegistrationLevel> inputs;
    for (int l = 0; l < levels; ++l) {
      inputs.push_back(
          {stage_->camera(l), active_[l].vertices, active_[l].normals, inactive_[l].vertices, inactive_[l].normals});
    }
    registration_->build(*arena_, inputs);
    for (const auto& [frame, targets] : {std::pair{&inactive, &inactive_}, std::pair{&active, &active_}}) {
      auto sequence = gpu::CommandSequence::create(context, "preprocess+copy");
      sequence->record([&](gpu::CommandRecorder& recorder) {
        stage_->record(recorder);
        recorder.computeBarrier();
        for (int l = 0; l < levels; ++l) {
          const preprocess::LevelBuffers& level = stage_->level(l);
          for (const auto& [from, to] :
               {std::pair{level.vertices, (*targets)[l].vertices}, std::pair{level.normals, (*targets)[l].normals}}) {
            recorder.copyBuffer(arena_->buffer(from), arena_->buffer(to), plan_.buffers()[from.index].bytes);
          }
        }
        recorder.computeBarrier();
      });
      stage_->upload(frame->depth_mm.view(), frame->rgb.view());
      sequence->run();
      // A rendering's w is the depth its surfel was observed from (map_predict_attributes.comp): the frame's own
      // depth, the inactive one's times inactive_observed_farther.
      const float observed_farther = targets == &inactive_ ? inactive_observed_farther : 1.0f;
      for (int l = 0; l < levels; ++l) {
        for (Eigen::Vector4f& v : arena_->buffer((*targets)[l].vertices).hostSpan<Eigen::Vector4f>()) {
          if (v.z() > 0.0f) v.w() = observed_farther * v.z();
        }
      }
    }
  }

  slam::RegistrationResult align() { return registration_->align(); }

 private:
  struct Maps {
    gpu::BufferId vertices, normals;
  };
  gpu::CapacityPlan plan_;
  std::unique_ptr<preprocess::PreprocessStage> stage_;
  std::vector<Maps> inactive_, active_;
  std::unique_ptr<slam::ModelRegistration> registration_;
  std::unique_ptr<gpu::MemoryArena> arena_;
};

class ModelRegistrationTest : public test::GpuTest {};

TEST_F(ModelRegistrationTest, AViewAgainstItselfIsTheIdentityAndAccepted) {
  const test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  RegistrationRig rig(context(), frame, frame);
  const slam::RegistrationResult result = rig.align();
  EXPECT_TRUE(result.accepted()) << slam::registrationVerdictName(result.verdict);
  EXPECT_LT(result.T_inactive_active.translation().norm(), 1e-5);
  EXPECT_LT(result.T_inactive_active.log().tail<3>().norm(), 1e-5);
  EXPECT_LT(result.mean_chi2, 0.01) << "identical maps agree exactly";
  EXPECT_GT(result.inliers, 0.5 * 640 * 480);
  EXPECT_LT(result.correction_chi2, 1e-3);
  EXPECT_FALSE(result.significant) << "no correction is no evidence of drift";
}

TEST_F(ModelRegistrationTest, TwoViewsRegisterToTheirRelativeMotion) {
  const test::SevenScenesFrame inactive = test::loadSevenScenesFrame(150);
  const test::SevenScenesFrame active = test::loadSevenScenesFrame(155);
  RegistrationRig rig(context(), inactive, active);
  const slam::RegistrationResult result = rig.align();
  const SE3d T_true = inactive.T_W_C.inverse() * active.T_W_C;
  const SE3d difference = T_true.inverse() * result.T_inactive_active;
  // KinectFusion's poses are not motion capture: within a centimetre and half a degree (as the ICP tests).
  EXPECT_LT(difference.translation().norm(), 0.015);
  EXPECT_LT(difference.log().tail<3>().norm(), 0.5 * M_PI / 180.0);
  EXPECT_GT(T_true.translation().norm(), 0.01) << "the views are apart";
  EXPECT_GT(result.inliers, 0.3 * 640 * 480);
  EXPECT_NEAR(result.correction_m, result.T_inactive_active.log().head<3>().norm(), 1e-12);
  // Centimetres at millimetre σ (the frames' own views disagree to χ² 1.5 per inlier, so the verdict is
  // the residual test's; the correction's χ² is computed either way).
  EXPECT_EQ(result.free_directions, 0) << "a room corner constrains every direction";
  EXPECT_GT(result.correction_chi2, slam::RegistrationOptions{}.min_correction_chi2.back());
  std::printf("registration 150 -> 155: %s, χ² %.3f, σ %.2f mm / %.3f°, correction χ² %.1f, %d iterations\n",
              slam::registrationVerdictName(result.verdict), result.mean_chi2, 1e3 * result.position_sigma_m,
              result.rotation_sigma_rad * 180.0 / M_PI, result.correction_chi2, result.iterations);
}

TEST_F(ModelRegistrationTest, UnrelatedViewsAreRefusedByName) {
  // Frames 150 and 199 see the scene from positions 0.2 m and several degrees apart: from the identity the
  // registration must not claim them; a strict overlap makes the refusal deterministic.
  const test::SevenScenesFrame inactive = test::loadSevenScenesFrame(150);
  const test::SevenScenesFrame active = test::loadSevenScenesFrame(199);
  slam::RegistrationOptions options;
  options.max_correction_m = 0.01;
  RegistrationRig rig(context(), inactive, active, options);
  const slam::RegistrationResult result = rig.align();
  EXPECT_FALSE(result.accepted());
  EXPECT_STRNE(slam::registrationVerdictName(result.verdict), "accepted");
}

TEST_F(ModelRegistrationTest, AWallAloneIsJudgedOverTheDirectionsItHolds) {
  // A fronto-parallel wall 1.5 m away leaves the two in-plane translations and the turn about its normal free.
  // With them projected out the 6×6 system is singular up to rounding: the step must move only what the wall
  // holds (an LDLT of it reported a numerical issue: "diverged"), and the verdict is taken over the three
  // directions left: the same wall agrees with itself, so the old surfaces may be reactivated, nothing moved.
  constexpr std::uint16_t kWallDepthMm = 1500;
  constexpr int kWallFreeDirections = 3;
  test::SevenScenesFrame wall = test::loadSevenScenesFrame(150);
  for (int y = 0; y < wall.depth_mm.height(); ++y) {
    for (int x = 0; x < wall.depth_mm.width(); ++x) wall.depth_mm(x, y) = kWallDepthMm;
  }
  RegistrationRig rig(context(), wall, wall);
  const slam::RegistrationResult result = rig.align();
  EXPECT_EQ(result.free_directions, kWallFreeDirections);
  EXPECT_TRUE(result.accepted()) << slam::registrationVerdictName(result.verdict);
  EXPECT_FALSE(result.significant);
  EXPECT_LT(result.T_inactive_active.translation().norm(), 1e-5);
  EXPECT_LT(result.T_inactive_active.log().tail<3>().norm(), 1e-5);
  EXPECT_TRUE(std::isfinite(result.position_sigma_m) && std::isfinite(result.rotation_sigma_rad))
      << "σ over the held directions only";
}

TEST_F(ModelRegistrationTest, AWallOffsetAlongItsNormalIsMeasuredButNotTrustedToMoveTheMap) {
  // The same wall 20 mm nearer in the active rendering: the correction is that 20 mm along the optical axis
  // (the wall's normal) and nothing along the wall, where the two renderings cannot tell an offset; being
  // evidence of drift with directions free, it is refused: the map would move by what nobody measured.
  constexpr std::uint16_t kWallDepthMm = 1500;
  constexpr std::uint16_t kOffsetMm = 20;
  test::SevenScenesFrame inactive = test::loadSevenScenesFrame(150);
  test::SevenScenesFrame active = inactive;
  for (int y = 0; y < inactive.depth_mm.height(); ++y) {
    for (int x = 0; x < inactive.depth_mm.width(); ++x) {
      inactive.depth_mm(x, y) = kWallDepthMm;
      active.depth_mm(x, y) = kWallDepthMm - kOffsetMm;
    }
  }
  RegistrationRig rig(context(), inactive, active);
  const slam::RegistrationResult result = rig.align();
  EXPECT_EQ(result.verdict, slam::RegistrationVerdict::kUnconstrained) << slam::registrationVerdictName(result.verdict);
  EXPECT_TRUE(result.significant) << "20 mm at millimetre σ";
  const Eigen::Vector3d t = result.T_inactive_active.translation();
  EXPECT_NEAR(t.z(), 1e-3 * kOffsetMm, 1e-3) << "the active camera is nearer the wall";
  EXPECT_LT(t.head<2>().norm(), 1e-4) << "nothing along the wall";
}

/// σ_z at the far end of the depth range the rig's preprocessing keeps [m]: the offset test's bound.
double farDepthSigma(const tracking::IcpOptions& icp) {
  return icp.axialSigmaAt(preprocess::PreprocessOptions{}.metric.max_depth_m);
}

/// The frame as a rig whose inverse-depth correction is off by `bias_per_m` sees it: 1/z_raw = 1/z + b.
test::SevenScenesFrame withInverseDepthBias(test::SevenScenesFrame frame, double bias_per_m) {
  for (int y = 0; y < frame.depth_mm.height(); ++y) {
    for (int x = 0; x < frame.depth_mm.width(); ++x) {
      const double z_m = 1e-3 * frame.depth_mm(x, y);
      if (z_m > 0.0)
        frame.depth_mm(x, y) = static_cast<std::uint16_t>(std::lround(1e3 * z_m / (1.0 + bias_per_m * z_m)));
    }
  }
  return frame;
}

/// Frame 150 seen by a rig whose 1/z correction is off by b = 2σ_b: the old layer (inactive) was observed from 1.5×
/// farther than the new one (active, the frame itself), so its points moved by b·(1.5 z)² and the new ones' by
/// b·z², and the renderings disagree by b·1.25 z², not by drift. `icp` carries σ_b (the calibration's).
struct BiasedLayers {
  static constexpr float kObservedFarther = 1.5f;
  explicit BiasedLayers(double bias_sigma_per_m)
      : bias_per_m(2.0 * bias_sigma_per_m),
        active(test::loadSevenScenesFrame(150)),
        inactive(withInverseDepthBias(active, bias_per_m * (kObservedFarther * kObservedFarther - 1.0))) {
    icp.inverse_depth_bias_sigma_per_m = static_cast<float>(bias_sigma_per_m);
  }
  double bias_per_m;
  test::SevenScenesFrame active, inactive;
  tracking::IcpOptions icp;
};

TEST_F(ModelRegistrationTest, ALayerOffByTheCalibratedDepthBiasIsNoEvidenceOfDrift) {
  // Millimetres at 1–3 m. Without σ_b they are significant against the alignment's noise; with it the
  // correction's χ² is at most (b/σ_b)² = 4 (Σ w e² bounds δᵀHδ; model_registration.hpp), below every
  // min_correction_chi2 entry, and the layers coincide to the depth noise: agreed.
  const BiasedLayers layers(5e-4);
  slam::RegistrationResult without_sigma;
  {
    RegistrationRig rig(context(), layers.inactive, layers.active, {}, {}, BiasedLayers::kObservedFarther);
    without_sigma = rig.align();
  }
  RegistrationRig rig(context(), layers.inactive, layers.active, {}, layers.icp, BiasedLayers::kObservedFarther);
  const slam::RegistrationResult with_sigma = rig.align();
  std::printf("layer off by b = %.0e /m: correction %.2f mm / %.3f°, χ² %.1f without σ_b, %.2f with σ_b = %.0e\n",
              layers.bias_per_m, 1e3 * with_sigma.correction_m, with_sigma.correction_rad * 180.0 / M_PI,
              without_sigma.correction_chi2, with_sigma.correction_chi2, layers.icp.inverse_depth_bias_sigma_per_m);
  const slam::RegistrationOptions defaults;
  EXPECT_GT(without_sigma.correction_chi2, defaults.min_correction_chi2.back()) << "millimetres at sub-mm σ";
  EXPECT_EQ(without_sigma.bias_bound, 0.0);
  EXPECT_GT(with_sigma.bias_bound, 0.0);
  EXPECT_LE(with_sigma.correction_chi2, 4.0);
  EXPECT_FALSE(with_sigma.significant);
  EXPECT_TRUE(with_sigma.accepted()) << slam::registrationVerdictName(with_sigma.verdict);
  EXPECT_NEAR(with_sigma.correction_m, without_sigma.correction_m, 1e-9) << "σ_b judges, it does not move";
  EXPECT_LE(with_sigma.correction_far_m, farDepthSigma(layers.icp)) << "the layers coincide to the depth noise";
}

TEST_F(ModelRegistrationTest, ALayerOffBeyondTheDepthNoiseIsNeitherMovedNorMerged) {
  // The layers above with σ_b (and so b) 2.5 times larger: the correction is still no evidence of drift (χ² ≤ 4),
  // but it moves a point at the far end of the depth range by more than σ_z there. Reactivating the old layer
  // would put both into the active map for tracking to pull between: the registration calls it ambiguous. A bias
  // this large also bends the layer by about the depth noise (χ² per inlier just over 1), which the residual test
  // judges; it is widened here to reach the test after it.
  const BiasedLayers layers(1.25e-3);
  slam::RegistrationOptions options;
  options.max_mean_chi2 = 1.5;
  RegistrationRig rig(context(), layers.inactive, layers.active, options, layers.icp, BiasedLayers::kObservedFarther);
  const slam::RegistrationResult result = rig.align();
  std::printf(
      "layer off by b = %.1e /m: correction %.2f mm / %.3f°, %.1f mm at the far end, χ² %.2f (%.2f per inlier)\n",
      layers.bias_per_m, 1e3 * result.correction_m, result.correction_rad * 180.0 / M_PI, 1e3 * result.correction_far_m,
      result.correction_chi2, result.mean_chi2);
  EXPECT_LE(result.correction_chi2, 4.0);
  EXPECT_FALSE(result.significant);
  EXPECT_GT(result.correction_far_m, farDepthSigma(layers.icp));
  EXPECT_EQ(result.verdict, slam::RegistrationVerdict::kAmbiguous) << slam::registrationVerdictName(result.verdict);
}

TEST_F(ModelRegistrationTest, LayersObservedFromTheSameDepthShareTheBias) {
  // Both layers observed from where the camera is now: a common 1/z error moves both renderings alike, so σ_b
  // adds nothing to the covariance.
  tracking::IcpOptions icp;
  icp.inverse_depth_bias_sigma_per_m = 5e-4f;
  const test::SevenScenesFrame frame = test::loadSevenScenesFrame(150);
  RegistrationRig rig(context(), frame, frame, {}, icp);
  EXPECT_EQ(rig.align().bias_bound, 0.0);
}

TEST_F(ModelRegistrationTest, DriftBeyondTheCalibratedDepthBiasStaysEvidenceOfDrift) {
  // Centimetres of motion between the two views (150 → 155), the old layer observed from 1.5× farther, against a
  // calibrated rig's σ_b: the systematic part bounds millimetres, so the correction is still evidence of drift.
  constexpr double kBiasSigma_per_m = 2e-4;
  constexpr float kObservedFarther = 1.5f;
  const test::SevenScenesFrame inactive = test::loadSevenScenesFrame(150);
  const test::SevenScenesFrame active = test::loadSevenScenesFrame(155);
  tracking::IcpOptions icp;
  icp.inverse_depth_bias_sigma_per_m = static_cast<float>(kBiasSigma_per_m);
  RegistrationRig rig(context(), inactive, active, {}, icp, kObservedFarther);
  const slam::RegistrationResult result = rig.align();
  std::printf("150 -> 155 with σ_b = %.0e: correction χ² %.1f (Σ w e² %.0f over %.0f inliers)\n", kBiasSigma_per_m,
              result.correction_chi2, result.bias_bound, result.inliers);
  EXPECT_GT(result.bias_bound, 0.0);
  EXPECT_GT(result.correction_chi2, slam::RegistrationOptions{}.min_correction_chi2.back());
}

TEST(RegistrationOptions, ValidationNamesTheField) {
  slam::RegistrationOptions options;
  options.min_overlap_share = 0.0;
  test::expectError([&] { options.validate(); }, "registration option 'min_overlap_share'");
  options = {};
  options.max_mean_chi2 = -1.0;
  test::expectError([&] { options.validate(); }, "registration option 'max_mean_chi2'");
  options = {};
  options.min_correction_chi2[2] = 0.0;
  test::expectError([&] { options.validate(); }, "registration option 'min_correction_chi2'");
}

}  // namespace
}  // namespace vifusion
