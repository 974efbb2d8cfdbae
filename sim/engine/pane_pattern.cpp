#include "sim/engine/pane_pattern.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "sim/blast/reflection.hpp"
#include "sim/fracture/patterns.hpp"
#include "sim/response/plate.hpp"

namespace brisance::engine {

fracture::PlateResponse pane_stress(const scene::FractureSpec& spec, const PaneSize& pane,
                                    const PaneLoad& load, double load_scale,
                                    std::size_t* solver_warnings) {
  if (spec.breakage == scene::FractureSpec::Breakage::static_plate)
    return fracture::simply_supported_plate(pane.width_m, pane.height_m, pane.thickness_m,
                                            load_scale * load.peak_pressure_pa,
                                            spec.youngs_modulus_pa);
  // The dynamic plate: Roark's small-deflection coefficients at this aspect ratio fix its
  // stiffness and bending stress (sim/response/plate.hpp); Poisson's ratio 0.3 as that table.
  const double aspect =
      std::max(pane.width_m, pane.height_m) / std::min(pane.width_m, pane.height_m);
  response::PlateSpec plate;
  plate.width_m = pane.width_m;
  plate.height_m = pane.height_m;
  plate.thickness_m = pane.thickness_m;
  plate.youngs_modulus_pa = spec.youngs_modulus_pa;
  plate.density_kg_m3 = pane.density_kg_m3;
  plate.small_deflection_alpha = fracture::roark_alpha(aspect);
  plate.small_deflection_beta = fracture::roark_beta(aspect);
  response::PlateSolveOptions options;
  options.load_scale = load_scale;
  options.break_stress_pa = spec.strength_pa;
  const response::PlateSdofResult r =
      response::solve_plate(response::plate_model(plate), load.history, options);
  if (solver_warnings) *solver_warnings += r.warnings;
  fracture::PlateResponse out;
  out.stress_pa = r.peak_stress_pa;
  out.deflection_m = r.peak_deflection_m;
  out.small_deflection = r.peak_deflection_m <= 0.5 * pane.thickness_m;
  out.break_time_s = r.break_time_s;
  out.break_velocity_m_s = r.break_velocity_m_s;
  return out;
}

double pane_clearing_distance_m(const PaneSize& pane) {
  return 0.5 * std::min(pane.width_m, pane.height_m);
}

PaneFaceLoad pane_face_load(const blast::Charge& charge, double distance_m, double cos_incidence,
                            const blast::PanelLoadOptions& options) {
  const blast::BlastPoint point = blast::blast_point(charge, distance_m);
  const double cos_a = std::clamp(cos_incidence, 0.0, 1.0);
  const blast::ObliqueReflection reflection = blast::oblique_reflection(
      point.incident_overpressure_pa, point.incident_impulse_pa_s, point.reflected_overpressure_pa,
      point.reflected_impulse_pa_s, std::acos(cos_a));
  PaneFaceLoad out;
  out.in_range = point.in_validity_range;
  out.peak_pressure_pa = reflection.overpressure_pa;
  out.component.arrival_s = point.arrival_time_s;
  if (!(reflection.overpressure_pa > 0.0 && point.positive_duration_s > 0.0 &&
        reflection.impulse_pa_s > 0.0 && point.incident_overpressure_pa > 0.0 &&
        point.incident_impulse_pa_s > 0.0))
    return out;  // no pulse: an empty history
  // The wave as Run::activate builds it for a front face.
  const blast::PanelWave wave =
      blast::panel_wave(point, cos_a, reflection.overpressure_pa, reflection.impulse_pa_s);
  // The relief waits for the wave at the pane's edges, as Run::activate has it for a front panel.
  blast::PanelLoadOptions cleared = options;
  if (cleared.clearing)
    cleared.clearing_delay_s = blast::clearing_delay_s(
        charge, distance_m * cos_a, distance_m * std::sqrt(std::max(0.0, 1.0 - cos_a * cos_a)),
        cleared.clearing_distance_m);
  out.component.history = blast::front_face_history(wave, cleared);
  return out;
}

int pattern_grid(int grid, double longer_m, double growth_length_m) {
  // Forks 4 cells apart give the fragment count of a finer grid (1.2 x 0.8 m pane, mean of 4
  // seeds: 829 at 4 cells, 960 at 2 cells of a coarser grid for the same growth length; 287 and
  // 293 at 10 and 5 cells): refining only at the 2-cell clamp would make the count drop there.
  const double wanted = kCellsPerGrowth * longer_m / growth_length_m;
  const int finest = std::max(grid, kFinestPatternGrid);
  if (!(wanted > grid)) return grid;
  return static_cast<int>(std::min(std::ceil(wanted), static_cast<double>(finest)));
}

PanePattern pane_pattern(const scene::FractureSpec& spec, const PaneSize& pane,
                         const PaneLoad& load, std::uint64_t seed) {
  const double width_m = pane.width_m;
  const double height_m = pane.height_m;
  const double thickness_m = pane.thickness_m;
  // The bit bucket: `spec.grid` cells along the longer side, refined (pattern_grid) up to the
  // finest grid a scene may ask for so that eq. 5.5's growth length keeps falling with pressure.
  const double longer = std::max(width_m, height_m);
  const double shorter = std::min(width_m, height_m);
  const double finest_cell = longer / std::max(spec.grid, kFinestPatternGrid);
  fracture::PaneFractureInput input;
  input.width_m = width_m;
  input.height_m = height_m;
  input.thickness_m = thickness_m;
  input.youngs_modulus_pa = spec.youngs_modulus_pa;
  input.fracture_toughness_pa_sqrt_m = spec.fracture_toughness_pa_sqrt_m;
  input.strength_pa = spec.strength_pa;
  input.pressure_pa = load.peak_pressure_pa;
  input.pattern_scale = spec.pattern_scale;
  input.max_growth_length_m = 0.5 * shorter;
  // A sliver of a pane (half its shorter side below two finest cells) grows at its half width.
  input.min_growth_length_m = std::min(kMinCellsPerGrowth * finest_cell, input.max_growth_length_m);

  PanePattern out;
  out.response =
      fracture::pane_fracture(input, pane_stress(spec, pane, load, 1.0, &out.solver_warnings));
  out.forced = spec.trigger == scene::FractureSpec::Trigger::always && !out.response.breaks;
  if (!out.response.breaks && !out.forced) return out;

  // The pattern's growth length: given, or eq. 5.5's scaled (forced panes below any stress
  // crack at the coarsest scale).
  double growth = out.response.growth_length_m;
  out.growth_length_clamped = out.response.clamped;
  if (spec.growth_length_m) {
    growth = std::clamp(*spec.growth_length_m, std::min(finest_cell, input.max_growth_length_m),
                        input.max_growth_length_m);
    out.growth_length_given = true;
    out.growth_length_clamped = growth != *spec.growth_length_m;
  } else if (!out.response.breaks) {
    growth = input.max_growth_length_m;
    out.growth_length_clamped = true;
  }
  out.growth_length_m = growth;

  fracture::FractureParams& params = out.params;
  params.width_m = width_m;
  params.height_m = height_m;
  const int grid = pattern_grid(spec.grid, longer, growth);
  const int cells_short = std::max(4, static_cast<int>(std::lround(grid * shorter / longer)));
  params.grid_x = width_m >= height_m ? grid : cells_short;
  params.grid_y = width_m >= height_m ? cells_short : grid;
  params.growth_length_m = growth;
  // An X at the pane's centre, where a framed pane cracks first (thesis §5.4.1): four tips
  // make an early death of the whole tree, which one segment's two tips can meet, unlikely.
  params.initial.shape = fracture::InitialCrack::Shape::cross;
  params.initial.length_m = std::min(2.0 * growth, 0.25 * shorter);
  params.branch_angle_deg = spec.branch_angle_deg;
  params.angle_variance_deg = spec.angle_variance_deg;
  params.wiggle_probability = spec.wiggle_probability;
  params.wiggle_variance_deg = spec.wiggle_variance_deg;
  params.wiggle_length_m = 0.0;  // = a_c: the whole pattern scales with the growth length
  params.seed = seed;

  // The pattern's kind (docs/fracture.md). Tempered glass falls into dice sized by its temper,
  // whatever broke it; annealed glass into radial cracks from the centre, as many as the plate's
  // stress lets branch, and rings where the petals they cut break under the pressure; a scene
  // that gives the growth length asks for the thesis's crack tree.
  using Kind = fracture::FractureParams::Kind;
  if (spec.surface_compression_pa > 0.0) {
    out.kind = params.kind = Kind::dice;
    out.dice_cell_m = params.dice_cell_m =
        fracture::dice_cell_m(spec.surface_compression_pa, spec.fracture_toughness_pa_sqrt_m);
  } else if (!spec.growth_length_m) {
    out.kind = params.kind = Kind::radial_ring;
    const fracture::RadialStar star =
        fracture::radial_star(width_m, height_m, out.response.plate.stress_pa);
    out.radial_cracks = star.count;
    out.branching_length_m = star.branching_length_m;
    const double rounded = std::round(star.count);
    out.radial_capped = rounded > fracture::FractureParams::kMaxRadialCracks;
    params.radial.count = static_cast<int>(
        std::clamp(rounded, 2.0, static_cast<double>(fracture::FractureParams::kMaxRadialCracks)));
    params.radial.ring_radii_m = fracture::ring_radii_m(
        load.peak_pressure_pa, spec.strength_pa, thickness_m, 0.5 * std::hypot(width_m, height_m));
  }
  return out;
}

double breaking_pressure_pa(const scene::FractureSpec& spec, const PaneSize& pane,
                            const PaneLoad& load) {
  assert(load.peak_pressure_pa > 0.0);
  const auto breaks = [&](double scale) {
    return pane_stress(spec, pane, load, scale).stress_pa > spec.strength_pa;
  };
  // Scale factors on the load; the stress grows with it (static: linearly; dynamic: the peak of a
  // hardening oscillator from rest grows with the load's amplitude).
  double low = 0.0, high = 1e3 / load.peak_pressure_pa;
  while (!breaks(high) && high * load.peak_pressure_pa < 1e12)
    high *= 2.0;
  // At most 200 halvings: the stress of a pane some 1e200 m wide overflows, so it breaks at any
  // pressure, and the interval shrank into the denormals where 1e-3 * high is 0 and the loop
  // never ended (`brisance fracture --width 1e200 ...` hung; found by fuzz_fracture). A pane
  // that breaks at all needs about 10.
  for (int halvings = 0; halvings < 200 && high - low > 1e-3 * high; ++halvings) {
    const double mid = 0.5 * (low + high);
    (breaks(mid) ? high : low) = mid;
  }
  return high * load.peak_pressure_pa;
}

}  // namespace brisance::engine
