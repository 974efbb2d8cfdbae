// sim/engine/simulator: runs a validated scene — prepare (bodies, panels, the arrival-ordered
// panel events), then impulse-exact stepping (DESIGN.md decision 6) with frames sampled at exact
// multiples of 1 / frame_rate, skipping whatever the scene does not need (decision 10).
#pragma once

#include <cstdint>
#include <functional>
#include <optional>

#include "sim/engine/budget.hpp"
#include "sim/engine/result.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::engine {

struct RunHooks {
  // Called with the fraction of simulated time done (0..1), at most about 200 times a run.
  std::function<void(double fraction)> progress;
  // Polled in every phase — while breaking panes (between crack-growth steps and fragments),
  // in each prepare stage and once per step — some microseconds to a millisecond of work apart;
  // returning true stops the run there. Once it returned true it must keep doing so.
  std::function<bool()> cancel_requested;
};

// Where a run was when it stopped before its end.
enum class RunPhase : std::uint8_t {
  fracture,  // breaking the panes (body sources)
  prepare,   // bodies, panels, holds, clearing, shielding, events
  stepping,
};

// Wall-clock time of each stage of a run, s: what a benchmark breaks the run down by. Kept out of
// the Result, whose contents depend on the scene alone.
struct StageTimes {
  double fracture_s = 0.0;   // body sources: breaking the panes into fragments
  double prepare_s = 0.0;    // bodies, panels, holds, clearing, events (shielding apart)
  double shielding_s = 0.0;  // the occlusion pass (thesis ch. 4)
  double stepping_s = 0.0;   // the stepping loop and the frames
};

struct RunOutcome {
  Result result;  // complete unless cancelled or over budget
  bool cancelled = false;
  RunPhase cancelled_in = RunPhase::stepping;  // when cancelled
  // Set when the run stopped because it would grow past its budget (breaking panes made more
  // fragments, panels or frame samples than the limits allow, or the memory estimate passed
  // the budget); the result is then incomplete.
  std::optional<OverBudget> over_budget;
  StageTimes times;
};

// `budget`: the limits on what the run creates (by default scene::Limits's) and its memory
// budget (by default none).
RunOutcome simulate(const scene::Scene& scene, const RunHooks& hooks = {},
                    const RunBudget& budget = {});

}  // namespace brisance::engine
