// sim/scene/parse_objects: the scene's `objects[]` entries — shapes (boxes, closed meshes and
// meshes named by file or uploaded asset),
// materials, mass or density, friction and flags — and the `fracture` of a breakable pane, which
// the window generator shares (docs/scene-format.md, docs/fracture.md).
#include <array>
#include <cstdint>
#include <limits>
#include <utility>

#include "sim/scene/sections.hpp"

namespace brisance::scene {

namespace {

// The shape's `type` as written; file and asset shapes become ShapeType::mesh.
enum class ShapeKind { box, mesh, file, asset };
constexpr std::array<Choice<ShapeKind>, 4> kShapeTypes = {{
    {"box", ShapeKind::box},
    {"mesh", ShapeKind::mesh},
    {"file", ShapeKind::file},
    {"asset", ShapeKind::asset},
}};
constexpr std::array<Choice<FractureSpec::Trigger>, 2> kTriggers = {{
    {"auto", FractureSpec::Trigger::automatic},
    {"always", FractureSpec::Trigger::always},
}};
constexpr std::array<Choice<FractureSpec::Breakage>, 2> kFractureBreakages = {{
    {"dynamic", FractureSpec::Breakage::dynamic},
    {"static", FractureSpec::Breakage::static_plate},
}};

constexpr std::array<Choice<FractureSpec::Clearing>, 2> kFractureClearings = {{
    {"fragment", FractureSpec::Clearing::fragment},
    {"pane", FractureSpec::Clearing::pane},
}};

std::string lower_case(std::string_view text) {
  std::string lower(text);
  for (char& c : lower) {
    if (c >= 'A' && c <= 'Z') c = static_cast<char>(c - 'A' + 'a');
  }
  return lower;
}

// The mesh of a {"type": "mesh"} shape; its closedness is checked by the caller.
std::optional<geometry::TriangleMesh> parse_mesh(const Fields& shape, const Limits& limits,
                                                 Errors& errors) {
  const ErrorScope scope(errors);
  geometry::TriangleMesh mesh;
  if (const json* vertices =
          shape.require("vertices", "an array of vertices [[x, y, z], ...] in metres")) {
    const std::string at = shape.at("vertices");
    if (expect_array(*vertices, at, "'vertices'", errors)) {
      if (vertices->size() > limits.max_mesh_vertices) {
        errors.add(at, "the mesh has " + std::to_string(vertices->size()) +
                           " vertices, more than the limit max_mesh_vertices = " +
                           std::to_string(limits.max_mesh_vertices) + "; simplify the mesh");
      } else {
        mesh.vertices.reserve(vertices->size());
        for (std::size_t i = 0; i < vertices->size(); ++i) {
          const std::string name = "vertices[" + std::to_string(i) + "]";
          if (auto vertex = read_vec3((*vertices)[i], child(at, i), name, any_number("m"), errors))
            mesh.vertices.push_back(*vertex);
        }
      }
    }
  }
  if (const json* triangles =
          shape.require("triangles",
                        "an array of triangles [[i, j, k], ...] indexing 'vertices', "
                        "counter-clockwise seen from outside")) {
    const std::string at = shape.at("triangles");
    if (expect_array(*triangles, at, "'triangles'", errors)) {
      mesh.triangles.reserve(triangles->size());
      for (std::size_t t = 0; t < triangles->size(); ++t) {
        const json& triangle = (*triangles)[t];
        const std::string triangle_at = child(at, t);
        if (!triangle.is_array() || triangle.size() != 3) {
          errors.add(triangle_at, "triangles[" + std::to_string(t) +
                                      "] must be an array of 3 vertex indices [i, j, k]; got " +
                                      describe(triangle));
          continue;
        }
        std::array<std::uint32_t, 3> indices{};
        bool ok = true;
        for (std::size_t k = 0; k < 3; ++k) {
          const std::string name =
              "triangles[" + std::to_string(t) + "][" + std::to_string(k) + "]";
          const auto index = read_integer(triangle[k], child(triangle_at, k), name, 0,
                                          std::numeric_limits<std::uint32_t>::max(), errors);
          if (index) {
            indices[k] = static_cast<std::uint32_t>(*index);
          } else {
            ok = false;
          }
        }
        if (ok) mesh.triangles.push_back(indices);
      }
      if (triangles->size() < 4 && scope.ok()) {
        errors.add(at, "a closed mesh needs at least 4 triangles; got " +
                           std::to_string(triangles->size()));
      }
    }
  }
  if (!scope.ok()) return std::nullopt;
  return mesh;
}

// A closed mesh into object.shape and mesh, or the reason it cannot be simulated at `at`.
void accept_mesh(geometry::TriangleMesh mesh, const std::string& at, const Limits& limits,
                 ObjectSpec& object, Errors& errors) {
  if (mesh.vertices.size() > limits.max_mesh_vertices) {
    errors.add(at, "the mesh has " + std::to_string(mesh.vertices.size()) +
                       " vertices, more than the limit max_mesh_vertices = " +
                       std::to_string(limits.max_mesh_vertices) + "; simplify the mesh");
  } else if (auto problem = geometry::check_closed_mesh(mesh)) {
    errors.add(at, "the mesh cannot be simulated: " + *problem +
                       "; give a closed mesh with triangles wound counter-clockwise seen "
                       "from outside");
  } else {
    object.shape = ShapeType::mesh;
    object.mesh = std::move(mesh);
  }
}

// A `file` or `asset` shape: the reference and the optional node, then the mesh from `resolver`.
void parse_mesh_reference(const json& shape, const std::string& at, ShapeKind kind,
                          const MeshResolver& resolver, const Limits& limits, ObjectSpec& object,
                          Errors& errors) {
  const bool is_file = kind == ShapeKind::file;
  const std::string_view key = is_file ? "path" : "asset";
  const Fields fields(shape, at, errors, is_file ? "a file shape" : "an asset shape",
                      {"type", key, "node"});
  const ErrorScope scope(errors);
  MeshReference reference;
  if (const json* value = fields.require(
          key, is_file ? "the mesh file's path (.glb, .gltf or .obj), relative to the scene file"
                       : "the id POST /v1/assets gave for the uploaded mesh")) {
    if (!value->is_string() || value->get_ref<const std::string&>().empty()) {
      errors.add(fields.at(key),
                 "'" + std::string(key) + "' must be a non-empty string; got " + describe(*value));
    } else {
      reference.reference = value->get<std::string>();
    }
  }
  if (const json* node = fields.get("node")) {
    if (!node->is_string() || node->get_ref<const std::string&>().empty()) {
      errors.add(fields.at("node"),
                 "'node' must be the name of a node in the file; got " + describe(*node));
    } else {
      reference.node = node->get<std::string>();
    }
  }
  if (!scope.ok()) return;
  if (!resolver) {
    errors.add(child(at, "type"),
               is_file ? "a 'file' shape can only be read by the CLI (brisance run or validate, "
                         "relative to the scene file); over HTTP upload the mesh with POST "
                         "/v1/assets and use {\"type\": \"asset\", \"asset\": ID}"
                       : "an 'asset' shape names a mesh uploaded to the HTTP service; in a scene "
                         "file use {\"type\": \"file\", \"path\": \"crate.glb\"}");
    return;
  }
  ResolvedMesh resolved = resolver(reference);
  if (!resolved.mesh) {
    errors.add(at, (is_file ? "cannot read the mesh file " : "cannot use the asset ") +
                       in_quotes(reference.reference) + ": " + resolved.error);
    return;
  }
  accept_mesh(std::move(*resolved.mesh), at, limits, object, errors);
}

// The object's required `shape`, into object.shape, box_size_m and mesh; true if it is valid.
bool parse_shape(const Fields& fields, const Limits& limits, const MeshSources& meshes,
                 ObjectSpec& object) {
  Errors& errors = fields.errors();
  const json* shape =
      fields.require("shape",
                     "{\"type\": \"box\", \"size\": [x, y, z]}, {\"type\": \"mesh\", "
                     "\"vertices\": [...], \"triangles\": [...]}, {\"type\": \"file\", \"path\": "
                     "...} or {\"type\": \"asset\", \"asset\": ID}");
  if (!shape) return false;
  const std::string at = fields.at("shape");
  if (!expect_object(*shape, at, "'shape'", errors)) return false;
  const ErrorScope scope(errors);
  const json* type = member(*shape, "type");
  if (!type) {
    errors.add(child(at, "type"), "'type' is required: one of " + join(choice_names(kShapeTypes)));
    return false;
  }
  const std::optional<ShapeKind> kind =
      read_enum(*type, child(at, "type"), "type", kShapeTypes, errors);
  if (kind == ShapeKind::box) {
    const Fields box(*shape, at, errors, "a box shape", {"type", "size"});
    if (auto size = box.required_vec3("size", positive("m"))) {
      object.shape = ShapeType::box;
      object.box_size_m = *size;
      object.mesh = geometry::make_box(*size);
    }
  } else if (kind == ShapeKind::mesh) {
    const Fields mesh_fields(*shape, at, errors, "a mesh shape", {"type", "vertices", "triangles"});
    if (auto mesh = parse_mesh(mesh_fields, limits, errors)) {
      if (auto problem = geometry::check_closed_mesh(*mesh)) {
        errors.add(at, "the mesh cannot be simulated: " + *problem +
                           "; give a closed mesh with triangles wound counter-clockwise seen "
                           "from outside");
      } else {
        object.shape = ShapeType::mesh;
        object.mesh = std::move(*mesh);
      }
    }
  } else if (kind == ShapeKind::file) {
    parse_mesh_reference(*shape, at, *kind, meshes.file, limits, object, errors);
  } else if (kind == ShapeKind::asset) {
    parse_mesh_reference(*shape, at, *kind, meshes.asset, limits, object, errors);
  }
  return scope.ok() && kind.has_value();
}

}  // namespace

// ---------------------------------------------------------------------------------------------
// Materials and mass

std::string material_names() {
  std::vector<std::string> names;
  for (const Material& material : known_materials())
    names.emplace_back(material.name);
  return join(names);
}

// Case-insensitive lookup of a material name.
std::optional<Material> find_material(std::string_view name) {
  const std::string key = lower_case(name);
  for (const Material& material : known_materials()) {
    if (material.name == key) return material;
  }
  return std::nullopt;
}

std::string breakable_material_names() {
  std::vector<std::string> names;
  for (const Material& material : known_materials())
    if (material.strength_pa > 0.0) names.emplace_back(material.name);
  return join(names);
}

MassOrDensity read_mass_or_density(const Fields& fields) {
  Errors& errors = fields.errors();
  const json* mass = fields.get("mass");
  const json* density = fields.get("density");
  MassOrDensity result;
  result.given = mass || density;
  if (mass && density) {
    errors.add(fields.at("density"),
               "give either 'mass' or 'density', not both; remove one of them");
  } else if (mass) {
    result.mass_kg = read_number(*mass, fields.at("mass"), "mass", positive("kg"), errors);
  } else if (density) {
    result.density_kg_m3 =
        read_number(*density, fields.at("density"), "density", positive("kg/m^3"), errors);
  }
  return result;
}

// ---------------------------------------------------------------------------------------------
// Fracture and objects

// The `fracture` member of an object or a window generator. `material` is the object's, if any:
// a breakable one supplies Young's modulus, K_c and the strength, which the fields may
// override. `allow_framed`: objects say whether an anchored frame holds them; a window's
// `frame` says it for its pane.
std::optional<FractureSpec> parse_fracture(const json& value, const std::string& pointer,
                                           const std::optional<Material>& material,
                                           bool allow_framed, Errors& errors) {
  if (!expect_object(value, pointer, "'fracture'", errors)) return std::nullopt;
  const ErrorScope scope(errors);
  std::initializer_list<std::string_view> known = {
      "break",           "growth_length",  "pattern_scale",
      "branch_angle",    "angle_variance", "wiggle_probability",
      "wiggle_variance", "grid",           "seed",
      "framed",          "bond_strength",  "frame_strength",
      "frame_bite",      "clearing",       "strength",
      "toughness",       "youngs_modulus", "breakage"};
  const Fields fields(value, pointer, errors, "'fracture'", known);
  FractureSpec spec;
  spec.trigger = fields.choice("break", FractureSpec::Trigger::automatic, kTriggers);
  if (const json* growth = fields.get("growth_length"))
    spec.growth_length_m = read_number(*growth, fields.at("growth_length"), "growth_length",
                                       range(0.0, true, 10.0, false, "m"), errors);
  spec.pattern_scale = fields.number("pattern_scale", spec.pattern_scale, positive());
  spec.branch_angle_deg =
      fields.number("branch_angle", spec.branch_angle_deg, range(5.0, false, 90.0, false, "deg"));
  spec.angle_variance_deg = fields.number("angle_variance", spec.angle_variance_deg,
                                          range(0.0, false, 90.0, false, "deg"));
  spec.wiggle_probability =
      fields.number("wiggle_probability", spec.wiggle_probability, range(0.0, false, 1.0, false));
  spec.wiggle_variance_deg = fields.number("wiggle_variance", spec.wiggle_variance_deg,
                                           range(0.0, false, 90.0, false, "deg"));
  if (const json* grid = fields.get("grid")) {
    if (auto cells = read_integer(*grid, fields.at("grid"), "grid", 16, 4096, errors))
      spec.grid = static_cast<int>(*cells);
  }
  if (const json* seed = fields.get("seed")) {
    if (auto seed_value = read_integer(*seed, fields.at("seed"), "seed", 0,
                                       std::numeric_limits<std::int64_t>::max(), errors))
      spec.seed = static_cast<std::uint64_t>(*seed_value);
  }
  if (const json* framed = fields.get("framed")) {
    if (allow_framed) {
      spec.framed = read_bool(*framed, fields.at("framed"), "framed", errors).value_or(false);
    } else {
      errors.add(fields.at("framed"),
                 "a window's pane is framed by the generator's 'frame'; remove 'framed' here");
    }
  }
  spec.bond_strength_pa = fields.number("bond_strength", spec.bond_strength_pa, non_negative("Pa"));
  spec.frame_strength_pa =
      fields.number("frame_strength", spec.frame_strength_pa, non_negative("Pa"));
  spec.frame_bite_m = fields.number("frame_bite", spec.frame_bite_m, positive("m"));
  spec.clearing = fields.choice("clearing", FractureSpec::Clearing::pane, kFractureClearings);
  spec.breakage = fields.choice("breakage", FractureSpec::Breakage::dynamic, kFractureBreakages);
  // The material's values, then the explicit ones.
  const bool breakable = material && material->strength_pa > 0.0;
  if (breakable) {
    spec.youngs_modulus_pa = material->youngs_modulus_pa;
    spec.fracture_toughness_pa_sqrt_m = material->fracture_toughness_pa_sqrt_m;
    spec.strength_pa = material->strength_pa;
    spec.surface_compression_pa = material->surface_compression_pa;
  }
  const bool all_given =
      fields.get("strength") && fields.get("toughness") && fields.get("youngs_modulus");
  if (!breakable && !all_given) {
    errors.add(pointer, "a breakable object needs a breakable 'material' (" +
                            breakable_material_names() +
                            ") or all of 'strength' (Pa), 'toughness' (Pa m^0.5) and "
                            "'youngs_modulus' (Pa) in 'fracture'");
  }
  spec.strength_pa = fields.number("strength", spec.strength_pa, positive("Pa"));
  spec.fracture_toughness_pa_sqrt_m =
      fields.number("toughness", spec.fracture_toughness_pa_sqrt_m, positive("Pa m^0.5"));
  spec.youngs_modulus_pa = fields.number("youngs_modulus", spec.youngs_modulus_pa, positive("Pa"));
  if (!scope.ok()) return std::nullopt;
  return spec;
}

// "sheltered": ["-z", ...]: the object-frame directions whose faces nothing reaches from behind.
std::uint8_t parse_sheltered(const json& value, const std::string& pointer, Errors& errors) {
  const std::string expected =
      "'sheltered' must be an array of axis directions of the object's "
      "own frame, each one of \"+x\", \"-x\", \"+y\", \"-y\", "
      "\"+z\", \"-z\"";
  if (!value.is_array()) {
    errors.add(pointer, expected + "; got " + describe(value));
    return 0;
  }
  std::uint8_t mask = 0;
  for (std::size_t i = 0; i < value.size(); ++i) {
    const json& item = value[i];
    bool known = false;
    for (std::size_t axis = 0; axis < 6 && item.is_string(); ++axis) {
      if (item.get_ref<const std::string&>() == kShelteredAxes[axis]) {
        if (mask & (1u << axis))
          errors.add(child(pointer, i), "'sheltered' lists " + in_quotes(kShelteredAxes[axis]) +
                                            " twice; list each direction once");
        mask = static_cast<std::uint8_t>(mask | (1u << axis));
        known = true;
      }
    }
    if (!known) errors.add(child(pointer, i), expected + "; got " + describe(item));
  }
  return mask;
}

std::optional<SceneObject> parse_object(const json& value, const std::string& pointer,
                                        const Limits& limits, const MeshSources& meshes,
                                        Errors& errors) {
  if (!expect_object(value, pointer, "an object", errors)) return std::nullopt;
  const ErrorScope scope(errors);
  const Fields fields(
      value, pointer, errors, "an object",
      {"name", "shape", "position", "orientation", "mass", "density", "friction",
       "drag_coefficient", "anchored", "blocks", "rotates", "sheltered", "material", "fracture"});
  ObjectSpec object;
  const auto name = fields.required_name("name");
  if (name) object.name = *name;

  std::optional<Material> material;
  if (const json* material_value = fields.get("material")) {
    const std::string at = fields.at("material");
    if (!material_value->is_string()) {
      errors.add(at, "'material' must be one of the strings " + material_names() + "; got " +
                         describe(*material_value));
    } else if ((material = find_material(material_value->get_ref<const std::string&>()))) {
      object.material = std::string(material->name);
    } else {
      errors.add(at, "unknown material " +
                         in_quotes(material_value->get_ref<const std::string&>()) +
                         "; use one of " + material_names() +
                         ", or give 'mass' or 'density' and 'friction' instead");
    }
  }

  const bool shape_ok = parse_shape(fields, limits, meshes, object);

  const ErrorScope placement(errors);
  object.position = fields.vec3("position", Vec3::Zero(), any_number("m"));
  object.orientation = fields.orientation("orientation");
  const bool placed = name && shape_ok && placement.ok();

  // Mass: given, or density (given or the material's) times the mesh's volume.
  const MassOrDensity given = read_mass_or_density(fields);
  std::optional<double> density_kg_m3 = given.density_kg_m3;
  if (given.mass_kg) object.mass_kg = *given.mass_kg;
  if (!given.given && material) {
    density_kg_m3 = material->density_kg_m3;
  } else if (!given.given && !fields.get("material")) {
    errors.add(fields.at("mass"),
               "'mass' is required: give 'mass' (kg), 'density' (kg/m^3) or a 'material' (" +
                   material_names() + ")");
  }
  if (density_kg_m3 && shape_ok) {
    object.mass_kg = geometry::mass_properties(object.mesh, *density_kg_m3).mass_kg;
    if (!(object.mass_kg > 0.0)) {
      errors.add(fields.at("shape"),
                 "the shape has no volume, so it has no mass; give it a "
                 "positive volume");
    }
  }

  object.friction = fields.number("friction", material ? material->friction : 0.5, non_negative());
  object.drag_coefficient = fields.number("drag_coefficient", 1.0, positive());
  object.anchored = fields.boolean("anchored", false);
  object.blocks = fields.boolean("blocks", true);
  object.rotates = fields.boolean("rotates", true);
  if (const json* sheltered = fields.get("sheltered"))
    object.sheltered = parse_sheltered(*sheltered, fields.at("sheltered"), errors);
  if (const json* fracture = fields.get("fracture")) {
    object.fracture = parse_fracture(*fracture, fields.at("fracture"), material, true, errors);
    if (object.fracture && shape_ok) {
      const Vec3& size = object.box_size_m;
      if (object.shape != ShapeType::box) {
        errors.add(fields.at("shape"),
                   "a breakable object (with 'fracture') must be a box pane {\"type\": \"box\", "
                   "\"size\": [width, height, thickness]}; use a box shape");
      } else if (size.x() > kMaxPaneSide_m || size.y() > kMaxPaneSide_m) {
        errors.add(child(fields.at("shape"), "size"),
                   "a breakable pane's width and height must be at most " +
                       format_number(kMaxPaneSide_m) + " m; got size [" + format_number(size.x()) +
                       ", " + format_number(size.y()) + ", " + format_number(size.z()) + "]");
      } else if (size.z() < kMinPaneThickness_m) {
        errors.add(child(child(fields.at("shape"), "size"), 2),
                   "a breakable pane must be at least " + format_number(kMinPaneThickness_m) +
                       " m (0.1 mm) thick; got " + format_number(size.z()) +
                       " m; make it thicker (or leave out 'fracture' for an unbreakable sheet)");
      } else if (size.z() > size.x() || size.z() > size.y()) {
        errors.add(child(child(fields.at("shape"), "size"), 2),
                   "a breakable pane's thickness is size[2] and must be its smallest edge; got "
                   "size [" +
                       format_number(size.x()) + ", " + format_number(size.y()) + ", " +
                       format_number(size.z()) +
                       "]; give [width, height, thickness] and turn the pane with 'orientation'");
      }
    }
    if (object.fracture && object.anchored) {
      errors.add(fields.at("anchored"),
                 "a breakable pane cannot be anchored (its fragments must fly); remove "
                 "'anchored' and set 'fracture.framed' to hold its edges in a frame");
    }
  }
  if (!scope.ok() && !placed) return std::nullopt;
  return SceneObject{std::move(object), fields.at("name"), fields.at("position"), std::nullopt};
}

}  // namespace brisance::scene
