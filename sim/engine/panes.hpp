// sim/engine/panes (private to the engine): breaks the scene's breakable panes before prepare
// (DESIGN.md decision 9, thesis ch. 6). For each pane: the peak reflected pressure at its centre
// gives its bending stress (Roark table 11.4 case 1a, sim/fracture/pane); below the strength the
// pane stays one body and no fracture work is done (decision 10); above it a crack pattern is
// grown at the scale of thesis eq. 5.5 and every fragment becomes a prism body with closed-form
// mass properties, at least five load panels per face, a hold and the time the wave reaches it.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "sim/engine/result.hpp"
#include "sim/geometry/mesh.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::engine {

struct FragmentBody {
  std::uint32_t pane = 0;                    // index into BrokenScene::reports
  geometry::MassProperties unit_mass;        // at 1 kg/m^3, shape frame, closed form
  std::vector<geometry::Panel> load_panels;  // both faces (>= 5 each), shape frame
  std::vector<geometry::Panel> drag_panels;  // faces and side walls, for the flight drag
  double hold_n = 0.0;                       // the load it takes to break it free, N
  double arrival_time_s = 0.0;               // first wave at its centroid, s
  double frontal_area_m2 = 0.0;
};

struct BrokenScene {
  // The scene with every breakable pane resolved: broken panes replaced by their fragments
  // (named "<pane>/f<k>", in place of the pane), unbroken framed panes anchored. Only filled when
  // the scene has a breakable pane (`changed`); otherwise use the original scene.
  scene::Scene scene;
  bool changed = false;
  std::vector<std::int32_t> fragment_of;  // per object of `scene`: index into fragments or -1
  std::vector<FragmentBody> fragments;
  std::vector<PaneReport> reports;
  std::vector<std::pair<std::string, std::string>> warnings;  // code, message

  const scene::Scene& effective(const scene::Scene& source) const {
    return changed ? scene : source;
  }
};

BrokenScene break_panes(const scene::Scene& scene);

}  // namespace brisance::engine
