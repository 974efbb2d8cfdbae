// sim/engine/prepare_shielding: the prepare stage of shielding (thesis chapter 4, sim/occlusion).
// Every body is projected around each charge as it stands at the start: what may shadow
// (`blocks`; a broken pane's fragments do not) and what is loaded (all but anchored bodies). A
// wall shields what stands behind it for the whole run, even once it flies: the wave passes in
// milliseconds, long before the debris moves far (thesis §4.2.2).
#include <algorithm>
#include <map>
#include <memory>
#include <mutex>
#include <utility>

#include "sim/engine/model.hpp"
#include "sim/occlusion/shielding.hpp"
#include "sim/occlusion/sphere_map.hpp"

namespace brisance::engine {

namespace {

// The sphere map of a resolution, built once per process (5.8 ms at the reference 32 x 28, more
// than the rest of a small scene's run) and shared by every run and worker thread: it is
// immutable once built.
const occlusion::SphereMap& sphere_map(int columns, int rows) {
  static std::mutex mutex;
  static std::map<std::pair<int, int>, std::unique_ptr<const occlusion::SphereMap>> maps;
  const std::lock_guard lock(mutex);
  auto& map = maps[{columns, rows}];
  if (!map) map = std::make_unique<const occlusion::SphereMap>(columns, rows);
  return *map;
}

}  // namespace

void prepare_shielding(const scene::SimulationSpec& simulation,
                       const std::vector<BodySource>& sources, Model& model, Stats& stats,
                       Checkpoint& checkpoint) {
  stats.occlusion_skipped = true;
  if (simulation.occlusion == scene::OcclusionMode::off || model.charges.empty() ||
      model.panels.empty())
    return;
  // World vertices of every body, and the objects as the occlusion pass sees them.
  std::vector<std::vector<Vec3>> world(sources.size());
  std::vector<occlusion::Object> objects(sources.size());
  for (std::size_t b = 0; b < sources.size(); ++b) {
    const BodySource& source = sources[b];
    const Quat q = source.orientation.normalized();
    world[b].reserve(source.mesh.vertices.size());
    for (const Vec3& v : source.mesh.vertices)
      world[b].push_back(source.position + q * v);
    objects[b].vertices = world[b];
    objects[b].triangles = source.mesh.triangles;
    objects[b].blocks = source.blocks;
    objects[b].receives = !source.anchored;
  }
  std::vector<occlusion::Panel> panels(model.panels.size());
  for (std::size_t p = 0; p < model.panels.size(); ++p) {
    const PanelModel& panel = model.panels[p];
    const BodySource& source = sources[panel.body];
    const Quat q = source.orientation.normalized();
    const Vec3 com = source.position + q * model.centre_of_mass[panel.body];
    panels[p] = occlusion::Panel{panel.body, com + q * panel.centre, panel.area_m2};
  }
  occlusion::Settings settings;
  settings.face_columns = simulation.shielding.resolution;
  settings.face_rows = std::max(2, (simulation.shielding.resolution * 7 + 4) / 8);
  settings.blocking_offset = simulation.shielding.blocking_offset;
  settings.separation_slope = simulation.shielding.separation_slope;
  settings.per_panel = simulation.shielding.per_panel;

  // Each body's bounding sphere, and what it may do before any charge is considered.
  std::vector<Vec3> centre(sources.size(), Vec3::Zero());
  std::vector<double> radius(sources.size(), 0.0);
  std::vector<std::uint8_t> blocks(sources.size()), receives(sources.size());
  for (std::size_t b = 0; b < sources.size(); ++b) {
    for (const Vec3& v : world[b])
      centre[b] += v;
    if (!world[b].empty()) centre[b] /= static_cast<double>(world[b].size());
    for (const Vec3& v : world[b])
      radius[b] = std::max(radius[b], (v - centre[b]).norm());
    blocks[b] = objects[b].blocks;
    receives[b] = objects[b].receives;
  }

  const bool forced = simulation.occlusion == scene::OcclusionMode::on;
  const occlusion::SphereMap* map = nullptr;  // for the first charge that needs it
  for (std::size_t c = 0; c < model.charges.size(); ++c) {
    checkpoint.poll();
    const Vec3& charge = model.charges[c].position;
    // A body wholly beyond the wave's reach at the end of the run takes no part for this
    // charge: none of its panels is loaded, and it shields none that is, as an occluder lies
    // in front of what it shields (its far side nearer the charge, within depth_tolerance_m)
    // and every loaded panel lies within the reach. Wide scenes need this: 16 walls 1 000 m
    // apart, each reached by its own charge only within 2 s, projected every body around every
    // charge (three times the prepare time of 16 single walls).
    const double reach = model.charges[c].reach_m + 2.0 * settings.depth_tolerance_m;
    for (std::size_t b = 0; b < sources.size(); ++b) {
      const bool reached = (centre[b] - charge).norm() - radius[b] <= reach;
      objects[b].blocks = blocks[b] && reached;
      objects[b].receives = receives[b] && reached;
    }
    if (!forced && !occlusion::footprints_may_overlap(charge, objects)) continue;
    if (!map) map = &sphere_map(settings.face_columns, settings.face_rows);
    const occlusion::Shielding shielding =
        occlusion::compute_shielding(*map, charge, objects, panels, settings);
    if (model.shielding.empty()) {
      model.shielding.assign(model.charges.size() * panels.size(), 1.0f);
      model.body_shielding.assign(model.charges.size() * sources.size(), 1.0f);
    }
    std::vector<double> weighted(sources.size(), 0.0), area(sources.size(), 0.0);
    for (std::size_t p = 0; p < panels.size(); ++p) {
      const double f = shielding.panel_attenuation[p];
      model.shielding[c * panels.size() + p] = static_cast<float>(f);
      weighted[panels[p].object] += f * panels[p].area_m2;
      area[panels[p].object] += panels[p].area_m2;
    }
    for (std::size_t b = 0; b < sources.size(); ++b)
      if (area[b] > 0.0)
        model.body_shielding[c * sources.size() + b] = static_cast<float>(weighted[b] / area[b]);
    stats.occlusion_skipped = false;
  }
}

}  // namespace brisance::engine
