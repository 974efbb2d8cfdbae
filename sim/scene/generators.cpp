#include "sim/scene/generators.hpp"

#include <algorithm>
#include <cassert>
#include <limits>
#include <string>
#include <utility>

namespace brisance::scene {

namespace {

std::uint64_t saturating_mul(std::uint64_t a, std::uint64_t b) {
  if (a != 0 && b > std::numeric_limits<std::uint64_t>::max() / a)
    return std::numeric_limits<std::uint64_t>::max();
  return a * b;
}

std::uint64_t saturating_add(std::uint64_t a, std::uint64_t b) {
  if (b > std::numeric_limits<std::uint64_t>::max() - a)
    return std::numeric_limits<std::uint64_t>::max();
  return a + b;
}

// A box-shaped object at `centre_local` in a frame placed at (origin, orientation) in the world.
ObjectSpec make_box_object(std::string name, const Vec3& size_m, const Vec3& centre_local,
                           const Vec3& origin, const Quat& orientation, double mass_kg,
                           double friction) {
  ObjectSpec object;
  object.name = std::move(name);
  object.shape = ShapeType::box;
  object.box_size_m = size_m;
  object.mesh = geometry::make_box(size_m);
  object.position = origin + orientation * centre_local;
  object.orientation = orientation;
  object.mass_kg = mass_kg;
  object.friction = friction;
  return object;
}

}  // namespace

std::uint64_t brick_wall_count(std::int64_t rows, std::int64_t columns) {
  if (rows < 1 || columns < 1) return 0;
  const auto r = static_cast<std::uint64_t>(rows);
  const auto c = static_cast<std::uint64_t>(columns);
  const std::uint64_t even_rows = (r + 1) / 2;  // rows 0, 2, ...: c full bricks
  const std::uint64_t odd_rows = r / 2;         // rows 1, 3, ...: c - 1 full + 2 half bricks
  return saturating_add(saturating_mul(even_rows, c), saturating_mul(odd_rows, c + 1));
}

std::array<double, 2> brick_wall_extent(const BrickWallParams& params) {
  const auto columns = static_cast<double>(params.columns);
  const auto rows = static_cast<double>(params.rows);
  const double gap = params.mortar_gap_m;
  return {columns * params.brick_size_m.x() + (columns - 1.0) * gap,
          rows * params.brick_size_m.y() + (rows - 1.0) * gap};
}

namespace {

// A rectangle in the wall's x-y plane: a brick or a part of one, m.
struct Rect {
  double left, right, bottom, top;
};

// The parts of `piece` outside every opening from `first` on: below and above an opening it keeps
// its full length, beside it the opening's height. Parts under the minimum size are dropped.
void cut_around(const Rect& piece, const std::vector<WallOpening>& openings, std::size_t first,
                double min_length, double min_height, std::vector<Rect>& parts) {
  for (std::size_t k = first; k < openings.size(); ++k) {
    const WallOpening& opening = openings[k];
    const Rect hole{opening.centre_m[0] - 0.5 * opening.size_m[0],
                    opening.centre_m[0] + 0.5 * opening.size_m[0],
                    opening.centre_m[1] - 0.5 * opening.size_m[1],
                    opening.centre_m[1] + 0.5 * opening.size_m[1]};
    // Overlaps of a nanometre are rounding (a hole on a course's edge), not a cut.
    constexpr double kTouch_m = 1e-9;
    if (hole.left >= piece.right - kTouch_m || hole.right <= piece.left + kTouch_m ||
        hole.bottom >= piece.top - kTouch_m || hole.top <= piece.bottom + kTouch_m)
      continue;
    // Below and above across the piece's length, so courses run on over and under a hole;
    // beside it only in the hole's height.
    const double inner_bottom = std::max(piece.bottom, hole.bottom);
    const double inner_top = std::min(piece.top, hole.top);
    const Rect candidates[] = {
        {piece.left, piece.right, piece.bottom, inner_bottom},                      // below
        {piece.left, std::max(piece.left, hole.left), inner_bottom, inner_top},     // left
        {std::min(piece.right, hole.right), piece.right, inner_bottom, inner_top},  // right
        {piece.left, piece.right, inner_top, piece.top},                            // above
    };
    for (const Rect& candidate : candidates) {
      if (candidate.right - candidate.left < min_length ||
          candidate.top - candidate.bottom < min_height)
        continue;
      cut_around(candidate, openings, k + 1, min_length, min_height, parts);
    }
    return;
  }
  parts.push_back(piece);
}

}  // namespace

std::vector<ObjectSpec> brick_wall(const BrickWallParams& params) {
  assert(params.rows >= 1 && params.columns >= 1);
  const double length = params.brick_size_m.x();
  const double height = params.brick_size_m.y();
  const double depth = params.brick_size_m.z();
  const double gap = params.mortar_gap_m;
  const double width = brick_wall_extent(params)[0];
  // An odd row has one piece and one joint more than an even row; equal widths need half bricks
  // of (length - gap) / 2, which puts every odd-row joint over the middle of a brick below.
  const double half_length = 0.5 * (length - gap);
  const double full_area = length * height;
  const double min_length = kMinBrickPartFraction * length;
  const double min_height = kMinBrickPartFraction * height;

  std::vector<ObjectSpec> bricks;
  bricks.reserve(brick_wall_count(params.rows, params.columns));
  std::vector<Rect> parts;
  for (std::int64_t row = 0; row < params.rows; ++row) {
    const double bottom = static_cast<double>(row) * (height + gap);
    const bool odd = row % 2 == 1;
    const std::int64_t pieces = odd ? params.columns + 1 : params.columns;
    double left = -0.5 * width;  // left end of the next piece, wall frame
    std::int64_t number = 0;     // of the next brick or part in the row
    for (std::int64_t index = 0; index < pieces; ++index) {
      const bool half = odd && (index == 0 || index == pieces - 1);
      const double piece_length = half ? half_length : length;
      const double piece_mass = half ? 0.5 * params.brick_mass_kg : params.brick_mass_kg;
      parts.clear();
      cut_around(Rect{left, left + piece_length, bottom, bottom + height}, params.openings, 0,
                 min_length, min_height, parts);
      const bool whole = parts.size() == 1 && parts[0].left == left &&
                         parts[0].right == left + piece_length && parts[0].top == bottom + height &&
                         parts[0].bottom == bottom;
      for (const Rect& part : parts) {
        // An uncut brick keeps the arithmetic of a wall without openings, bit for bit.
        const Vec3 size = whole ? Vec3(piece_length, height, depth)
                                : Vec3(part.right - part.left, part.top - part.bottom, depth);
        const Vec3 centre =
            whole ? Vec3(left + 0.5 * piece_length, bottom + 0.5 * height, 0.0)
                  : Vec3(0.5 * (part.left + part.right), 0.5 * (part.bottom + part.top), 0.0);
        // A cut part has its share of the brick's mass, by area.
        const double mass =
            whole ? piece_mass : params.brick_mass_kg * (size.x() * size.y()) / full_area;
        ObjectSpec brick = make_box_object(
            params.name + "/r" + std::to_string(row) + "/b" + std::to_string(number++), size,
            centre, params.position, params.orientation, mass, params.friction);
        brick.material = "brick";
        bricks.push_back(std::move(brick));
      }
      left += piece_length + gap;
    }
  }
  for (std::size_t k = 0; k < params.openings.size(); ++k) {
    const WallOpening& opening = params.openings[k];
    if (!opening.window) continue;
    WindowParams window_params = *opening.window;
    window_params.name = params.name + "/opening" + std::to_string(k);
    const Vec3 centre(opening.centre_m[0], opening.centre_m[1], 0.0);
    window_params.position = params.position + params.orientation * centre;
    window_params.orientation = params.orientation;
    // The frame lies outside the pane: its outer edges meet the opening's.
    const double frame = window_params.frame ? window_params.frame_width_m : 0.0;
    window_params.width_m = opening.size_m[0] - 2.0 * frame;
    window_params.height_m = opening.size_m[1] - 2.0 * frame;
    for (ObjectSpec& object : window(window_params))
      bricks.push_back(std::move(object));
  }
  return bricks;
}

std::uint64_t blocks_count(const std::array<std::int64_t, 3>& counts) {
  std::uint64_t total = 1;
  for (std::int64_t n : counts) {
    if (n < 1) return 0;
    total = saturating_mul(total, static_cast<std::uint64_t>(n));
  }
  return total;
}

std::vector<ObjectSpec> blocks(const BlocksParams& params) {
  assert(params.counts[0] >= 1 && params.counts[1] >= 1 && params.counts[2] >= 1);
  // Centre of box 0 along each axis: x and z centred on the origin, y standing on it.
  Vec3 first;
  Vec3 pitch;
  for (int axis = 0; axis < 3; ++axis) {
    const auto n = static_cast<double>(params.counts[static_cast<std::size_t>(axis)]);
    const double extent = n * params.size_m[axis] + (n - 1.0) * params.spacing_m[axis];
    pitch[axis] = params.size_m[axis] + params.spacing_m[axis];
    first[axis] = (axis == 1 ? 0.0 : -0.5 * extent) + 0.5 * params.size_m[axis];
  }
  std::vector<ObjectSpec> boxes;
  boxes.reserve(blocks_count(params.counts));
  for (std::int64_t j = 0; j < params.counts[1]; ++j) {
    for (std::int64_t k = 0; k < params.counts[2]; ++k) {
      for (std::int64_t i = 0; i < params.counts[0]; ++i) {
        const Vec3 centre =
            first + Vec3(static_cast<double>(i) * pitch.x(), static_cast<double>(j) * pitch.y(),
                         static_cast<double>(k) * pitch.z());
        boxes.push_back(make_box_object(params.name + "/x" + std::to_string(i) + "/y" +
                                            std::to_string(j) + "/z" + std::to_string(k),
                                        params.size_m, centre, params.position, params.orientation,
                                        params.mass_kg, params.friction));
      }
    }
  }
  return boxes;
}

std::vector<ObjectSpec> window(const WindowParams& params) {
  assert(params.width_m > 0.0 && params.height_m > 0.0 && params.thickness_m > 0.0);
  std::vector<ObjectSpec> objects;
  const Vec3 pane_size(params.width_m, params.height_m, params.thickness_m);
  ObjectSpec pane =
      make_box_object(params.name + "/pane", pane_size, Vec3::Zero(), params.position,
                      params.orientation, params.density_kg_m3 * pane_size.prod(), params.friction);
  pane.material = params.material;
  pane.fracture = params.fracture;
  pane.fracture->framed = params.frame;
  if (params.sheltered_back) pane.sheltered = kShelteredBack;
  objects.push_back(std::move(pane));
  if (!params.frame) return objects;
  // Bottom and top bars run the full outer width; the sides fill the height between them.
  const double w = params.width_m;
  const double h = params.height_m;
  const double f = params.frame_width_m;
  const double d = params.frame_depth_m;
  const Vec3 horizontal(w + 2.0 * f, f, d);
  const Vec3 vertical(f, h, d);
  const struct {
    const char* name;
    Vec3 size;
    Vec3 centre;
  } bars[] = {
      {"bottom", horizontal, Vec3(0.0, -0.5 * (h + f), 0.0)},
      {"top", horizontal, Vec3(0.0, 0.5 * (h + f), 0.0)},
      {"left", vertical, Vec3(-0.5 * (w + f), 0.0, 0.0)},
      {"right", vertical, Vec3(0.5 * (w + f), 0.0, 0.0)},
  };
  for (const auto& bar : bars) {
    ObjectSpec object =
        make_box_object(params.name + "/frame/" + bar.name, bar.size, bar.centre, params.position,
                        params.orientation, params.frame_density_kg_m3 * bar.size.prod(), 0.4);
    object.anchored = true;
    object.material = "wood";
    objects.push_back(std::move(object));
  }
  return objects;
}

}  // namespace brisance::scene
