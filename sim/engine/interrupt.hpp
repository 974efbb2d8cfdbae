// sim/engine/interrupt (private to the engine): how a run stops before its end in any phase —
// breaking panes, every prepare stage, stepping. The RunHooks::cancel_requested hook (a cancel,
// the job's time limit) is polled at checkpoints some microseconds to a millisecond of work
// apart. A stop unwinds the prepare stages by an exception that simulate() alone catches: the
// stages stay free of stop paths of their own, and nothing half built is ever used. (Returned
// flags through every stage were the alternative: each stage and each loop in it would need its
// own exit, and a missed one runs on unbounded.)
#pragma once

#include <cstdint>
#include <functional>
#include <utility>

#include "sim/engine/budget.hpp"

namespace brisance::engine {

// Thrown by Checkpoint::poll when the hook asks the run to stop.
struct RunCancelled {};

// Thrown by BudgetTally when the run would grow past its budget.
struct RunOverBudget {
  OverBudget what;
};

class Checkpoint {
 public:
  explicit Checkpoint(std::function<bool()> cancel_requested = {})
      : cancel_requested_(std::move(cancel_requested)) {}

  // Whether the run should stop now (the hook says so); for sim/fracture, which knows no engine.
  bool requested() const { return cancel_requested_ && cancel_requested_(); }
  // Throws RunCancelled when the run should stop.
  void poll() const {
    if (requested()) throw RunCancelled{};
  }
  // poll() once every `stride` calls: for loops whose body costs nanoseconds.
  void tick(std::uint32_t stride = 4096) {
    if (++ticks_ % stride == 0) poll();
  }
  // The same check as a callable, for modules that take a stop request.
  std::function<bool()> stop_request() const {
    return [this] { return requested(); };
  }

 private:
  std::function<bool()> cancel_requested_;
  std::uint64_t ticks_ = 0;
};

}  // namespace brisance::engine
