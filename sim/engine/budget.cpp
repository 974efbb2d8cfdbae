// sim/engine/budget: the run's size as its bodies are created, against the scene limits and the
// memory budget (budget.hpp). The byte estimate follows the engine's own containers: what each
// body, panel and frame costs in the body sources, the Model, the run's state, the shielding
// pass and the Result. It leaves out the scene the caller holds and a writer's output.
#include <array>
#include <cmath>
#include <string>

#include "sim/engine/model.hpp"
#include "sim/occlusion/shielding.hpp"

namespace brisance::engine {

namespace {

std::string megabytes(std::uint64_t bytes) {
  return std::to_string((bytes + (1u << 20) - 1) >> 20) + " MB";
}

}  // namespace

BudgetTally::BudgetTally(const RunBudget& budget, const scene::Scene& scene)
    : budget_(budget), charges_(scene.charges.size()) {
  const scene::SimulationSpec& sim = scene.simulation;
  frames_ = static_cast<std::uint64_t>(std::floor(sim.duration_s * sim.frame_rate_hz + 1e-9)) + 1;
}

BudgetTally::BodySize BudgetTally::size_of(const BodySource& source) {
  BodySize size;
  size.vertices = source.mesh.vertices.size();
  size.triangles = source.mesh.triangles.size();
  size.load_panels = source.load_panels.size();
  size.drag_panels = source.drag_panels.size();
  size.name_bytes = source.name.size();
  size.anchored = source.anchored;
  size.fragment = source.fragment;
  return size;
}

std::uint64_t BudgetTally::bytes_of(const BodySize& size) const {
  // The mesh: its vertices in the source (then the result), as hull points, and twice in the
  // shielding pass (world vertices and the occlusion object's copy); its triangles there too.
  std::uint64_t bytes = size.vertices * sizeof(Vec3) * 4 +
                        size.triangles * sizeof(std::array<std::uint32_t, 3>) * 2 +
                        (size.load_panels + size.drag_panels) * sizeof(geometry::Panel);
  // Each load panel: the Model's, the clearing search's world plane, index and disjoint set
  // (80 B), the shielding pass's, its loaded flag; per charge its event and shielding factor.
  bytes += size.load_panels * (sizeof(PanelModel) + 80 + sizeof(occlusion::Panel) + 1 +
                               charges_ * (sizeof(PanelEvent) + sizeof(float)));
  // The body: its source, model, result entry and final state, three states (initial, running,
  // placed for contacts), three load sums (this step's, deferred, peak), the Model's and the
  // run's per-body scalars and a contact shape (256 B), and its name three times.
  bytes += sizeof(BodySource) + sizeof(dynamics::BodyModel) + sizeof(BodyInfo) +
           sizeof(FinalState) + 3 * sizeof(dynamics::BodyState) + 3 * sizeof(dynamics::StepLoads) +
           256 + 3 * size.name_bytes + charges_ * sizeof(float);
  // Frames: a movable body's pose in every frame while recording, and again in the Result's
  // frames if it moved (all may).
  if (!size.anchored) bytes += frames_ * sizeof(Pose) * 2;
  return bytes;
}

void BudgetTally::add(const BodySize& size, std::uint64_t copies) {
  bodies_ += copies;
  if (size.fragment) fragments_ += copies;
  panels_ += size.load_panels * copies;
  bytes_ += bytes_of(size) * copies;
  check();
}

void BudgetTally::check() const {
  const scene::Limits& limits = budget_.limits;
  const auto stop = [](OverBudget::Kind kind, std::string message) {
    throw RunOverBudget{OverBudget{kind, std::move(message)}};
  };
  if (fragments_ > limits.max_fragments)
    stop(OverBudget::Kind::limit,
         "breaking the scene's panes makes more than " + std::to_string(limits.max_fragments) +
             " fragments (the limit max_fragments); give the panes larger fragments "
             "(fracture.growth_length grows the crack tree instead of radial cracks), "
             "break fewer panes, or use smaller tempered panes (their dice are set by the "
             "temper)");
  if (panels_ > limits.max_panels)
    stop(OverBudget::Kind::limit,
         "the scene's objects and the fragments of its panes make more than " +
             std::to_string(limits.max_panels) +
             " load panels (the limit max_panels); raise simulation.max_panel_area, give the "
             "panes larger fragments (fracture.growth_length) or use fewer objects");
  if (static_cast<double>(frames_) * static_cast<double>(bodies_) >
      static_cast<double>(limits.max_frame_samples))
    stop(OverBudget::Kind::limit,
         std::to_string(frames_) + " frames x " + std::to_string(bodies_) +
             " bodies (fragments counted) is more than the limit max_frame_samples = " +
             std::to_string(limits.max_frame_samples) +
             "; shorten simulation.duration, lower simulation.frame_rate, or give the panes "
             "larger fragments (fracture.growth_length)");
  if (budget_.memory_bytes > 0 && bytes_ > budget_.memory_bytes)
    stop(OverBudget::Kind::memory,
         "the run would hold about " + megabytes(bytes_) + " for " + std::to_string(bodies_) +
             " bodies so far (" + std::to_string(fragments_) + " fragments), their panels and " +
             std::to_string(frames_) + " frames, over the job memory budget of " +
             megabytes(budget_.memory_bytes) +
             "; lower simulation.frame_rate or duration, use fewer bodies or give the panes "
             "larger fragments (fracture.growth_length)");
}

}  // namespace brisance::engine
