// What the shielding heuristic (sim/occlusion, thesis chapter 4) predicts behind a rigid wall: the
// load scale f(b, k) of eq. 4.1 on small gauges standing on the ground 0.5 to 8 wall heights
// behind a long wall, for charges at 1, 2 and 4 wall heights in front of it. This is the
// prediction side of issue 12's comparison with blast-wall measurements (docs/occlusion.md says
// which measurements were reachable and what they say). No constant is tuned here.
//
//   wall_shielding_study [--face-columns N]
//
// Prints one row per gauge distance: f for each stand-off, per-panel (the gauge's face towards
// the wall) and per-object (the thesis's mode). Brisance scales pressure and impulse alike, so
// the predicted reduction of both is 1 - f.
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "sim/geometry/mesh.hpp"
#include "sim/occlusion/shielding.hpp"

namespace {

namespace occlusion = brisance::occlusion;
namespace geometry = brisance::geometry;
using occlusion::Vec3;

constexpr double kWallHeight_m = 2.0;
constexpr double kWallThickness_m = 0.3;
constexpr double kWallLength_m = 40.0;  // 20 heights: long enough to act as an infinite wall
constexpr double kGauge_m = 0.2;        // a small cube standing on the ground
constexpr double kChargeHeight_m = 0.5;

struct Row {
  double per_panel;
  double per_object;
};

// f on a gauge `behind_h` wall heights behind the wall's rear face, charge `standoff_h` wall
// heights in front of its front face.
Row shielding_behind(const occlusion::SphereMap& map, const occlusion::Settings& base,
                     double standoff_h, double behind_h) {
  geometry::TriangleMesh wall =
      geometry::make_box(Vec3(kWallLength_m, kWallHeight_m, kWallThickness_m));
  for (Vec3& v : wall.vertices)
    v += Vec3(0.0, kWallHeight_m / 2, kWallThickness_m / 2);
  const double gauge_z = kWallThickness_m + behind_h * kWallHeight_m + kGauge_m / 2;
  geometry::TriangleMesh gauge = geometry::make_box(Vec3(kGauge_m, kGauge_m, kGauge_m));
  for (Vec3& v : gauge.vertices)
    v += Vec3(0.0, kGauge_m / 2, gauge_z);
  const occlusion::Object objects[] = {{wall.vertices, wall.triangles, true, false},
                                       {gauge.vertices, gauge.triangles, false, true}};
  // The gauge's face towards the charge (its -z face).
  const occlusion::Panel panels[] = {
      {1, Vec3(0.0, kGauge_m / 2, gauge_z - kGauge_m / 2), kGauge_m * kGauge_m}};
  const Vec3 charge(0.0, kChargeHeight_m, -standoff_h * kWallHeight_m);
  Row row{};
  occlusion::Settings settings = base;
  settings.per_panel = true;
  row.per_panel =
      occlusion::compute_shielding(map, charge, objects, panels, settings).panel_attenuation[0];
  settings.per_panel = false;
  row.per_object =
      occlusion::compute_shielding(map, charge, objects, panels, settings).objects[1].attenuation;
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  occlusion::Settings settings;
  for (int i = 1; i < argc; ++i) {
    if (std::strcmp(argv[i], "--face-columns") == 0 && i + 1 < argc) {
      settings.face_columns = std::atoi(argv[++i]);
      settings.face_rows = settings.face_columns * 7 / 8;
    } else {
      std::fprintf(stderr, "usage: wall_shielding_study [--face-columns N]\n");
      return 2;
    }
  }
  if (settings.face_columns < 4 || settings.face_columns > 256) {
    std::fprintf(stderr, "--face-columns must be 4 to 256\n");
    return 2;
  }
  const occlusion::SphereMap map(settings.face_columns, settings.face_rows);
  const double standoffs[] = {1.0, 2.0, 4.0};
  std::printf("# wall %.1f m high, %.1f m thick, %.0f m long; charge %.1f m above the ground;\n",
              kWallHeight_m, kWallThickness_m, kWallLength_m, kChargeHeight_m);
  std::printf(
      "# gauges: %.1f m cubes on the ground; %d x %d pixels a face; eq. 4.1 constants "
      "%.0f, %.0f\n",
      kGauge_m, settings.face_columns, settings.face_rows, settings.blocking_offset,
      settings.separation_slope);
  std::printf("# f = load scale (pressure and impulse alike); reduction = 1 - f\n");
  std::printf("%-10s", "behind/H");
  for (double s : standoffs)
    std::printf("  f(front %.0fH) panel  object", s);
  std::printf("\n");
  for (const double behind : {0.5, 1.0, 1.5, 2.0, 3.0, 4.0, 5.0, 6.0, 8.0}) {
    std::printf("%-10.1f", behind);
    for (const double s : standoffs) {
      const Row row = shielding_behind(map, settings, s, behind);
      std::printf("  %19.3f  %6.3f", row.per_panel, row.per_object);
    }
    std::printf("\n");
  }
  return 0;
}
