// sim/dynamics/ground_contact: contact of a rigid body with the ground plane, with Coulomb
// friction and restitution, so debris comes to rest (DESIGN.md decision 7). One body at a time,
// in named stages (ground_contact.cpp): prepare contacts, the exact sticking solve, warm start,
// sequential-impulse sweeps (restitution as each contact's target normal speed), store impulses.
// Body-body contacts will reuse the sweep over the same kind of contact.
#pragma once

#include <array>
#include <vector>

#include "sim/dynamics/rigid_body.hpp"

namespace brisance::dynamics {

struct Ground {
  double height_m = 0.0;
  double friction = 0.5;
  double restitution = 0.2;
};

// The impulses each hull point took from the ground last step (normal, along x, along z; N s),
// so the next step starts from them (warm starting): a resting body's contact then settles in
// one or two sweeps instead of eight.
struct ContactMemory {
  std::vector<std::array<double, 3>> impulses;  // per hull point; zero where not touching
};

// Resolves contact of a body with the plane y = ground.height_m after a step: pushes it out of
// the ground and applies normal and friction impulses at the penetrating hull points. Without a
// bounce it first tries to bring every touching point to rest at once (the body stops, or turns
// about its edge or corner), which holds if no impulse pulls or leaves its Coulomb disc; else
// sequential impulses with accumulated clamping, warm-started from `memory` when given.
// Returns true if the body touches the ground.
bool resolve_ground_contact(const BodyModel& model, BodyState& state, const Ground& ground,
                            ContactMemory* memory = nullptr);

}  // namespace brisance::dynamics
