// sim/scene/generators (private to sim/scene): expand the scene's `generators[]` entries into
// plain objects. The parameters arrive here already validated by parse_generators.cpp; the
// generators only do geometry. Every generated object is a box.
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "sim/scene/scene.hpp"

namespace brisance::scene {

// A window: one breakable glass pane (thesis ch. 6), optionally in an anchored frame. In the
// window's own frame the pane is centred on the origin, spans x (width) and y (height) and is
// `thickness_m` deep along z, its front face +z; `orientation` turns it about its centre.
// The frame, if any, is four anchored boxes of `frame_width_m` around the pane's edges, as deep
// as `frame_depth_m`, named "<name>/frame/{bottom,top,left,right}"; the pane is "<name>/pane".
struct WindowParams {
  std::string name;
  Vec3 position = Vec3::Zero();  // world position of the pane's centre, m
  Quat orientation = Quat::Identity();
  double width_m = 1.2;
  double height_m = 0.9;
  double thickness_m = 0.006;
  std::string material = "annealed_glass";
  double density_kg_m3 = 2500.0;
  double friction = 0.9;
  bool frame = true;
  // A room behind the pane: its back (−z of the window's frame) is loaded only by a wave that
  // strikes it, never by one wrapping around (the pane's ObjectSpec::sheltered).
  bool sheltered_back = true;
  double frame_width_m = 0.05;
  double frame_depth_m = 0.07;
  double frame_density_kg_m3 = 500.0;  // wood
  FractureSpec fracture;               // its `framed` follows `frame`
};

// A rectangular opening in a brick wall, in the wall's own frame (see BrickWallParams): its
// centre `centre_m` = [x along the wall from the wall's centre line, y up from the wall's base]
// and its full `size_m` = [width, height]. An opening with a window holds it with the frame's
// outer edges on the opening's edges: the pane is the opening less the frame on every side.
struct WallOpening {
  std::array<double, 2> centre_m = {0.0, 1.0};
  std::array<double, 2> size_m = {1.0, 1.0};
  // The window in the opening; its name, position, orientation and pane size come from the wall
  // and the opening. Absent: an empty hole.
  std::optional<WindowParams> window;
};

// A running-bond brick wall (thesis §3.6, fig. 3.4). In the wall's own frame the wall runs along
// +x, rises along +y and is `brick_size_m.z()` deep along z; the frame's origin is the centre of
// the wall's base, and `orientation` turns the wall about it. Even rows (0, 2, ...) hold `columns`
// full bricks; odd rows are shifted by half a brick: a half brick at each end and columns - 1 full
// bricks between, so every row spans the same width and each vertical joint of an odd row sits
// over the middle of a brick below.
struct BrickWallParams {
  std::string name;              // prefix of the object names "<name>/r<row>/b<index>"
  Vec3 position = Vec3::Zero();  // world position of the centre of the wall's base, m
  Quat orientation = Quat::Identity();
  std::int64_t rows = 1;                     // >= 1
  std::int64_t columns = 1;                  // full bricks per even row, >= 1
  Vec3 brick_size_m = Vec3(0.4, 0.15, 0.1);  // full brick [length, height, depth], m
  double brick_mass_kg = 10.0;               // full brick; a half brick has half
  double friction = 0.6;
  double mortar_gap_m = 0.0;  // empty joint between neighbouring bricks, m
  // Holes through the wall, inside its outline and not overlapping one another (checked by the
  // parser). Every brick is cut around each opening: the parts of it below and above the opening
  // (its whole length) and beside it (the opening's height) remain as boxes of the same depth and
  // proportional mass; a part shorter than a quarter of a brick's length or lower than a quarter
  // of its height is dropped (no slivers).
  std::vector<WallOpening> openings;
};

// The smallest part of a brick cut around an opening that is kept, as a fraction of the full
// brick's length (along the wall) and height.
inline constexpr double kMinBrickPartFraction = 0.25;

// The wall's outline in its own frame: width along x (centred on 0) and height along y (from 0).
std::array<double, 2> brick_wall_extent(const BrickWallParams& params);

// Bricks (full and half) a wall of this many rows and columns has, saturating at UINT64_MAX, so
// a caller can check limits before generating anything.
std::uint64_t brick_wall_count(std::int64_t rows, std::int64_t columns);

// The wall's bricks, row by row from the bottom, left (-x) to right within a row. Each brick is an
// ObjectSpec with a box mesh, material "brick" and the given friction. With openings, a row's
// bricks and the parts of cut bricks are numbered brick by brick from the left, a cut brick's
// parts bottom, left, right, top; the bricks are followed by the windows of the openings, in
// opening order, named
// "<name>/opening<k>" (the window's own objects "<name>/opening<k>/pane" and
// "<name>/opening<k>/frame/..."), centred in the opening in the wall's mid-plane (z = 0), turned
// with the wall, their front face the wall's +z.
std::vector<ObjectSpec> brick_wall(const BrickWallParams& params);

// A regular grid of equal boxes. In the grid's own frame the boxes are centred on x and z and
// stand on y = 0; the frame's origin is the centre of the grid's base.
struct BlocksParams {
  std::string name;              // prefix of the object names "<name>/x<i>/y<j>/z<k>"
  Vec3 position = Vec3::Zero();  // world position of the centre of the grid's base, m
  Quat orientation = Quat::Identity();
  std::array<std::int64_t, 3> counts = {1, 1, 1};  // boxes along x, y, z, each >= 1
  Vec3 size_m = Vec3::Ones();                      // full edge lengths of one box, m
  Vec3 spacing_m = Vec3::Zero();  // gap between neighbouring boxes along each axis, m
  double mass_kg = 1.0;           // of one box
  double friction = 0.5;
};

// Boxes in the grid, saturating at UINT64_MAX.
std::uint64_t blocks_count(const std::array<std::int64_t, 3>& counts);

// The grid's boxes, x fastest, then z, then y (bottom layer first).
std::vector<ObjectSpec> blocks(const BlocksParams& params);

// The window's objects: the pane first, then the frame's four bars.
std::vector<ObjectSpec> window(const WindowParams& params);

}  // namespace brisance::scene
