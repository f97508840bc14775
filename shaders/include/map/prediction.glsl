// Surfel splatting shared by the prediction kernels (map_predict_splat.comp in its two passes and
// map_predict_attributes.comp). Mirrored by pipeline/map/src/prediction_cpu.cpp.
//
// Which surfels are rendered (PredictionParams.surfels): those whose centre lies in front of the
// camera within (min_depth_m, max_depth_m] and that are
//   kPredictActive (tracking's model): ACTIVE (updated within the time window δ_t) and STABLE
//     (confidence ≥ the threshold) — except while the map is young (frame < young_map_frames), when
//     every active surfel is rendered, because no surfel can have reached the threshold yet and
//     tracking needs a model;
//   kPredictInactive (local loop closure's "inactive model", ElasticFusion's): NOT active (last
//     updated more than δ_t frames ago) and STABLE. The young-map rule does not apply: a young map
//     has no inactive surfels worth closing a loop on, and unstable ones are never rendered here.
//   kPredictStable (localisation-only tracking's model): STABLE, whatever the age. Nothing is fused in
//     that mode, so no surfel is ever updated and "active" would empty the model within δ_t frames.
// and, whatever the set, CREATED before PredictionParams.created_before (0xffffffff: all): a loaded map's own
// surfels, shown by the inactive model for their reactivation while the camera maps in it (slam/slam.hpp).
//
// How: each surfel is a disk of radius r_eff = max(r, one pixel's footprint at its depth) — so
// that every rendered surfel covers at least its centre pixel. Its footprint is the pixel box
// [u ± r_eff·|fx|/z] × [v ± r_eff·|fy|/z], capped at max_half_footprint_px around the centre
// pixel; every pixel of the box whose ray meets the surfel plane inside the disk is covered, at
// the depth of that intersection.
//
// Which surfel wins a pixel: the nearest surfel whose CENTRE projects into it, else the nearest
// surfel whose disk covers it (splatKey). A plain nearest-disk test picks the minimum of the ~6
// noisy surfels overlapping each pixel and of their tilted planes, which biases the model towards
// the camera by about one depth-noise σ (measured: 27 mm median on ICL-NUIM-noise frames at 3 m)
// and drags tracking with it; the centre surfel is an unbiased sample. The disks only fill the
// pixels no centre falls into. Cost: at an occluding edge a background centre can win a pixel a
// foreground disk rim covers, shifting silhouettes by at most the footprint cap.
#ifndef VIFUSION_MAP_PREDICTION_GLSL
#define VIFUSION_MAP_PREDICTION_GLSL

#include "map/surfel.glsl"
#include "map/view.glsl"

struct PredictionParams {
  MapView view;
  float confidence_threshold;  // stable when confidence ≥ this
  uint time_window_frames;     // δ_t: active when updated within this many frames
  uint young_map_frames;       // before this frame every active surfel is rendered
  float min_depth_m;           // surfel centres nearer than this are not rendered [m]
  float max_depth_m;           // nor farther than this [m]
  int max_half_footprint_px;   // footprint cap: (2·cap + 1)² pixels
  uint surfels;                // which surfels: kPredictActive, kPredictInactive or kPredictStable
  uint created_before;         // and of those only surfels created before this frame (0xffffffff: all)
};

// PredictionParams.surfels (vifusion::map::PredictedSurfels).
const uint kPredictActive = 0u;
const uint kPredictInactive = 1u;
const uint kPredictStable = 2u;

// "No surfel" in the splat id image (surfel indices are < 2^26).
const uint kNoSurfel = 0xffffffffu;

bool isRendered(Surfel surfel, PredictionParams params) {
  // ("active" is a reserved word in GLSL.)
  const bool is_active = framesSince(params.view, surfel.colour_times.z) <= params.time_window_frames;
  const bool is_stable = surfel.position_confidence.w >= params.confidence_threshold;
  if (!(uint(surfel.colour_times.y) < params.created_before)) return false;
  if (params.surfels == kPredictInactive) return !is_active && is_stable;
  if (params.surfels == kPredictStable) return is_stable;
  return is_active && (is_stable || params.view.frame < params.young_map_frames);
}

// A surfel in camera coordinates, ready to splat.
struct CameraSurfel {
  vec3 p_C;          // centre [m]
  vec3 n_C;          // normal (as stored, not flipped)
  float radius2_m2;  // r_eff² [m²]
};

CameraSurfel toCamera(Surfel surfel, MapView view) {
  CameraSurfel s;
  s.p_C = transformPoint(view, surfel.position_confidence.xyz);
  s.n_C = rotateVector(view, surfel.normal_radius.xyz);
  precise float min_radius_m = s.p_C.z * max(abs(view.inv_fx), abs(view.inv_fy));
  precise float radius_m = max(surfel.normal_radius.w, min_radius_m);
  precise float radius2 = radius_m * radius_m;
  s.radius2_m2 = radius2;
  return s;
}

// The depth [m] a surfel was observed from, by inverting fusion's radius √2·z/f̄ (map/fusion_params.glsl's
// measurementRadius; f̄ of the view's level-0 camera, the one the map fuses with). Fusion enlarges the radius
// by up to 2× for slanted views, so this is the observation depth up to a factor 2 above it, never below.
float observationDepth(Surfel surfel, MapView view) {
  precise float mean_focal_px = (abs(view.fx) + abs(view.fy)) * 0.5;
  precise float depth_m = surfel.normal_radius.w * mean_focal_px * 0.70710678;  // · 1/√2
  return depth_m;
}

// Pixel box a surfel may cover, inclusive; empty when x0 > x1 or y0 > y1.
struct Footprint {
  int x0, x1, y0, y1;
  ivec2 centre;  // the pixel the centre projects into
};

Footprint footprintOf(CameraSurfel s, PredictionParams params) {
  Footprint f = Footprint(0, -1, 0, -1, ivec2(-1));
  const MapView view = params.view;
  const float cap = float(params.max_half_footprint_px);
  precise vec2 uv = projectPoint(view, s.p_C);
  // Centres farther than the cap outside the image cover nothing (and would overflow int).
  if (!(uv.x > -cap - 1.0 && uv.x < float(view.width) + cap && uv.y > -cap - 1.0 && uv.y < float(view.height) + cap)) {
    return f;
  }
  precise float inv_z = 1.0 / s.p_C.z;
  precise float radius_m = sqrt(s.radius2_m2);
  precise float half_x = radius_m * abs(view.fx) * inv_z;
  precise float half_y = radius_m * abs(view.fy) * inv_z;
  precise vec2 centre = floor(uv + 0.5);
  f.centre = ivec2(centre);
  f.x0 = int(max(max(ceil(uv.x - half_x), centre.x - cap), 0.0));
  f.x1 = int(min(min(floor(uv.x + half_x), centre.x + cap), float(view.width - 1)));
  f.y0 = int(max(max(ceil(uv.y - half_y), centre.y - cap), 0.0));
  f.y1 = int(min(min(floor(uv.y + half_y), centre.y + cap), float(view.height - 1)));
  return f;
}

// Where the ray through `pixel` meets the surfel plane: depth along the optical axis [m] and the
// camera-frame point. True when that point lies on the disk in front of the camera (a ray
// parallel to the plane gives inf/NaN, which fails the tests).
bool splatPixel(CameraSurfel s, ivec2 pixel, MapView view, out vec3 q_C) {
  precise float dx = (float(pixel.x) - view.cx) * view.inv_fx;
  precise float dy = (float(pixel.y) - view.cy) * view.inv_fy;
  precise float n_dot_d = (s.n_C.x * dx + s.n_C.y * dy) + s.n_C.z;
  precise float n_dot_p = (s.n_C.x * s.p_C.x + s.n_C.y * s.p_C.y) + s.n_C.z * s.p_C.z;
  precise float t = n_dot_p * (1.0 / n_dot_d);
  precise vec3 q = vec3(t * dx, t * dy, t);
  precise vec3 e = q - s.p_C;
  precise float e2 = (e.x * e.x + e.y * e.y) + e.z * e.z;
  q_C = q;
  return t > 0.0 && e2 <= s.radius2_m2;
}

// The z-buffer key of a covered pixel: centre pixels first (top bit clear), then by depth. The
// depth's float bits shifted right by one keep their order for positive floats and leave the top
// bit for the class; ties (now within 2 ulp) go to the lowest surfel index.
uint splatKey(Footprint f, ivec2 pixel, float depth_m) {
  const uint disk_only = all(equal(pixel, f.centre)) ? 0u : 0x80000000u;
  return disk_only | (floatBitsToUint(depth_m) >> 1);
}

#endif
