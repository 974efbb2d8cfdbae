// sim/engine/body_sources: the first prepare stage — every scene object becomes one body
// source, except breakable panes, which panes.cpp breaks into fragment sources (or leaves one
// body). Prepare then builds all bodies from this one list. Also the one charge → blast charge
// conversion.
#include <algorithm>

#include "sim/engine/model.hpp"
#include "sim/engine/panes.hpp"

namespace brisance::engine {

blast::Charge blast_charge(const scene::ChargeSpec& spec) {
  blast::Charge charge;
  charge.tnt_equivalent_kg = spec.mass_kg * spec.tnt_factor;
  charge.impulse_tnt_equivalent_kg = spec.mass_kg * spec.impulse_tnt_factor;
  charge.burst = spec.burst;
  charge.surface_model = spec.surface_model;
  return charge;
}

Box world_box(const BodySource& source) {
  Box box{Vec3::Constant(INFINITY), Vec3::Constant(-INFINITY)};
  for (const Vec3& v : source.mesh.vertices) {
    const Vec3 p = source.position + source.orientation * v;
    box.min = box.min.cwiseMin(p);
    box.max = box.max.cwiseMax(p);
  }
  return box;
}

BodySource object_source(const scene::ObjectSpec& object, double max_panel_area_m2) {
  BodySource source;
  source.name = object.name;
  source.material = object.material;
  source.mesh = object.mesh;
  source.position = object.position;
  source.orientation = object.orientation;
  source.mass_kg = object.mass_kg;
  source.friction = object.friction;
  source.drag_coefficient = object.drag_coefficient;
  source.anchored = object.anchored;
  source.blocks = object.blocks;
  source.rotates = object.rotates;
  source.sheltered = object.sheltered;
  source.unit_mass = geometry::mass_properties(object.mesh, 1.0);
  source.load_panels = geometry::make_panels(object.mesh, max_panel_area_m2);
  return source;
}

BodySources body_sources(const scene::Scene& scene, Checkpoint& checkpoint, BudgetTally* tally) {
  BodySources sources;
  sources.bodies.reserve(scene.objects.size());
  std::vector<ChargeModel> charges;
  for (const scene::ChargeSpec& spec : scene.charges)
    charges.push_back({spec.position, blast_charge(spec)});
  bool out_of_range = false;
  bool large_deflection = false;
  std::size_t solver_warnings = 0;
  for (std::size_t index = 0; index < scene.objects.size(); ++index) {
    const scene::ObjectSpec& object = scene.objects[index];
    checkpoint.tick(64);  // a pane breaking polls on its own; other objects cost microseconds
    if (!object.fracture) {
      sources.bodies.push_back(object_source(object, scene.simulation.max_panel_area_m2));
      if (tally) tally->add(sources.bodies.back());
      continue;
    }
    // Breakable panes (DESIGN.md decision 9): a broken pane's fragments take its place. They are
    // counted as soon as the pane is broken, so a run past its budget stops within one pane.
    const std::size_t first = sources.bodies.size();
    PaneReport report = break_pane(object, index, charges, scene.simulation, sources.bodies,
                                   out_of_range, solver_warnings, checkpoint);
    if (tally)
      for (std::size_t b = first; b < sources.bodies.size(); ++b)
        tally->add(sources.bodies[b]);
    // Only the static model's stress is an upper estimate beyond small deflections.
    if (object.fracture->breakage == scene::FractureSpec::Breakage::static_plate)
      large_deflection = large_deflection || !report.small_deflection;
    sources.reports.push_back(std::move(report));
  }
  if (out_of_range) sources.warnings.emplace_back("blast_out_of_range", kBlastOutOfRangeMessage);
  if (large_deflection)
    sources.warnings.emplace_back(
        "pane_large_deflection",
        "a pane's small-deflection bending stress (Roark table 11.4) implies a deflection beyond "
        "half its thickness, where membrane action carries part of the load: its stress, and "
        "with it the fracture scale, is an upper estimate (docs/fracture.md; fracture.breakage "
        "\"dynamic\" takes membrane action into account)");
  if (solver_warnings > 0)
    sources.warnings.emplace_back(
        "pane_response_incomplete",
        "the dynamic plate model of a pane met a non-finite state or its step cap: its peak "
        "stress covers only part of the load (docs/fracture.md)");
  return sources;
}

}  // namespace brisance::engine
