// sim/engine/budget: what a run may create and hold — the scene limits on what breaking panes
// adds (fragments, their panels, frames x bodies with the fragments counted) and a memory budget
// against an estimate of the bytes the run holds (meshes, panels, bodies, stored frames). The
// engine counts as the run grows, before it allocates the frames, and stops a run that would go
// past either (RunOutcome::over_budget) instead of growing on.
#pragma once

#include <cstdint>
#include <string>

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

}  // namespace brisance::engine
