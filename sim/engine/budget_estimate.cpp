// sim/engine/budget_estimate: the run's size judged before it runs (budget.hpp), so that the
// service refuses at submission a scene its run would certainly stop for, instead of queueing it.
// Everything here is a lower bound of what BudgetTally counts during the run: the bodies the
// scene lists are counted exactly, a pane that will break by at most the fragments it makes.
#include <algorithm>
#include <array>
#include <cmath>
#include <map>

#include "sim/engine/interrupt.hpp"
#include "sim/engine/model.hpp"
#include "sim/engine/panes.hpp"

namespace brisance::engine {

// Measured with `brisance fracture` over 800 random panes (0.1 to 2.5 m wide, aspect 1:10 to
// 10:1, growth lengths from 1 % to half the shorter side, every branch angle, angle variance,
// wiggle and grid a scene allows; tests/sim/engine/budget_estimate_test.cpp repeats a sample):
// fragments x growth length / (width + height) ran from 0.22 to 13.9. The crack front forks once
// per growth length grown and its tips end on the border, so the count follows the outline over
// the growth length. Half the smallest measured ratio leaves room for patterns not measured.
std::uint64_t fewest_fragments(double width_m, double height_m, double growth_length_m) {
  constexpr double kFragmentsPerOutline = 0.1;
  const double estimate = kFragmentsPerOutline * (width_m + height_m) / growth_length_m;
  if (!(estimate >= 1.0)) return 1;
  return static_cast<std::uint64_t>(std::min(std::floor(estimate), 1e15));
}

std::uint64_t fewest_fragments(const PanePattern& pattern, double width_m, double height_m) {
  using Kind = fracture::FractureParams::Kind;
  if (pattern.kind == Kind::dice) {
    // dice_pattern's grid: lround(side / cell) cells along each side, at least one.
    const double cell = pattern.params.dice_cell_m;
    const double nx = std::max(1.0, std::round(width_m / cell));
    const double ny = std::max(1.0, std::round(height_m / cell));
    return static_cast<std::uint64_t>(std::min(nx * ny, 1e15));
  }
  if (pattern.kind == Kind::radial_ring)
    return static_cast<std::uint64_t>(std::max(1, pattern.params.radial.count / 2));
  return fewest_fragments(width_m, height_m, pattern.growth_length_m);
}

std::optional<BudgetRefusal> refuse_before_run(const scene::Scene& scene, const RunBudget& budget) {
  BudgetTally tally(budget, scene);
  std::vector<ChargeModel> charges;
  for (const scene::ChargeSpec& spec : scene.charges)
    charges.push_back({spec.position, blast_charge(spec)});
  const double max_panel_area_m2 = scene.simulation.max_panel_area_m2;
  // Equal boxes (a wall has two sizes) are cut into panels once.
  std::map<std::array<double, 3>, std::uint64_t> box_panels;
  const auto panels_of = [&](const scene::ObjectSpec& object) -> std::uint64_t {
    if (object.shape != scene::ShapeType::box)
      return geometry::count_panels(object.mesh, max_panel_area_m2);
    const std::array<double, 3> size = {object.box_size_m.x(), object.box_size_m.y(),
                                        object.box_size_m.z()};
    auto [it, inserted] = box_panels.try_emplace(size, 0);
    if (inserted) it->second = geometry::count_panels(object.mesh, max_panel_area_m2);
    return it->second;
  };
  for (std::size_t index = 0; index < scene.objects.size(); ++index) {
    const scene::ObjectSpec& object = scene.objects[index];
    // The body as object_source makes it (a framed pane that stays whole is anchored).
    BudgetTally::BodySize whole;
    whole.vertices = object.mesh.vertices.size();
    whole.triangles = object.mesh.triangles.size();
    whole.name_bytes = object.name.size();
    whole.anchored = object.anchored;
    try {
      if (!object.fracture) {
        whole.load_panels = panels_of(object);
        tally.add(whole);
        continue;
      }
      // A breakable pane: judged as break_pane judges it (the same load, stress and growth
      // length), without growing its pattern.
      const scene::FractureSpec& spec = *object.fracture;
      const double width = object.box_size_m.x();
      const double height = object.box_size_m.y();
      const double thickness = object.box_size_m.z();
      const Vec3 normal = object.orientation.normalized() * Vec3::UnitZ();
      bool out_of_range = false;
      const PaneSize size{width, height, thickness, object.mass_kg / (width * height * thickness)};
      Vec3 push;
      const PaneLoad load =
          pane_load_at(object.position, normal, charges,
                       pane_load_options(object, scene.simulation, size), out_of_range, push);
      const PanePattern pattern = pane_pattern(spec, size, load, 1);
      if (!pattern.response.breaks && !pattern.forced) {
        whole.load_panels = panels_of(object);
        whole.anchored = whole.anchored || spec.framed;
        tally.add(whole);
        continue;
      }
      // Its fragments, each no smaller than the least a fragment can be: a triangular prism
      // (6 vertices, 8 triangles), one load panel on each face (a fragment under 2 cm or
      // crossed within 2 cm of path; others have 5 to 16), its two faces and three sides for drag,
      // named "<pane>/f<k>".
      BudgetTally::BodySize fragment;
      fragment.vertices = 6;
      fragment.triangles = 8;
      fragment.load_panels = 2;
      fragment.drag_panels = 5;
      fragment.name_bytes = object.name.size() + 3;
      fragment.fragment = true;
      tally.add(fragment, fewest_fragments(pattern, width, height));
    } catch (RunOverBudget& over) {
      return BudgetRefusal{index, std::move(over.what)};
    }
  }
  return std::nullopt;
}

}  // namespace brisance::engine
