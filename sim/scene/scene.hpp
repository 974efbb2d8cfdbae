// sim/scene: the typed scene spec, parsed from the scene JSON of DESIGN.md and validated in one
// place. After parse_scene() succeeds, the simulator trusts every value in a Scene.
// Units: SI throughout (m, kg, s, Pa); +Y up; quaternions [x, y, z, w] on the wire.
#pragma once

#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <nlohmann/json_fwd.hpp>

#include "sim/blast/blast_point.hpp"
#include "sim/blast/pulse.hpp"
#include "sim/geometry/mesh.hpp"

namespace brisance::scene {

using Vec3 = Eigen::Vector3d;
using Quat = Eigen::Quaterniond;

// The names of ObjectSpec::sheltered's bits, bit k for kShelteredAxes[k].
inline constexpr std::string_view kShelteredAxes[6] = {"+x", "-x", "+y", "-y", "+z", "-z"};
inline constexpr std::uint8_t kShelteredBack = 1u << 5;  // "-z": behind a window's pane

// Whether a face with this outward normal (object frame, unit) is sheltered by `mask`.
bool is_sheltered(std::uint8_t mask, const Vec3& normal);

struct ChargeSpec {
  Vec3 position = Vec3::Zero();     // world, m
  double mass_kg = 1.0;             // mass of explosive, > 0
  std::string explosive = "TNT";    // canonical name from blast::known_explosives(), or "custom"
  double tnt_factor = 1.0;          // W = mass_kg * tnt_factor
  double impulse_tnt_factor = 1.0;  // W for impulses (UFC 3-340-02 eq. 2-5); = tnt_factor if none
  blast::Burst burst = blast::Burst::air;
  blast::SurfaceBurstModel surface_model = blast::SurfaceBurstModel::hemispherical;
};

struct GroundSpec {
  double height_m = 0.0;     // the plane y = height_m
  double friction = 0.5;     // Coulomb coefficient, >= 0
  double restitution = 0.2;  // in [0, 1]
};

struct EnvironmentSpec {
  Vec3 gravity_m_s2 = Vec3(0.0, -9.81, 0.0);
  double air_density_kg_m3 = 1.225;  // 0 turns flight drag off
  double ambient_pressure_pa = 101325.0;
  std::optional<GroundSpec> ground = GroundSpec{};  // null in JSON: no ground
};

// `file` and `asset` shapes are meshes once read (ShapeType::mesh).
enum class ShapeType { box, mesh };

// A breakable pane (DESIGN.md decision 9, thesis ch. 5–6): a box whose thickness is its local z
// (size[2], the smallest edge), front face +z. In engine::prepare the peak reflected pressure
// on the pane gives its bending stress; above the strength the pane is cut into fragments.
// The longest side a breakable pane may have, m: the plate model behind its breakage (a
// lumped-mass plate of the pane's size) and its crack pattern are meant for glazing, and beyond
// some 1e100 m its stiffness underflows to zero. Real panes stay below about 20 m.
inline constexpr double kMaxPaneSide_m = 100.0;
// The thinnest breakable pane, m: 0.1 mm, far below any glazing (thin glass starts near 0.5 mm).
// The plate model's mass and stiffness go with the thickness and its cube; below about 1e-100 m
// they underflow to zero.
inline constexpr double kMinPaneThickness_m = 1e-4;

struct FractureSpec {
  enum class Trigger { automatic, always };
  enum class Clearing { fragment, pane };
  enum class Breakage { dynamic, static_plate };
  // automatic: break when the stress beats the strength; always: break whatever the pressure
  // (artist control: the thesis decouples pattern and blast by choice, §6).
  Trigger trigger = Trigger::automatic;
  // Material, resolved from the object's material or given: Young's modulus, Pa; fracture
  // toughness K_c, Pa m^0.5; bending strength, Pa.
  double youngs_modulus_pa = 70e9;
  double fracture_toughness_pa_sqrt_m = 0.75e6;
  double strength_pa = 45e6;
  // Tempered glass: the residual surface compression of its temper, Pa (0: annealed). A pane
  // with one breaks into dice sized by it (docs/fracture.md), whatever the load.
  double surface_compression_pa = 0.0;
  // Crack pattern. growth_length_m, when given, overrides eq. 5.5's scale (artist control).
  std::optional<double> growth_length_m;
  double pattern_scale = 5000.0;  // growth length = pattern_scale x a_c (docs/fracture.md)
  double branch_angle_deg = 25.0;
  double angle_variance_deg = 34.5;
  double wiggle_probability = 0.3;
  double wiggle_variance_deg = 30.0;
  int grid = 2048;                    // bit-bucket cells along the pane's longer side
  std::optional<std::uint64_t> seed;  // default: from simulation.seed and the object
  // Holds until release: the crack faces' interlock, Pa over the crack's area (length x
  // thickness), and, for a pane in an anchored frame, the glazing along the frame, Pa over the
  // edge length x frame_bite_m.
  bool framed = false;
  double bond_strength_pa = 1e3;
  double frame_strength_pa = 138e3;
  double frame_bite_m = 0.01;
  // pane: every fragment clears from the edges of the surface its pane lies in, as the pane
  // does (the cracks are closed while the wave loads it); fragment: each fragment clears from
  // its own edges (thesis §6.5), which takes most of a fragment's load within microseconds.
  Clearing clearing = Clearing::pane;
  // How the pane's stress is judged (docs/fracture.md): dynamic — the peak centre stress of a
  // large-deflection plate SDOF under the pane's pressure history (sim/response/plate);
  // static_plate ("static") — Roark's small-deflection stress under the peak pressure.
  Breakage breakage = Breakage::dynamic;
};

struct ObjectSpec {
  std::string name;  // unique within the scene
  ShapeType shape = ShapeType::box;
  Vec3 box_size_m = Vec3::Ones();  // full edge lengths, for ShapeType::box
  geometry::TriangleMesh mesh;     // the shape as a mesh in its own frame (boxes included)
  Vec3 position = Vec3::Zero();    // world position of the shape's origin, m
  Quat orientation = Quat::Identity();
  double mass_kg = 0.0;           // resolved: given mass, or density * volume
  double friction = 0.5;          // mu of the frictional hold (thesis §3.6), >= 0
  double drag_coefficient = 1.0;  // C_D for blast drag and flight drag
  bool anchored = false;          // never moves
  bool blocks = true;             // may shield others from the blast (sim/occlusion)
  bool rotates = true;            // false: translation only
  // Faces with nothing to reach them from behind (a room behind a window, a wall's far side
  // against the ground): one bit per axis direction of the object's own frame, in the order
  // +x, -x, +y, -y, +z, -z (kShelteredAxes). A face whose outward normal lies within 45° of a
  // sheltered direction is loaded only by a wave that strikes it, never by one wrapping around.
  std::uint8_t sheltered = 0;
  std::string material;                  // optional name from the materials table
  std::optional<FractureSpec> fracture;  // breakable pane (box shapes only)
};

enum class Integrator { explicit_euler, semi_implicit_euler, rk4 };
enum class OcclusionMode { automatic, on, off };
// Contacts between bodies (issue 13): `automatic` skips pairs that cannot meet (both at rest or
// held, or moving apart without touching) and reports them in stats.
enum class CollisionMode { automatic, on, off };

// The shielding heuristic's parameters (thesis §4.2, sim/occlusion, docs/occlusion.md).
struct ShieldingSpec {
  int resolution = 32;  // sphere-map pixels along a face's base; rows are 7/8 of it (32 x 28)
  double blocking_offset = 1.0;   // eq. 4.1: f reaches 0 at b = offset + slope k
  double separation_slope = 7.0;  //
  bool per_panel = true;          // false: one attenuation per object, as the thesis
};

struct SimulationSpec {
  double duration_s = 2.0;            // (0, max_duration_s]
  double frame_rate_hz = 30.0;        // frames at exact multiples of 1 / frame_rate
  std::optional<double> time_step_s;  // fixed step; if absent the step follows `tolerance`
  double tolerance = 1e-3;            // relative error target of the adaptive step
  std::uint64_t seed = 0;
  bool clearing = true;
  OcclusionMode occlusion = OcclusionMode::automatic;
  ShieldingSpec shielding;
  CollisionMode collisions = CollisionMode::off;  // off by default until stacks settle (issue 13)
  Integrator integrator = Integrator::semi_implicit_euler;
  blast::PulseShape pulse_shape = blast::PulseShape::friedlander;
  double max_panel_area_m2 = 0.05;  // larger faces are cut into panels of at most this
  double linear_damping = 0.0;      // per second, thesis §6.5 global damping
  double angular_damping = 0.0;     // per second
  double rotation_factor = 1.0;     // scales blast torques (thesis §6.5)
  bool sleep = true;                // bodies at rest on the ground stop being integrated
  // Each body takes substeps of its own where its spin (at most 2 sqrt(tolerance) rad a substep)
  // or its approach to the ground needs them, instead of shortening every body's step;
  // semi-implicit Euler and collisions off only. Unset: on where it applies (body_substeps()).
  std::optional<bool> body_substeps;
};

struct Scene {
  std::vector<ChargeSpec> charges;
  EnvironmentSpec environment;
  std::vector<ObjectSpec> objects;  // generators already expanded into objects
  SimulationSpec simulation;
};

// Configurable limits; exceeding one is a validation error naming the limit and its value.
struct Limits {
  std::size_t max_objects = 20000;
  std::size_t max_charges = 64;
  std::size_t max_mesh_vertices = 200000;  // per mesh
  std::size_t max_panels = 2000000;        // whole scene, after subdivision
  double max_duration_s = 600.0;
  double max_frame_rate_hz = 1000.0;
  std::size_t max_frame_samples = 50000000;  // frames x bodies (fragments of broken panes too)
  // Fragments all broken panes of a run make together; counted as the panes break (the pattern
  // depends on the blast), so a run past it stops with an error rather than grow.
  std::size_t max_fragments = 100000;
};

// One problem with the input: an RFC 6901 JSON pointer to the offending value and a message that
// says what is wrong and what would be right.
struct ValidationError {
  std::string pointer;
  std::string message;
};

struct ParseResult {
  std::optional<Scene> scene;           // set when errors is empty
  std::vector<ValidationError> errors;  // every problem found, not just the first
};

// Meshes that a scene names rather than contains: {"type": "file", "path": ..., "node": ...}
// (the CLI reads it relative to the scene file) and {"type": "asset", "asset": ID, "node": ...}
// (an asset uploaded to the HTTP service). The parser asks a resolver for the mesh and checks it
// like an inline mesh; without a resolver for the kind, such a shape is an error that says where
// it can be used.
struct MeshReference {
  std::string reference;            // the file's path as written, or the asset id
  std::optional<std::string> node;  // the node to take; nullopt: the whole file
};
struct ResolvedMesh {
  std::optional<geometry::TriangleMesh> mesh;  // m, in the frame of the node or file
  std::string error;                           // why there is none, when `mesh` is empty
};
using MeshResolver = std::function<ResolvedMesh(const MeshReference&)>;
struct MeshSources {
  MeshResolver file;   // `file` shapes; empty: refused (the HTTP service reads no files)
  MeshResolver asset;  // `asset` shapes; empty: refused (a scene file names files instead)
};

// Validates and converts a scene document; all errors are collected.
ParseResult parse_scene(const nlohmann::json& document, const Limits& limits = {},
                        const MeshSources& meshes = {});
// The same from text; malformed JSON is one error with pointer "" and the parser's position.
ParseResult parse_scene_text(std::string_view text, const Limits& limits = {},
                             const MeshSources& meshes = {});

// Named materials for `material` (density and default friction; for breakable materials also
// Young's modulus, fracture toughness and bending strength), with their public sources. Every
// material lives in one table, sim/scene/materials.cpp.
struct Material {
  std::string_view name;
  double density_kg_m3;
  double friction;
  std::string_view source;
  // Breakable materials only (strength_pa > 0): may carry `fracture`.
  double youngs_modulus_pa = 0.0;
  double fracture_toughness_pa_sqrt_m = 0.0;  // K_c
  double strength_pa = 0.0;                   // bending strength
  std::string_view fracture_source = {};
  double surface_compression_pa = 0.0;  // tempered glass: its temper's surface compression
};
std::vector<Material> known_materials();

}  // namespace brisance::scene
