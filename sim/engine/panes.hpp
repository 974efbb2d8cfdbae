// sim/engine/panes (private to the engine): the prepare stage that breaks one breakable pane
// (DESIGN.md decision 9, thesis ch. 6). The reflected pressure at its centre gives its peak
// stress (pane_pattern: the dynamic plate SDOF, or Roark's static stress); below the strength the
// pane stays one body and no fracture work is done (decision 10); above it a crack pattern is grown
// at the scale of thesis eq. 5.5 and every fragment becomes a body source: a prism with closed-form
// mass properties, at least five load panels per face, a hold and the time the wave reaches it.
#pragma once

#include <cstdint>
#include <vector>

#include "sim/engine/model.hpp"
#include "sim/engine/pane_pattern.hpp"

namespace brisance::engine {

// A scene object as a body source, its panels cut at max_panel_area_m2.
BodySource object_source(const scene::ObjectSpec& object, double max_panel_area_m2);

// How a pane's front face is loaded, as the engine loads its fragments' (run.cpp, prepare.cpp):
// the scene's pulse shape and clearing switch, S from the pane's own edges, the object's C_D.
blast::PanelLoadOptions pane_load_options(const scene::ObjectSpec& object,
                                          const scene::SimulationSpec& simulation,
                                          const PaneSize& size);

// The load on the pane with centre `centre` and unit normal `normal` (world frame) from
// `charges` with `options`: what break_pane judges the pane by (panes.cpp). Sets `out_of_range`
// as break_pane does and `push` to the direction the largest peak pushes the pane.
PaneLoad pane_load_at(const Vec3& centre, const Vec3& normal,
                      const std::vector<ChargeModel>& charges,
                      const blast::PanelLoadOptions& options, bool& out_of_range, Vec3& push);

// Breaks the pane `object` (scene object `index`), appending its body sources
// to `out`: the fragments (named "<pane>/f<k>"), or the pane itself unbroken (anchored when
// framed). Sets `out_of_range` when a charge's blast point lies outside the fitted range and
// adds the dynamic plate solver's warnings to `solver_warnings`. Polls `checkpoint` after the
// plate model, during crack growth and between fragments.
PaneReport break_pane(const scene::ObjectSpec& object, std::size_t index,
                      const std::vector<ChargeModel>& charges,
                      const scene::SimulationSpec& simulation, std::vector<BodySource>& out,
                      bool& out_of_range, std::size_t& solver_warnings, Checkpoint& checkpoint);

}  // namespace brisance::engine
