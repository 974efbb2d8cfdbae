// sim/engine/pane_pattern: how a breakable pane of a scene becomes a crack pattern — its stress
// under the blast (the dynamic large-deflection plate SDOF of sim/response/plate under the pane's
// pressure history, or Roark's static small-deflection stress under its peak pressure, as the
// scene's fracture.breakage says), whether it breaks, the growth length (thesis eq. 5.5, or the
// one given) and the crack-tree parameters. One function, so that `brisance fracture` previews
// exactly the pattern a job grows for the same pane, load and seed. The coupling of
// sim/response and sim/fracture lives here: neither includes the other.
#pragma once

#include <cstdint>

#include "sim/blast/blast_point.hpp"
#include "sim/blast/panel_load.hpp"
#include "sim/fracture/crack_tree.hpp"
#include "sim/fracture/pane.hpp"
#include "sim/response/sdof.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::engine {

// The pane: its size and density (the dynamic model's mass).
struct PaneSize {
  double width_m = 1.0;
  double height_m = 1.0;
  double thickness_m = 0.006;
  double density_kg_m3 = 2500.0;
};

// The load on the pane's face: the largest peak pressure (what the static model takes) and the
// summed pressure history, time since clock_start_s (what the dynamic model integrates).
struct PaneLoad {
  double peak_pressure_pa = 0.0;
  response::PressureLoad history;
  double clock_start_s = 0.0;  // the history's time 0 after detonation (the first arrival), s
};

// The clearing distance S of a pane's front face: half its shorter side. The engine's fragments
// of a pane keep it (prepare.cpp does not merge them into a surrounding surface), so the pane's
// own face is the surface it clears from, before and after it breaks.
double pane_clearing_distance_m(const PaneSize& pane);

// The pressure on the face of a pane that faces one charge, at the pane's centre, as the engine
// loads its fragments' front faces (sim/engine/run.cpp, Run::activate): the Kingery–Bulmash
// point at distance_m, the oblique reflection at the angle of incidence (cos_incidence, 0..1),
// and blast::front_face_history with `options` (pulse shape, clearing on or off, the clearing
// distance S, the drag coefficient C_D): the reflected pulse cleared over 3 S / U to the
// stagnation pressure (thesis eqs. 2.30-2.31, UFC 3-340-02 §2-15.3; t_c lengthened by
// blast::clearing_delay_s as for the engine's front panels), or uncleared when that
// carries less impulse or clearing is off. Arrives at the curves' arrival time.
struct PaneFaceLoad {
  double peak_pressure_pa = 0.0;  // P_r at the angle of incidence (the history's value at 0)
  response::LoadComponent component;
  bool in_range = true;  // the blast point lies inside every fitted range
};
PaneFaceLoad pane_face_load(const blast::Charge& charge, double distance_m, double cos_incidence,
                            const blast::PanelLoadOptions& options);

struct PanePattern {
  fracture::PaneFracture response;  // plate stress, breaks, a_c, eq. 5.5's growth length
  bool forced = false;              // trigger "always" broke a pane its stress does not
  double growth_length_m = 0.0;     // what the pattern is grown with
  bool growth_length_given = false;
  bool growth_length_clamped = false;
  std::size_t solver_warnings = 0;  // the dynamic model's (non-finite state, step cap)
  fracture::FractureParams params;  // valid when the pane breaks (or is forced)
  // The pattern's kind and sizes (docs/fracture.md): radial cracks and rings for annealed glass
  // (the thesis's crack tree when the scene gives fracture.growth_length), dice for tempered.
  fracture::FractureParams::Kind kind = fracture::FractureParams::Kind::crack_tree;
  double radial_cracks = 0.0;       // the star's arm count before rounding and the cap
  bool radial_capped = false;       // more than kMaxRadialCracks: capped
  double branching_length_m = 0.0;  // r_b = (A_b / sigma_e)^2 at the centre
  double dice_cell_m = 0.0;
};

// The pane's peak centre stress and deflection under `load` scaled by `load_scale`, by the
// spec's breakage model. `solver_warnings`, if given, counts the dynamic solver's warnings.
fracture::PlateResponse pane_stress(const scene::FractureSpec& spec, const PaneSize& pane,
                                    const PaneLoad& load, double load_scale = 1.0,
                                    std::size_t* solver_warnings = nullptr);

// The pattern's bit bucket: the scene's grid (cells along the pane's longer side) unless the
// growth length is shorter than kCellsPerGrowth of its cells; then finer, at most
// kFinestPatternGrid (the largest `fracture.grid` a scene may ask for; a finer grid given to
// `brisance fracture` stays). Eq. 5.5's growth length
// is clamped at kMinCellsPerGrowth cells of the finest grid: beyond that, pressure no longer
// refines the pattern (docs/fracture.md).
inline constexpr int kFinestPatternGrid = 4096;
inline constexpr double kCellsPerGrowth = 4.0;
inline constexpr double kMinCellsPerGrowth = 2.0;
int pattern_grid(int grid, double longer_m, double growth_length_m);

// The pane `spec` of `pane`'s size under `load`, its pattern grown from `seed`. The parameters
// are not validated here: a scene's spec was, and the CLI checks fracture::validate(params) with
// the flags it took.
PanePattern pane_pattern(const scene::FractureSpec& spec, const PaneSize& pane,
                         const PaneLoad& load, std::uint64_t seed);

// The lowest peak pressure that breaks the pane by its stress with `load`'s time shape: the load
// is scaled (bisection on pane_stress to 0.1 %) and the scaled peak returned, Pa. For the static
// model the shape does not matter. load.peak_pressure_pa must be > 0.
double breaking_pressure_pa(const scene::FractureSpec& spec, const PaneSize& pane,
                            const PaneLoad& load);

}  // namespace brisance::engine
