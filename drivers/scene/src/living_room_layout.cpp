// The furniture of the standard living room. All of it stands in the bands between the walls and
// the camera region (x < −0.3, z < −2.1, z > 1.8 m) or below y = 0.3 m (rug, coffee table), so it
// keeps kFurnitureClearance_m from every camera path. The east band (x > 2.5 m) stays empty so the
// white wall is seen unobstructed.

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "vifusion/scene/counter_rng.hpp"
#include "vifusion/scene/living_room.hpp"

namespace vifusion::scene {
namespace {

class Layout {
 public:
  /// Axis-aligned box from its corners [m].
  void add(std::string_view name, const Eigen::Vector3d& min_W, const Eigen::Vector3d& max_W, Material material,
           std::uint32_t variant = 0) {
    boxes_.push_back(BoxSpec{.name = name,
                             .center_W = 0.5 * (min_W + max_W),
                             .half_extent_m = 0.5 * (max_W - min_W),
                             .yaw_rad = 0.0,
                             .material = material,
                             .variant = variant});
  }

  /// Part of a yawed object: offset_B and the part's half extents in the object's frame [m].
  void addPart(std::string_view name, const Eigen::Vector3d& object_center_W, double yaw_rad,
               const Eigen::Vector3d& offset_B, const Eigen::Vector3d& half_extent_m, Material material,
               std::uint32_t variant = 0) {
    // R_y(yaw) as in Box: the object's x axis is (cos, 0, −sin) in the world.
    const double c = std::cos(yaw_rad);
    const double s = std::sin(yaw_rad);
    const Eigen::Vector3d offset_W(c * offset_B.x() + s * offset_B.z(), offset_B.y(),
                                   -s * offset_B.x() + c * offset_B.z());
    boxes_.push_back(BoxSpec{.name = name,
                             .center_W = object_center_W + offset_W,
                             .half_extent_m = half_extent_m,
                             .yaw_rad = yaw_rad,
                             .material = material,
                             .variant = variant});
  }

  std::vector<BoxSpec> take() { return std::move(boxes_); }

 private:
  std::vector<BoxSpec> boxes_;
};

using V = Eigen::Vector3d;

void addSofa(Layout& l) {
  // Against the west wall, facing +x; fabric variant 3 is a warm red.
  for (double z : {-1.25, 1.25}) {
    for (double x : {-1.52, -0.80})
      l.add("sofa_foot", V(x - 0.02, 0.0, z - 0.02), V(x + 0.02, 0.08, z + 0.02), Material::kMetal);
  }
  l.add("sofa_base", V(-1.55, 0.08, -1.1), V(-0.75, 0.40, 1.1), Material::kFabric, 3);
  l.add("sofa_cushion", V(-1.35, 0.40, -1.0), V(-0.78, 0.50, -0.01), Material::kFabric, 3);
  l.add("sofa_cushion", V(-1.35, 0.40, 0.01), V(-0.78, 0.50, 1.0), Material::kFabric, 3);
  l.add("sofa_back", V(-1.55, 0.40, -1.1), V(-1.35, 0.88, 1.1), Material::kFabric, 3);
  l.add("sofa_arm", V(-1.55, 0.08, -1.3), V(-0.75, 0.65, -1.1), Material::kFabric, 3);
  l.add("sofa_arm", V(-1.55, 0.08, 1.1), V(-0.75, 0.65, 1.3), Material::kFabric, 3);
  l.addPart("sofa_pillow", V(-1.25, 0.66, 0.7), 0.3, V::Zero(), V(0.06, 0.16, 0.18), Material::kFabric, 8);
}

void addCoffeeTable(Layout& l) {
  // Low enough (top at 0.26 m) to stand under the camera region, turned 0.25 rad on a rug.
  l.add("rug", V(0.0, 0.0, -1.1), V(1.9, 0.008, 0.9), Material::kRug);
  const V centre(0.95, 0.0, -0.1);
  constexpr double kYaw_rad = 0.25;
  l.addPart("table_top", centre, kYaw_rad, V(0.0, 0.24, 0.0), V(0.55, 0.02, 0.32), Material::kWood, 1);
  for (double x : {-0.48, 0.48}) {
    for (double z : {-0.26, 0.26}) {
      l.addPart("table_leg", centre, kYaw_rad, V(x, 0.11, z), V(0.03, 0.11, 0.03), Material::kWood, 1);
    }
  }
  l.addPart("table_book", centre, kYaw_rad + 0.4, V(0.1, 0.275, 0.05), V(0.12, 0.015, 0.09), Material::kBook, 41);
}

/// Books (and the odd ornament) on one shelf of the bookcase, from x_begin to x_end at height y_m.
void addShelfContents(Layout& l, int level, double y_m, double x_begin_m, double x_end_m) {
  constexpr double kBack_m = -3.17;
  int item = 0;
  for (double x = x_begin_m; x < x_end_m; ++item) {
    const auto u = [&](std::uint64_t salt) {
      return static_cast<double>(counterBits(0x5e1f, static_cast<std::uint64_t>(level * 64 + item), salt) >> 11) *
             0x1.0p-53;
    };
    if (u(0) < 0.08) {  // an ornament instead of a book
      const double width = 0.10 + 0.06 * u(1);
      if (x + width > x_end_m) break;
      l.add("ornament", V(x, y_m, kBack_m + 0.04), V(x + width, y_m + 0.10 + 0.12 * u(2), kBack_m + 0.04 + width),
            u(3) < 0.5 ? Material::kMetal : Material::kPaintedWood, 2);
      x += width + 0.03;
      continue;
    }
    const double width = 0.022 + 0.03 * u(1);
    if (x + width > x_end_m) break;
    l.add("book", V(x, y_m, kBack_m), V(x + width, y_m + 0.18 + 0.12 * u(2), kBack_m + 0.15 + 0.07 * u(3)),
          Material::kBook, static_cast<std::uint32_t>(level * 64 + item));
    x += width + (u(4) < 0.15 ? 0.06 : 0.002);
  }
}

void addBookshelf(Layout& l) {
  // Against the north wall, facing +z, x ∈ [−0.7, 0.5].
  l.add("shelf_side", V(-0.70, 0.0, -3.2), V(-0.68, 2.1, -2.85), Material::kWood, 2);
  l.add("shelf_side", V(0.48, 0.0, -3.2), V(0.50, 2.1, -2.85), Material::kWood, 2);
  l.add("shelf_back", V(-0.68, 0.0, -3.2), V(0.48, 2.1, -3.18), Material::kWood, 0);
  l.add("shelf_plinth", V(-0.68, 0.0, -3.18), V(0.48, 0.08, -2.85), Material::kWood, 2);
  const double kBoardTops_m[] = {0.5, 0.9, 1.3, 1.7, 2.1};
  for (double top : kBoardTops_m)
    l.add("shelf_board", V(-0.68, top - 0.02, -3.18), V(0.48, top, -2.85), Material::kWood, 2);
  const double kLevels_m[] = {0.08, 0.5, 0.9, 1.3, 1.7};
  for (int level = 0; level < 5; ++level) {
    // Partly filled shelves, alternating sides, so the back panel shows between the books.
    const bool left = level % 2 == 0;
    addShelfContents(l, level, kLevels_m[level], left ? -0.67 : -0.25, left ? 0.10 : 0.47);
  }
}

void addCabinetAndTv(Layout& l) {
  l.add("cabinet", V(1.0, 0.0, -3.2), V(2.2, 0.85, -2.75), Material::kPaintedWood, 1);
  l.add("cabinet_top", V(0.98, 0.85, -3.2), V(2.22, 0.88, -2.73), Material::kWood, 1);
  l.add("tv_stand", V(1.5, 0.88, -3.1), V(1.7, 0.98, -2.95), Material::kMetal);
  l.add("tv_bezel", V(1.13, 0.96, -3.08), V(2.07, 1.52, -3.005), Material::kMetal);
  l.add("tv_screen", V(1.15, 0.98, -3.005), V(2.05, 1.50, -3.0), Material::kScreen);
}

/// A picture: four frame bars around an inset canvas, on the wall whose inward normal is `normal_axis`
/// (0: west wall, +x; 2: north wall +z or south wall −z by `facing`). centre is on the wall plane.
void addPicture(Layout& l, const V& centre_W, int normal_axis, double facing, double width_m, double height_m,
                std::uint32_t variant) {
  constexpr double kBar_m = 0.05;
  constexpr double kFrameDepth_m = 0.035;
  constexpr double kCanvasDepth_m = 0.02;
  const int across = normal_axis == 0 ? 2 : 0;  // horizontal in-wall axis
  const auto corners = [&](double a0, double a1, double y0, double y1, double depth) {
    V lo;
    V hi;
    lo[across] = centre_W[across] + a0;
    hi[across] = centre_W[across] + a1;
    lo[1] = centre_W[1] + y0;
    hi[1] = centre_W[1] + y1;
    const double wall = centre_W[normal_axis];
    lo[normal_axis] = facing > 0.0 ? wall : wall - depth;
    hi[normal_axis] = facing > 0.0 ? wall + depth : wall;
    return std::pair{lo, hi};
  };
  const double w = 0.5 * width_m;
  const double h = 0.5 * height_m;
  const std::pair<V, V> bars[] = {corners(-w, w, h - kBar_m, h, kFrameDepth_m),
                                  corners(-w, w, -h, -h + kBar_m, kFrameDepth_m),
                                  corners(-w, -w + kBar_m, -h + kBar_m, h - kBar_m, kFrameDepth_m),
                                  corners(w - kBar_m, w, -h + kBar_m, h - kBar_m, kFrameDepth_m)};
  for (const auto& [lo, hi] : bars) l.add("frame_bar", lo, hi, Material::kWood, variant);
  const auto [lo, hi] = corners(-w + kBar_m, w - kBar_m, -h + kBar_m, h - kBar_m, kCanvasDepth_m);
  l.add("canvas", lo, hi, Material::kCanvas, variant);
}

void addDoor(Layout& l) {
  // In the south wall (z = 2.8), facing −z, hinged on the west side.
  l.add("door", V(-1.35, 0.0, 2.76), V(-0.45, 2.05, 2.79), Material::kPaintedWood, 0);
  l.add("door_casing", V(-1.43, 0.0, 2.775), V(-1.35, 2.13, 2.8), Material::kPaintedWood, 0);
  l.add("door_casing", V(-0.45, 0.0, 2.775), V(-0.37, 2.13, 2.8), Material::kPaintedWood, 0);
  l.add("door_casing", V(-1.35, 2.05, 2.775), V(-0.45, 2.13, 2.8), Material::kPaintedWood, 0);
  l.add("door_rose", V(-0.56, 0.98, 2.75), V(-0.50, 1.04, 2.76), Material::kMetal);
  l.add("door_handle_stem", V(-0.54, 1.0, 2.72), V(-0.52, 1.02, 2.75), Material::kMetal);
  l.add("door_handle", V(-0.68, 1.0, 2.70), V(-0.52, 1.02, 2.72), Material::kMetal);
}

void addArmchair(Layout& l) {
  // In the south band, turned 0.35 rad towards the room centre.
  const V centre(1.3, 0.0, 2.3);
  constexpr double kYaw_rad = 0.35;
  l.addPart("armchair_base", centre, kYaw_rad, V(0.0, 0.25, 0.0), V(0.38, 0.20, 0.34), Material::kFabric, 5);
  l.addPart("armchair_back", centre, kYaw_rad, V(0.0, 0.70, 0.26), V(0.38, 0.25, 0.08), Material::kFabric, 5);
  for (double x : {-0.33, 0.33}) {
    l.addPart("armchair_arm", centre, kYaw_rad, V(x, 0.59, 0.0), V(0.05, 0.14, 0.34), Material::kFabric, 5);
  }
  for (double x : {-0.34, 0.34}) {
    for (double z : {-0.30, 0.30}) {
      l.addPart("armchair_leg", centre, kYaw_rad, V(x, 0.025, z), V(0.02, 0.025, 0.02), Material::kWood, 1);
    }
  }
}

void addLampAndPlant(Layout& l) {
  // Floor lamp in the north-west corner: its 3 cm pole is the thin structure the dot-pattern filter eats.
  l.add("lamp_base", V(-1.45, 0.0, -3.0), V(-1.25, 0.03, -2.8), Material::kMetal);
  l.add("lamp_pole", V(-1.365, 0.03, -2.915), V(-1.335, 1.55, -2.885), Material::kMetal);
  l.add("lamp_shade", V(-1.55, 1.55, -3.1), V(-1.15, 1.85, -2.7), Material::kLampShade);
  // Plant beside the sofa.
  l.add("plant_pot", V(-1.5, 0.0, 1.55), V(-1.25, 0.35, 1.8), Material::kPaintedWood, 2);
  l.addPart("plant_leaves", V(-1.375, 0.0, 1.675), 0.5, V(0.0, 0.75, 0.0), V(0.2, 0.4, 0.12), Material::kLeaves);
  l.addPart("plant_leaves", V(-1.375, 0.0, 1.675), -0.6, V(0.0, 0.8, 0.0), V(0.18, 0.36, 0.1), Material::kLeaves);
}

}  // namespace

std::vector<BoxSpec> livingRoomFurniture() {
  Layout l;
  addSofa(l);
  addCoffeeTable(l);
  addBookshelf(l);
  addCabinetAndTv(l);
  addPicture(l, V(LivingRoom::kMinX_m, 1.55, 0.0), 0, +1.0, 1.0, 0.7, 11);  // over the sofa
  addPicture(l, V(2.9, 1.55, LivingRoom::kMinZ_m), 2, +1.0, 0.6, 0.8, 12);  // north wall, east of the TV
  addPicture(l, V(1.0, 1.5, LivingRoom::kMaxZ_m), 2, -1.0, 0.9, 0.6, 13);   // south wall, over the armchair
  addPicture(l, V(2.2, 1.6, LivingRoom::kMaxZ_m), 2, -1.0, 0.4, 0.5, 14);
  addDoor(l);
  addArmchair(l);
  addLampAndPlant(l);
  return l.take();
}

}  // namespace vifusion::scene
