// sim/engine/budget: what a run may create and hold — the scene limits on what breaking panes
// adds (fragments, their panels, frames x bodies with the fragments counted) and a memory budget
// against an estimate of the bytes the run holds (meshes, panels, bodies, stored frames). The
// engine counts as the run grows, before it allocates the frames, and stops a run that would go
// past either (RunOutcome::over_budget) instead of growing on.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>

#include "sim/engine/pane_pattern.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::engine {

struct RunBudget {
  scene::Limits limits;            // max_fragments, max_panels, max_frame_samples
  std::uint64_t memory_bytes = 0;  // the run's estimated bytes at most; 0: no budget
};

// Why a run stopped before its end for its size.
struct OverBudget {
  enum class Kind : std::uint8_t {
    limit,   // fragments, panels or frames x bodies past scene::Limits
    memory,  // the estimate past RunBudget::memory_bytes
  };
  Kind kind = Kind::limit;
  std::string message;  // what grew past what, and what to change
};

// A scene the run would certainly stop for its size, judged before it is queued
// (budget_estimate.cpp): `object` is the scene object (index into Scene::objects) at which the
// estimate passed a limit or the memory budget.
struct BudgetRefusal {
  std::size_t object = 0;
  OverBudget what;
};

// Counts what the run will at least create, in the order the run creates it, without breaking a
// pane: every object that is not a breakable pane exactly as the run counts it; a pane that stays
// whole likewise; a pane that breaks (the run's own stress and growth length, from the same load)
// as fewest_fragments(...) fragments of the smallest size a fragment can have. Every count and
// byte is at most the run's, so a scene refused here is one the run would stop; a scene accepted
// may still stop when its panes break. Cost: one plate model per breakable pane.
std::optional<BudgetRefusal> refuse_before_run(const scene::Scene& scene, const RunBudget& budget);

// A lower bound of the fragments a pane of width_m x height_m breaks into at this growth length
// (docs/service.md, "Run size"): 0.1 (width + height) / growth length, at least 1. Measured
// patterns give 0.22 to 13.9 times (width + height) / growth length.
std::uint64_t fewest_fragments(double width_m, double height_m, double growth_length_m);
// The same for a pane's planned pattern (pane_pattern): the crack tree's bound above at its
// growth length; a tempered pane's dice exactly (their grid); radial cracks and rings half the
// radial cracks (measured: 1.8 to 40 fragments per radial crack, tests/sim/engine/
// budget_estimate_test.cpp).
std::uint64_t fewest_fragments(const PanePattern& pattern, double width_m, double height_m);

}  // namespace brisance::engine
