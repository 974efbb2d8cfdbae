// sim/scene/parse_generators: the scene's `generators[]` entries. Each type has one function that
// reads its parameters, checks the objects it would make against max_objects before making any,
// and hands the parameters to its generator (generators.hpp), which only does geometry.
#include <array>
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

// {"type": "brick_wall"}: a running-bond wall of bricks and half bricks.
std::vector<ObjectSpec> parse_brick_wall(const GeneratorContext& context) {
  const json& value = context.value;
  const std::string& pointer = context.pointer;
  Errors& errors = context.errors;
  const ErrorScope scope(errors);
  const Fields fields(value, pointer, errors, "a brick_wall generator",
                      {"type", "name", "position", "orientation", "rows", "columns", "brick_size",
                       "brick_mass", "friction", "mortar_gap"});
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
  if (!scope.ok() || !context.room_for(brick_wall_count(wall.rows, wall.columns))) return {};
  return brick_wall(wall);
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
      const auto width = read_number((*size)[0], child(at, 0), "size[0]", positive("m"), errors);
      const auto height = read_number((*size)[1], child(at, 1), "size[1]", positive("m"), errors);
      if (width) window_params.width_m = *width;
      if (height) window_params.height_m = *height;
    }
  }
  window_params.thickness_m =
      fields.number("thickness", window_params.thickness_m, range(0.0, true, 0.1, false, "m"));
  if (window_params.thickness_m > std::min(window_params.width_m, window_params.height_m)) {
    errors.add(fields.at("thickness"),
               "'thickness' must not exceed the pane's width and height; make it thinner");
  }
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
  }
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
