// sim/engine/simulator: runs a validated scene — the prepare stages (body sources with broken
// panes, holds, clearing surfaces, panel events; see model.hpp), then impulse-exact stepping
// (run.cpp, DESIGN.md decision 6), then the fragment statistics.
#include "sim/engine/simulator.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstddef>
#include <utility>

#include "sim/engine/hazard.hpp"
#include "sim/engine/interrupt.hpp"
#include "sim/engine/model.hpp"
#include "sim/engine/run.hpp"

namespace brisance::engine {

namespace {

Distribution distribution_of(std::vector<double> values) {
  Distribution d;
  if (values.empty()) return d;
  std::sort(values.begin(), values.end());
  d.count = values.size();
  double sum = 0.0;
  for (double v : values)
    sum += v;
  d.mean = sum / static_cast<double>(values.size());
  // Nearest rank: the smallest value with at least p of the values at or below it.
  const auto rank = [&](double p) {
    const auto k = static_cast<std::size_t>(std::ceil(p * static_cast<double>(values.size())));
    return values[std::max<std::size_t>(k, 1) - 1];
  };
  d.min = values.front();
  d.p10 = rank(0.1);
  d.p50 = rank(0.5);
  d.p90 = rank(0.9);
  d.max = values.back();
  return d;
}

// Fragment statistics of every broken pane, once the run is over.
void report_fragments(const std::vector<BodySource>& sources, const RunState& run,
                      std::vector<PaneReport>& panes) {
  for (PaneReport& pane : panes) {
    if (!pane.broken) continue;
    std::vector<double> areas;
    std::vector<double> releases;
    std::vector<std::pair<double, double>> launched;  // area, launch speed
    double momentum = 0.0;
    double released_mass = 0.0;
    for (std::uint32_t b = pane.first_body; b < pane.first_body + pane.fragment_count; ++b) {
      const double frontal_area_m2 = sources[b].frontal_area_m2;
      areas.push_back(frontal_area_m2);
      const double release = run.release_time_s[b];
      pane.release_times_s.push_back(release);
      if (release < 0.0) continue;
      releases.push_back(release);
      // Still loaded when the run ended: its speed then.
      const double launch = run.launch_speed_m_s[b];
      const double speed = launch >= 0.0 ? launch : run.bodies[b].velocity.norm();
      launched.emplace_back(frontal_area_m2, speed);
      momentum += sources[b].mass_kg * speed;
      released_mass += sources[b].mass_kg;
    }
    pane.released = releases.size();
    if (released_mass > 0.0) pane.launch_speed_mass_weighted_m_s = momentum / released_mass;
    pane.frontal_area_m2 = distribution_of(std::move(areas));
    pane.release_time_s = distribution_of(std::move(releases));
    std::vector<double> speeds;
    for (const auto& [area, speed] : launched)
      speeds.push_back(speed);
    pane.launch_speed_m_s = distribution_of(std::move(speeds));
    std::sort(launched.begin(), launched.end());
    const std::size_t half = launched.size() / 2;
    double small = 0.0;
    double large = 0.0;
    for (std::size_t i = 0; i < launched.size(); ++i)
      (i < half ? small : large) += launched[i].second;
    if (half > 0) pane.launch_speed_smaller_half_m_s = small / static_cast<double>(half);
    if (launched.size() > half)
      pane.launch_speed_larger_half_m_s = large / static_cast<double>(launched.size() - half);
  }
}

}  // namespace

RunOutcome simulate(const scene::Scene& scene, const RunHooks& hooks, const RunBudget& budget) {
  const auto start = std::chrono::steady_clock::now();
  RunOutcome outcome;
  Result& result = outcome.result;
  WarningLog warnings;
  // Every body to create, breakable panes broken into their fragments (DESIGN.md decision 9).
  using Clock = std::chrono::steady_clock;
  const auto seconds_since = [](Clock::time_point from) {
    return std::chrono::duration<double>(Clock::now() - from).count();
  };
  // Cancel and the time limit reach every phase (interrupt.hpp): a stop in breaking panes or in
  // prepare unwinds to here; the step loop polls the same hook.
  Checkpoint checkpoint(hooks.cancel_requested);
  const auto stopped_in = [&](RunPhase phase) {
    outcome.cancelled = true;
    outcome.cancelled_in = phase;
    result.stats.wall_time_s = seconds_since(start);
    return std::move(outcome);
  };
  // What the run creates is counted as it is created, before prepare and the frames allocate
  // for it (budget.hpp).
  BudgetTally tally(budget, scene);
  BodySources sources;
  try {
    sources = body_sources(scene, checkpoint, &tally);
  } catch (const RunCancelled&) {
    return stopped_in(RunPhase::fracture);
  } catch (RunOverBudget& over) {
    outcome.over_budget = std::move(over.what);
    result.stats.wall_time_s = seconds_since(start);
    return outcome;
  }
  outcome.times.fracture_s = seconds_since(start);
  for (const auto& [code, message] : sources.warnings)
    warnings.add(code, message);
  result.fracture = std::move(sources.reports);
  for (const PaneReport& pane : result.fracture) {
    if (pane.broken) {
      ++result.stats.panes_broken;
      result.stats.fragments += pane.fragment_count;
    } else {
      ++result.stats.panes_not_broken;
    }
  }
  const auto prepare_start = Clock::now();
  Model model;
  try {
    model = prepare(scene, sources.bodies, result.bodies, result.stats, checkpoint,
                    &outcome.times.shielding_s);
  } catch (const RunCancelled&) {
    return stopped_in(RunPhase::prepare);
  }
  outcome.times.prepare_s = seconds_since(prepare_start) - outcome.times.shielding_s;
  result.stats.bodies = model.bodies.size();
  if (model.panels_inside_charges > 0)
    warnings.add(
        "charge_inside_object",
        "a charge overlaps an object: its centre is closer to a load panel than its own "
        "radius as a sphere of TNT; contact is the charge's surface touching the face, and "
        "loads from inside an object are not modelled (see docs/blast-model.md)",
        model.panels_inside_charges);
  if (!model.body_shielding.empty()) {
    const std::size_t bodies = model.bodies.size();
    for (std::uint32_t c = 0; c < model.charges.size(); ++c) {
      ChargeShielding& charge = result.shielding.emplace_back();
      charge.charge = c;
      for (std::uint32_t b = 0; b < bodies; ++b) {
        const float f = model.body_shielding[c * bodies + b];
        if (f < 1.0f) charge.bodies.push_back({b, f});
      }
    }
  }

  const auto stepping_start = Clock::now();
  Run run(model, result, warnings);
  outcome.cancelled = !run.execute(hooks);
  outcome.times.stepping_s = seconds_since(stepping_start);
  if (!outcome.cancelled) {
    report_fragments(sources.bodies, run.state(), result.fracture);
    rate_pane_hazards(scene, result);
  }
  result.warnings = warnings.list();
  result.stats.wall_time_s =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  if (hooks.progress && !outcome.cancelled) hooks.progress(1.0);
  return outcome;
}

}  // namespace brisance::engine
