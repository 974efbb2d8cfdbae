// sim/scene/parse_sections: the scene's `charges[]` entries, `environment` and `simulation`
// (docs/scene-format.md). Objects and generators have files of their own.
#include <array>
#include <cmath>
#include <cstdint>

#include "sim/blast/explosives.hpp"
#include "sim/scene/sections.hpp"

namespace brisance::scene {

namespace {

constexpr double kMaxTimeStep_s = 0.1;

// The JSON names of the enums, in the order messages list them.
constexpr std::array<Choice<blast::Burst>, 2> kBursts = {{
    {"air", blast::Burst::air},
    {"surface", blast::Burst::surface},
}};
constexpr std::array<Choice<blast::SurfaceBurstModel>, 2> kSurfaceBurstModels = {{
    {"hemispherical", blast::SurfaceBurstModel::hemispherical},
    {"factor_1_8", blast::SurfaceBurstModel::factor_1_8},
}};
constexpr std::array<Choice<CollisionMode>, 3> kCollisionModes = {{
    {"auto", CollisionMode::automatic},
    {"on", CollisionMode::on},
    {"off", CollisionMode::off},
}};
constexpr std::array<Choice<OcclusionMode>, 3> kOcclusionModes = {{
    {"auto", OcclusionMode::automatic},
    {"on", OcclusionMode::on},
    {"off", OcclusionMode::off},
}};
constexpr std::array<Choice<Integrator>, 3> kIntegrators = {{
    {"explicit_euler", Integrator::explicit_euler},
    {"semi_implicit_euler", Integrator::semi_implicit_euler},
    {"rk4", Integrator::rk4},
}};
constexpr std::array<Choice<blast::PulseShape>, 3> kPulseShapes = {{
    {"friedlander", blast::PulseShape::friedlander},
    {"triangle_same_impulse", blast::PulseShape::triangle_same_impulse},
    {"triangle_same_period", blast::PulseShape::triangle_same_period},
}};

}  // namespace

std::optional<ChargeSpec> parse_charge(const json& value, const std::string& pointer,
                                       Errors& errors) {
  if (!expect_object(value, pointer, "a charge", errors)) return std::nullopt;
  const ErrorScope scope(errors);
  const Fields fields(value, pointer, errors, "a charge",
                      {"position", "mass", "explosive", "burst", "burst_model"});
  ChargeSpec charge;
  const auto position = fields.required_vec3("position", any_number("m"));
  if (position) charge.position = *position;
  if (auto mass = fields.required_number("mass", positive("kg"))) charge.mass_kg = *mass;

  if (const json* explosive = fields.get("explosive")) {
    const std::string at = fields.at("explosive");
    if (explosive->is_string()) {
      const auto& name = explosive->get_ref<const std::string&>();
      if (const auto found = blast::find_explosive(name)) {
        charge.explosive = std::string(found->name);
        charge.tnt_factor = found->tnt_factor;
        charge.impulse_tnt_factor = found->impulse_factor();
      } else {
        errors.add(at, "unknown explosive " + in_quotes(name) + "; use one of " +
                           blast::known_explosive_names() +
                           ", or {\"tnt_factor\": F} for a custom TNT equivalence");
      }
    } else if (explosive->is_object()) {
      const Fields custom(*explosive, at, errors, "a custom explosive",
                          {"tnt_factor", "impulse_tnt_factor"});
      if (auto factor = custom.required_number("tnt_factor", positive("kg TNT per kg"))) {
        charge.explosive = "custom";
        charge.tnt_factor = *factor;
        charge.impulse_tnt_factor =
            custom.number("impulse_tnt_factor", *factor, positive("kg TNT per kg"));
      }
    } else {
      errors.add(at, "'explosive' must be an explosive's name (" + blast::known_explosive_names() +
                         ") or an object {\"tnt_factor\": F}; got " + describe(*explosive));
    }
  }
  // The blast curves take the TNT equivalent's cube root: it must be a finite mass.
  if (!std::isfinite(charge.mass_kg * charge.tnt_factor) ||
      !std::isfinite(charge.mass_kg * charge.impulse_tnt_factor))
    errors.add(fields.at("mass"),
               "times the explosive's TNT factor is not a finite mass of TNT; "
               "use a smaller mass or factor");
  charge.burst = fields.choice("burst", blast::Burst::air, kBursts);
  charge.surface_model =
      fields.choice("burst_model", blast::SurfaceBurstModel::hemispherical, kSurfaceBurstModels);
  // A charge placed where it is valid still takes part in the scene-wide checks (below the
  // ground, inside an object) when its other fields are wrong, so every problem is listed at once.
  if (!scope.ok() && !position) return std::nullopt;
  return charge;
}

EnvironmentSpec parse_environment(const json& value, const std::string& pointer, Errors& errors) {
  EnvironmentSpec environment;
  if (!expect_object(value, pointer, "'environment'", errors)) return environment;
  const Fields fields(value, pointer, errors, "'environment'",
                      {"gravity", "air_density", "ambient_pressure", "ground"});
  environment.gravity_m_s2 = fields.vec3("gravity", environment.gravity_m_s2, any_number("m/s^2"));
  environment.air_density_kg_m3 =
      fields.number("air_density", environment.air_density_kg_m3, non_negative("kg/m^3"));
  environment.ambient_pressure_pa =
      fields.number("ambient_pressure", environment.ambient_pressure_pa, positive("Pa"));
  if (const json* ground = fields.get("ground")) {
    if (ground->is_null()) {
      environment.ground.reset();
    } else if (ground->is_object()) {
      const Fields ground_fields(*ground, fields.at("ground"), errors, "'ground'",
                                 {"height", "friction", "restitution"});
      GroundSpec spec;
      spec.height_m = ground_fields.number("height", spec.height_m, any_number("m"));
      spec.friction = ground_fields.number("friction", spec.friction, non_negative());
      spec.restitution =
          ground_fields.number("restitution", spec.restitution, range(0.0, false, 1.0, false));
      environment.ground = spec;
    } else {
      errors.add(fields.at("ground"),
                 "'ground' must be an object {\"height\", \"friction\", \"restitution\"} or null "
                 "for no ground; got " +
                     describe(*ground));
    }
  }
  return environment;
}

// {"resolution", "blocking_offset", "separation_slope", "per_panel"}: the shielding heuristic.
ShieldingSpec parse_shielding(const json& value, const std::string& pointer, Errors& errors) {
  ShieldingSpec spec;
  if (!expect_object(value, pointer, "'shielding'", errors)) return spec;
  const Fields fields(value, pointer, errors, "'shielding'",
                      {"resolution", "blocking_offset", "separation_slope", "per_panel"});
  if (fields.get("resolution")) {
    if (auto resolution = fields.required_integer("resolution", 4, 128))
      spec.resolution = static_cast<int>(*resolution);
  }
  spec.blocking_offset = fields.number("blocking_offset", spec.blocking_offset, positive());
  spec.separation_slope = fields.number("separation_slope", spec.separation_slope, non_negative());
  spec.per_panel = fields.boolean("per_panel", spec.per_panel);
  return spec;
}

SimulationSpec parse_simulation(const json& value, const std::string& pointer, const Limits& limits,
                                Errors& errors) {
  SimulationSpec simulation;
  if (!expect_object(value, pointer, "'simulation'", errors)) return simulation;
  const Fields fields(
      value, pointer, errors, "'simulation'",
      {"duration", "frame_rate", "time_step", "tolerance", "seed", "clearing", "occlusion",
       "shielding", "integrator", "pulse", "max_panel_area", "linear_damping", "angular_damping",
       "rotation_factor", "sleep", "collisions", "body_substeps"});
  simulation.duration_s =
      fields.number("duration", simulation.duration_s,
                    range(0.0, true, limits.max_duration_s, false, "s", "max_duration_s"));
  simulation.frame_rate_hz = fields.number(
      "frame_rate", simulation.frame_rate_hz,
      range(0.0, true, limits.max_frame_rate_hz, false, "frames per s", "max_frame_rate_hz"));
  if (const json* step = fields.get("time_step")) {
    simulation.time_step_s = read_number(*step, fields.at("time_step"), "time_step",
                                         range(0.0, true, kMaxTimeStep_s, false, "s"), errors);
  }
  simulation.tolerance =
      fields.number("tolerance", simulation.tolerance, range(0.0, true, 1.0, true));
  if (fields.get("time_step") && fields.get("tolerance")) {
    errors.add(fields.at("tolerance"),
               "give either 'time_step' (a fixed step) or 'tolerance' (an adaptive step), not "
               "both; remove one of them");
  }
  if (const json* seed = fields.get("seed")) {
    const std::string at = fields.at("seed");
    if (seed->is_number_unsigned()) {
      simulation.seed = seed->get<std::uint64_t>();
    } else if (seed->is_number_integer() && seed->get<std::int64_t>() >= 0) {
      simulation.seed = static_cast<std::uint64_t>(seed->get<std::int64_t>());
    } else if (seed->is_number_float() && seed->get<double>() >= 0.0 &&
               seed->get<double>() < 1.8446744073709552e19 &&
               seed->get<double>() == std::floor(seed->get<double>())) {
      simulation.seed = static_cast<std::uint64_t>(seed->get<double>());
    } else {
      errors.add(at, "'seed' must be an integer in [0, 2^64 - 1]; got " + describe(*seed));
    }
  }
  simulation.clearing = fields.boolean("clearing", simulation.clearing);
  simulation.occlusion = fields.choice("occlusion", simulation.occlusion, kOcclusionModes);
  if (const json* shielding = fields.get("shielding"))
    simulation.shielding = parse_shielding(*shielding, fields.at("shielding"), errors);
  simulation.collisions = fields.choice("collisions", simulation.collisions, kCollisionModes);
  simulation.integrator = fields.choice("integrator", simulation.integrator, kIntegrators);
  simulation.pulse_shape = fields.choice("pulse", simulation.pulse_shape, kPulseShapes);
  simulation.max_panel_area_m2 =
      fields.number("max_panel_area", simulation.max_panel_area_m2, positive("m^2"));
  simulation.linear_damping =
      fields.number("linear_damping", simulation.linear_damping, non_negative("1/s"));
  simulation.angular_damping =
      fields.number("angular_damping", simulation.angular_damping, non_negative("1/s"));
  simulation.rotation_factor =
      fields.number("rotation_factor", simulation.rotation_factor, non_negative());
  simulation.sleep = fields.boolean("sleep", simulation.sleep);
  if (fields.get("body_substeps"))
    simulation.body_substeps = fields.boolean("body_substeps", false);
  if (simulation.body_substeps == true &&
      simulation.integrator != Integrator::semi_implicit_euler) {
    errors.add(fields.at("body_substeps"),
               "'body_substeps' needs the \"semi_implicit_euler\" integrator (the only one that "
               "turns a body by its own rule); remove it or change 'integrator'");
  }
  if (simulation.body_substeps == true && simulation.collisions != CollisionMode::off) {
    errors.add(fields.at("body_substeps"),
               "'body_substeps' needs \"collisions\": \"off\" (contacts between bodies are "
               "solved once a step, for every body at once); remove one of them");
  }
  return simulation;
}

}  // namespace brisance::scene
