#pragma once
// Procedural surface textures of the synthetic living room. Every albedo is a pure function of the
// material, a per-object variant and the point's in-plane surface coordinates (no image files, no
// state), so a surface point has the same colour from every view: brightness constancy holds exactly
// before noise, as the photometric tracker assumes.
//
// The textured materials carry structure at three scales because the tracker aligns a 3-level
// pyramid (640, 320, 160 px): coarse (stripes, panels, planks, tiles: 0.2–0.6 m), medium (checks,
// bricks, weave: 5–15 cm) and fine (grain, stipple, joints: 0.4–2 cm, a few pixels at 2 m and 640 px).
// Fine structure, hard edges and distant or grazing surfaces would alias under point sampling, so
// albedo() can return the texture averaged over a pixel's footprint (src/texture_filter.hpp), as a camera
// pixel integrates it.

#include <Eigen/Core>
#include <cstdint>

namespace vifusion::scene {

enum class Material : std::uint8_t {
  kWallStripes,  ///< wallpaper: broad vertical stripes, small checks, grain
  kWallPanels,   ///< wainscot panels below a chair rail, mottled plaster above
  kWallBricks,   ///< running-bond brick with mortar joints
  kWhiteWall,    ///< uniform white, no texture at all (the `white_wall` preset looks at it)
  kFloorPlanks,  ///< staggered wooden floor boards with grain
  kCeiling,      ///< off-white ceiling tiles with stipple
  kRug,          ///< diamond pattern, bands, wool noise
  kFabric,       ///< tartan upholstery; variant picks the colours
  kWood,         ///< grained wood; variant picks the tone
  kPaintedWood,  ///< painted panels with grooves; variant picks the paint
  kBook,         ///< book spine colour with bands; variant picks the colour
  kCanvas,       ///< a smooth abstract painting; variant picks the composition
  kMetal,        ///< brushed grey
  kLeaves,       ///< mottled green
  kLampShade,    ///< pleated linen
  kScreen,       ///< switched-off display, nearly uniform dark
};

/// Linear RGB albedo in [0, 1].
using Albedo = Eigen::Vector3f;

/// Albedo of `material` (object `variant`) at in-plane coordinates st_m [m]. For walls and floor, st
/// are world coordinates in the plane measured from the room's minimum corner, t upwards on walls; for
/// box faces, the two box-frame coordinates in the face measured from the box's minimum corner.
///
/// J_st_px is the footprint to average over: pixel offsets (a, b) ∈ [−½, ½]² [px] around the sample
/// reach st_m + J_st_px·(a, b) [m] (pixel_footprint.hpp). Zero, the default, is a point sample.
Albedo albedo(Material material, std::uint32_t variant, const Eigen::Vector2d& st_m,
              const Eigen::Matrix2d& J_st_px = Eigen::Matrix2d::Zero());

}  // namespace vifusion::scene
