#pragma once
// Synthetic camera paths in the ICL-NUIM living room (y up, floor y = 0, ceiling 2.7 m, room ≈ 5.5 m × 6 m
// centred near (1.1, 0, −0.2)). Each preset is a smooth closed-form motion sampled at 30 Hz into camera
// poses T_W_C (camera x right, y down, z forward), the same form as a trajectory file, so presets and
// files take the same path: fitTrajectory → spline → IMU simulation and rendering. Camera positions stay in
// the ICL-NUIM box x ∈ [−0.1, 2.3], y ∈ [0.5, 1.8], z ∈ [−1.9, 1.6] m and the camera looks roughly
// horizontally. Every preset starts and ends at rest (a smooth time warp ramps the motion in and out),
// which gives an estimator a static start and a clean end.
//
// Measured on the fitted spline (default TrajectoryFitOptions, T_S_C = identity; tests/unit/sim print the
// figures for a rig with a 4.7 cm lever arm and check them loosely): peak |v|, peak |ω|, peak |a|.
//  - "fast":           20 s hand-held motion through the room, 20.5 m, peak 1.9 m/s, 3.05 rad/s, 2.7 m/s²;
//  - "quick_rotation": 20 s of fast pans (±115° yaw swings at 0.4 Hz, some tilt) while drifting slowly,
//                      peak 5.3 rad/s (below the 7.8 rad/s gyro saturation on every axis), 0.26 m/s;
//  - "white_wall":     20 s slow walk along z (−0.9 … 0.85 m) looking into the room (+z), with a turn to
//                      the blank x = 3.85 m wall and a pass along it from ≈ 1.6 m, where it fills the view
//                      (≈ 4 s from t ≈ 6.8 s), then back to the part of the room mapped before — the
//                      paper's low-texture sequences 16–17 (18 stays on the wall "too long" and fails);
//                      peak 0.35 m/s, 1.7 rad/s in the turns;
//  - "long":           60 s, two laps (16.4 m) of an ellipse around the room looking outward at ≈ 60° from the
//                      direction of travel, ending exactly on its start pose (a loop closure), peak 0.35 m/s,
//                      0.44 rad/s;
//  - "unmapped_turn":  16 s slow walk (≤ 0.4 m/s) looking at the room's north half, then a 180° turn in 1.4 s
//                      (peak 4.1 rad/s, t ≈ 6.8–8.2 s) to the south half, which it has not seen, and a slow
//                      walk there — the paper's "quick rotation into an unmapped area";
//  - "fast_pan":       14 s standing with a hand-held pan from the start: 2.65 rad/s peak after a 0.7 s ramp,
//                      410° in 3.5 s, so the view leaves the first frame's map within a second, then slow
//                      looking around; the position sways ±4 cm.
// The first four keep every frequency ≤ 0.45 Hz and ramp over 2.5–3 s, so the default fit (every 10th pose,
// i.e. 3 Hz) reproduces every 30 Hz pose to < 1 mm and < 0.33°; the last two turn within a second or two and
// are fitted through every 3rd and 2nd pose (PresetTraits), to < 0.3 mm and < 0.21°. Exception: with a
// camera–IMU lever arm, quick_rotation's ±115° pans move the IMU with harmonics above 1.5 Hz, and the spline departs from the generated camera
// positions by up to ~5 mm (for a 4.7 cm arm); the spline remains the ground truth.

#include <string_view>
#include <vector>

#include "vifusion/sim/stamped_pose.hpp"

namespace vifusion::sim {

inline constexpr double kPresetFrameRateHz = 30.0;
/// The paper's "spline through every 10th pose" (TrajectoryFitOptions::subsample's default).
inline constexpr int kDefaultFitSubsample = 10;

/// How a preset is turned into a dataset besides its poses.
struct PresetTraits {
  /// The spline goes through every n-th pose (TrajectoryFitOptions::subsample). The presets are exact
  /// closed forms, so a denser fit only follows faster motion; the paper's 10 is for ICL-NUIM's jittery files.
  int fit_subsample = kDefaultFitSubsample;
  bool motion_blur = false;  ///< fast enough that the images get sub-frame motion blur
};

/// "fast", "quick_rotation", "white_wall", "long", "unmapped_turn", "fast_pan".
std::vector<std::string_view> presetNames();

/// @throws vifusion::Error naming the known presets if `name` is not one of them.
PresetTraits presetTraits(std::string_view name);

/// The preset's camera poses T_W_C at 30 Hz from t = 0 (stamps round(i·10⁹/30) ns).
/// @throws vifusion::Error naming the known presets if `name` is not one of them.
std::vector<StampedPose> presetCameraPoses(std::string_view name);

}  // namespace vifusion::sim
