// sim/scene/parse_generators: the scene's `generators[]` entries. Each type has one function that
// reads its parameters, checks the objects it would make against max_objects before making any,
// and hands the parameters to its generator (generators.hpp), which only does geometry.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <utility>

#include "sim/scene/generators.hpp"
#include "sim/scene/sections.hpp"

namespace brisance::scene {

namespace {

enum class GeneratorType { brick_wall, blocks, window };

constexpr std::array<Choice<GeneratorType>, 3> kGeneratorTypes = {{
    {"brick_wall", GeneratorType::brick_wall},
    {"blocks", GeneratorType::blocks},
    {"window", GeneratorType::window},
}};

// Rows, columns and counts stay within int32 so the object counts cannot overflow.
constexpr std::int64_t kMaxCount = std::numeric_limits<std::int32_t>::max();

// One generator entry and where it stands in the scene.
struct GeneratorContext {
  const json& value;
  const std::string& pointer;
  std::size_t objects_before;  // objects already in the scene
  const Limits& limits;
  Errors& errors;

  // Whether `count` more objects fit under max_objects; reports it if not.
  bool room_for(std::uint64_t count) const {
    const std::uint64_t room =
        limits.max_objects > objects_before ? limits.max_objects - objects_before : 0;
    if (count <= room) return true;
    errors.add(pointer, "this generator would make " + std::to_string(count) + " objects and " +
                            std::to_string(objects_before) +
                            " come before it, more than the limit max_objects = " +
                            std::to_string(limits.max_objects) + "; make it smaller");
    return false;
  }
};

// The pane must be at least as wide and as high as it is thick.
void check_pane_thickness(const Fields& fields, const WindowParams& window_params) {
  if (window_params.thickness_m > std::min(window_params.width_m, window_params.height_m)) {
    fields.errors().add(fields.at("thickness"),
                        "'thickness' must not exceed the pane's width and height; make it thinner");
  }
}

// The fields a window shares with a window in a wall's opening: everything but its name, place
// and size. `pane_known`: the pane's size is already in `window_params`, so its thickness is
// checked against it here; otherwise the caller checks it once the size is known.
void read_window_fields(const Fields& fields, bool pane_known, WindowParams& window_params) {
  Errors& errors = fields.errors();
  window_params.thickness_m = fields.number("thickness", window_params.thickness_m,
                                            range(kMinPaneThickness_m, false, 0.1, false, "m"));
  if (pane_known) check_pane_thickness(fields, window_params);
  std::optional<Material> material = find_material(window_params.material);
  if (const json* name = fields.get("material")) {
    const std::string at = fields.at("material");
    std::optional<Material> found;
    if (name->is_string()) found = find_material(name->get_ref<const std::string&>());
    if (found && found->strength_pa > 0.0) {
      material = found;
    } else {
      errors.add(at, "a window's 'material' must be a breakable material (" +
                         breakable_material_names() + "); got " + describe(*name));
    }
  }
  if (material) {
    window_params.material = std::string(material->name);
    window_params.density_kg_m3 = material->density_kg_m3;
    window_params.friction = material->friction;
  }
  window_params.frame = fields.boolean("frame", true);
  window_params.sheltered_back = fields.boolean("sheltered_back", true);
  window_params.frame_width_m =
      fields.number("frame_width", window_params.frame_width_m, positive("m"));
  window_params.frame_depth_m =
      fields.number("frame_depth", window_params.frame_depth_m, positive("m"));
  if (window_params.frame_depth_m < window_params.thickness_m) {
    errors.add(fields.at("frame_depth"), "'frame_depth' must be at least the pane's thickness " +
                                             format_number(window_params.thickness_m) +
                                             " m; make the frame deeper");
  }
  if (const json* fracture = fields.get("fracture")) {
    if (auto spec = parse_fracture(*fracture, fields.at("fracture"), material, false, errors))
      window_params.fracture = *spec;
  } else if (material) {
    window_params.fracture.youngs_modulus_pa = material->youngs_modulus_pa;
    window_params.fracture.fracture_toughness_pa_sqrt_m = material->fracture_toughness_pa_sqrt_m;
    window_params.fracture.strength_pa = material->strength_pa;
    window_params.fracture.surface_compression_pa = material->surface_compression_pa;
  }
}

// One entry of a brick wall's `openings`: {"position": [x, y] (the opening's centre in the wall's
// frame), "size": [width, height], "window": {...}}, inside the wall's outline.
std::optional<WallOpening> read_opening(const json& value, const std::string& pointer,
                                        const BrickWallParams& wall, Errors& errors) {
  if (!expect_object(value, pointer, "an opening {position, size, window}", errors)) return {};
  const ErrorScope scope(errors);
  const Fields fields(value, pointer, errors, "an opening", {"position", "size", "window"});
  WallOpening opening;
  const auto read_pair = [&](std::string_view key, std::string_view what, const Bound& bound,
                             std::array<double, 2>& out) {
    const json* pair = fields.require(key, what);
    if (!pair) return;
    const std::string at = fields.at(key);
    if (!pair->is_array() || pair->size() != 2) {
      errors.add(at, "'" + std::string(key) + "' must be " + std::string(what) + "; got " +
                         describe(*pair));
      return;
    }
    for (std::size_t i = 0; i < 2; ++i) {
      if (auto number =
              read_number((*pair)[i], child(at, i),
                          std::string(key) + "[" + std::to_string(i) + "]", bound, errors))
        out[i] = *number;
    }
  };
  read_pair("position", "an array [x, y] of the opening's centre in the wall's frame, m",
            any_number("m"), opening.centre_m);
  read_pair("size", "an array [width, height] of the opening, m, each > 0", positive("m"),
            opening.size_m);
  if (!scope.ok()) return {};
  const auto [wall_width, wall_height] = brick_wall_extent(wall);
  const double left = opening.centre_m[0] - 0.5 * opening.size_m[0];
  const double right = opening.centre_m[0] + 0.5 * opening.size_m[0];
  const double bottom = opening.centre_m[1] - 0.5 * opening.size_m[1];
  const double top = opening.centre_m[1] + 0.5 * opening.size_m[1];
  // A micrometre of slack: an opening flush with the wall's edge is inside.
  constexpr double kSlack_m = 1e-6;
  if (left < -0.5 * wall_width - kSlack_m || right > 0.5 * wall_width + kSlack_m ||
      bottom < -kSlack_m || top > wall_height + kSlack_m) {
    errors.add(fields.at("position"),
               "the opening spans x " + format_number(left) + " to " + format_number(right) +
                   " m and y " + format_number(bottom) + " to " + format_number(top) +
                   " m, outside the wall (x " + format_number(-0.5 * wall_width) + " to " +
                   format_number(0.5 * wall_width) + " m, y 0 to " + format_number(wall_height) +
                   " m, centre of its base at [0, 0]); move it or make it smaller");
    return {};
  }
  if (const json* window_value = fields.get("window")) {
    const std::string at = fields.at("window");
    if (!expect_object(*window_value, at, "a window {thickness, material, frame, ...}", errors))
      return {};
    // The window generator's fields but those the opening decides: name, place and size.
    const Fields window_fields(*window_value, at, errors, "a window in an opening",
                               {"thickness", "material", "frame", "frame_width", "frame_depth",
                                "sheltered_back", "fracture"});
    WindowParams window_params;
    read_window_fields(window_fields, false, window_params);
    if (!scope.ok()) return {};
    const double frame = window_params.frame ? window_params.frame_width_m : 0.0;
    window_params.width_m = opening.size_m[0] - 2.0 * frame;
    window_params.height_m = opening.size_m[1] - 2.0 * frame;
    if (window_params.width_m <= 0.0 || window_params.height_m <= 0.0) {
      errors.add(window_fields.at("frame_width"),
                 "the frame (" + format_number(frame) + " m on each side, inside the opening) " +
                     "leaves no room for the pane in an opening of " +
                     format_number(opening.size_m[0]) + " x " + format_number(opening.size_m[1]) +
                     " m; make 'frame_width' smaller or the opening larger");
      return {};
    }
    if (window_params.width_m > kMaxPaneSide_m || window_params.height_m > kMaxPaneSide_m) {
      errors.add(child(pointer, "size"),
                 "the window's pane (the opening less its frame) must be "
                 "at most " +
                     format_number(kMaxPaneSide_m) + " m wide and high; make the opening smaller");
      return {};
    }
    check_pane_thickness(window_fields, window_params);
    if (!scope.ok()) return {};
    opening.window = std::move(window_params);
  }
  return opening;
}

// Openings may touch but not overlap: reported at the later one of each overlapping pair.
void check_openings_apart(const std::vector<WallOpening>& openings, const std::string& pointer,
                          Errors& errors) {
  for (std::size_t k = 0; k < openings.size(); ++k) {
    for (std::size_t j = 0; j < k; ++j) {
      const WallOpening& a = openings[j];
      const WallOpening& b = openings[k];
      const double dx = 0.5 * (a.size_m[0] + b.size_m[0]) - std::abs(a.centre_m[0] - b.centre_m[0]);
      const double dy = 0.5 * (a.size_m[1] + b.size_m[1]) - std::abs(a.centre_m[1] - b.centre_m[1]);
      if (dx > 1e-6 && dy > 1e-6) {
        errors.add(child(pointer, k), "this opening overlaps opening " + std::to_string(j) +
                                          "; move it or make one smaller (openings may touch)");
        break;
      }
    }
  }
}

// {"type": "brick_wall"}: a running-bond wall of bricks and half bricks.
std::vector<ObjectSpec> parse_brick_wall(const GeneratorContext& context) {
  const json& value = context.value;
  const std::string& pointer = context.pointer;
  Errors& errors = context.errors;
  const ErrorScope scope(errors);
  const Fields fields(value, pointer, errors, "a brick_wall generator",
                      {"type", "name", "position", "orientation", "rows", "columns", "brick_size",
                       "brick_mass", "friction", "mortar_gap", "openings"});
  BrickWallParams wall;
  if (auto name = fields.required_name("name")) wall.name = *name;
  wall.position = fields.vec3("position", Vec3::Zero(), any_number("m"));
  wall.orientation = fields.orientation("orientation");
  if (auto rows = fields.required_integer("rows", 1, kMaxCount)) wall.rows = *rows;
  if (auto columns = fields.required_integer("columns", 1, kMaxCount)) wall.columns = *columns;
  const auto size = fields.required_vec3("brick_size", positive("m"));
  if (size) wall.brick_size_m = *size;
  if (auto mass = fields.required_number("brick_mass", positive("kg"))) wall.brick_mass_kg = *mass;
  wall.friction = fields.number("friction", 0.6, non_negative());
  wall.mortar_gap_m = fields.number("mortar_gap", 0.0, non_negative("m"));
  if (size && wall.mortar_gap_m >= size->x()) {
    errors.add(fields.at("mortar_gap"),
               "'mortar_gap' must be smaller than the brick length brick_size[0] = " +
                   format_number(size->x()) + " m, or the half bricks have no length");
  }
  if (const json* openings = fields.get("openings")) {
    const std::string at = fields.at("openings");
    if (expect_array(*openings, at, "'openings' (of {position, size, window})", errors) &&
        scope.ok()) {
      for (std::size_t k = 0; k < openings->size(); ++k) {
        if (auto opening = read_opening((*openings)[k], child(at, k), wall, errors))
          wall.openings.push_back(std::move(*opening));
      }
      // Pointers name openings by their index: only a complete list is checked pairwise.
      if (scope.ok()) check_openings_apart(wall.openings, at, errors);
    }
  }
  std::uint64_t windows = 0;
  for (const WallOpening& opening : wall.openings)
    if (opening.window) windows += opening.window->frame ? 5 : 1;
  // Cutting round the openings makes at most a few parts more than the uncut wall has bricks.
  if (!scope.ok() || !context.room_for(brick_wall_count(wall.rows, wall.columns) + windows))
    return {};
  std::vector<ObjectSpec> objects = brick_wall(wall);
  if (!context.room_for(objects.size())) return {};
  return objects;
}

// {"type": "blocks"}: a grid of equal boxes.
std::vector<ObjectSpec> parse_blocks(const GeneratorContext& context) {
  const json& value = context.value;
  const std::string& pointer = context.pointer;
  Errors& errors = context.errors;
  const ErrorScope scope(errors);
  const Fields fields(value, pointer, errors, "a blocks generator",
                      {"type", "name", "position", "orientation", "counts", "size", "spacing",
                       "mass", "density", "friction"});
  BlocksParams grid;
  if (auto name = fields.required_name("name")) grid.name = *name;
  grid.position = fields.vec3("position", Vec3::Zero(), any_number("m"));
  grid.orientation = fields.orientation("orientation");
  if (const json* counts = fields.require("counts", "an array of 3 integers [nx, ny, nz] >= 1")) {
    const std::string at = fields.at("counts");
    if (!counts->is_array() || counts->size() != 3) {
      errors.add(at, "'counts' must be an array of 3 integers [nx, ny, nz], each >= 1; got " +
                         describe(*counts));
    } else {
      for (std::size_t axis = 0; axis < 3; ++axis) {
        if (auto n = read_integer((*counts)[axis], child(at, axis),
                                  "counts[" + std::to_string(axis) + "]", 1, kMaxCount, errors))
          grid.counts[axis] = *n;
      }
    }
  }
  const auto size = fields.required_vec3("size", positive("m"));
  if (size) grid.size_m = *size;
  grid.spacing_m = fields.vec3("spacing", Vec3::Zero(), non_negative("m"));
  const MassOrDensity given = read_mass_or_density(fields);
  if (given.mass_kg) grid.mass_kg = *given.mass_kg;
  if (given.density_kg_m3 && size) grid.mass_kg = *given.density_kg_m3 * size->prod();
  if (!given.given) {
    errors.add(fields.at("mass"),
               "'mass' is required: give 'mass' (kg, of one block) or 'density' (kg/m^3)");
  }
  grid.friction = fields.number("friction", 0.5, non_negative());
  if (!scope.ok() || !context.room_for(blocks_count(grid.counts))) return {};
  return blocks(grid);
}

// {"type": "window"}: a breakable pane, optionally in an anchored frame.
std::vector<ObjectSpec> parse_window(const GeneratorContext& context) {
  const json& value = context.value;
  const std::string& pointer = context.pointer;
  Errors& errors = context.errors;
  const ErrorScope scope(errors);
  const Fields fields(value, pointer, errors, "a window generator",
                      {"type", "name", "position", "orientation", "size", "thickness", "material",
                       "frame", "frame_width", "frame_depth", "sheltered_back", "fracture"});
  WindowParams window_params;
  if (auto name = fields.required_name("name")) window_params.name = *name;
  window_params.position = fields.vec3("position", Vec3::Zero(), any_number("m"));
  window_params.orientation = fields.orientation("orientation");
  if (const json* size = fields.require("size", "an array [width, height] of the pane, m")) {
    const std::string at = fields.at("size");
    if (!size->is_array() || size->size() != 2) {
      errors.add(at, "'size' must be an array of 2 numbers [width, height], m, each > 0; got " +
                         describe(*size));
    } else {
      const Bound pane_side{0.0, true, kMaxPaneSide_m, false, "m", ""};
      const auto width = read_number((*size)[0], child(at, 0), "size[0]", pane_side, errors);
      const auto height = read_number((*size)[1], child(at, 1), "size[1]", pane_side, errors);
      if (width) window_params.width_m = *width;
      if (height) window_params.height_m = *height;
    }
  }
  read_window_fields(fields, true, window_params);
  if (!scope.ok() || !context.room_for(window_params.frame ? 5 : 1)) return {};
  return window(window_params);
}

}  // namespace

std::vector<SceneObject> parse_generator(const json& value, const std::string& pointer,
                                         std::size_t generator_index, std::size_t objects_before,
                                         const Limits& limits, Errors& errors) {
  if (!expect_object(value, pointer, "a generator", errors)) return {};
  const json* type = member(value, "type");
  if (!type) {
    errors.add(child(pointer, "type"),
               "'type' is required: one of " + join(choice_names(kGeneratorTypes)));
    return {};
  }
  const auto kind = read_enum(*type, child(pointer, "type"), "type", kGeneratorTypes, errors);
  if (!kind) return {};

  const GeneratorContext context{value, pointer, objects_before, limits, errors};
  std::vector<ObjectSpec> objects;
  switch (*kind) {
    case GeneratorType::brick_wall:
      objects = parse_brick_wall(context);
      break;
    case GeneratorType::blocks:
      objects = parse_blocks(context);
      break;
    case GeneratorType::window:
      objects = parse_window(context);
      break;
  }

  std::vector<SceneObject> generated;
  generated.reserve(objects.size());
  for (ObjectSpec& object : objects) {
    generated.push_back(SceneObject{std::move(object), child(pointer, "name"),
                                    child(pointer, "position"), generator_index});
  }
  return generated;
}

}  // namespace brisance::scene
