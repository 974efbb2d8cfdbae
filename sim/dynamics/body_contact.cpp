// sim/dynamics/body_contact: sequential impulses over contacts between bodies, in stages —
//   prepare    arms, tangents, effective masses, target normal speeds (restitution, gaps)
//   warm start last step's impulses by contact key, friction kept inside its Coulomb disc
//   sweeps     accumulated clamping, until a sweep changes no body's velocity by more than
//              30 um/s or 0.3 % of the island's slowest body's speed
//   runaway    a solve that did not converge and left a body faster than twice the island's
//              fastest, done again: without friction, then with friction capped by that pass
//   positions  the penetration beyond the slop, removed by shifts along the normals
#include "sim/dynamics/body_contact.hpp"

#include <algorithm>
#include <cmath>

#include "sim/dynamics/coulomb.hpp"
#include "sim/dynamics/sticking.hpp"

namespace brisance::dynamics {

namespace {

inline std::size_t slot_of(std::uint64_t key, std::size_t mask) {
  return static_cast<std::size_t>((key * 0x9E3779B97F4A7C15ull) >> 32) & mask;
}

}  // namespace

void ContactImpulses::seal() {
  std::size_t size = 16;
  while (size < 2 * entries_.size())
    size *= 2;
  slots_.assign(size, 0);
  const std::size_t mask = size - 1;
  for (std::size_t i = 0; i < entries_.size(); ++i) {
    std::size_t slot = slot_of(entries_[i].key, mask);
    // Linear probing; a key added again takes over its slot (the last added is kept).
    while (slots_[slot] != 0 && entries_[slots_[slot] - 1].key != entries_[i].key)
      slot = (slot + 1) & mask;
    slots_[slot] = static_cast<std::uint32_t>(i + 1);
  }
}

const Vec3* ContactImpulses::find(std::uint64_t key) const {
  if (slots_.empty()) return nullptr;
  const std::size_t mask = slots_.size() - 1;
  for (std::size_t slot = slot_of(key, mask); slots_[slot] != 0; slot = (slot + 1) & mask)
    if (entries_[slots_[slot] - 1].key == key) return &entries_[slots_[slot] - 1].impulse;
  return nullptr;
}

namespace {

// The speed of b relative to a at the contact along direction k (0 normal, 1 u, 2 v).
inline double relative_speed(const SolverBody& a, const SolverBody& b, const ContactRow& r,
                             const Vec3& direction, int k) {
  return direction.dot(b.velocity - a.velocity) + r.lever_b[k].dot(b.omega) -
         r.lever_a[k].dot(a.omega);
}

// An impulse j along direction k on b (and -j on a).
inline void apply(SolverBody& a, SolverBody& b, const ContactRow& r, const Vec3& direction, int k,
                  double j) {
  a.velocity -= (j * a.inverse_mass) * direction;
  a.omega -= j * r.spin_a[k];
  b.velocity += (j * b.inverse_mass) * direction;
  b.omega += j * r.spin_b[k];
}

// The friction directions' spins and effective masses, left until a contact first has a normal
// impulse to bound its friction (over half of the contacts on the brick wall never do: gaps
// within the margin, or pulled apart). The same arithmetic as for the normal, in the same order.
inline void prepare_friction(const std::vector<SolverBody>& bodies, ContactRow& r) {
  const SolverBody& a = bodies[r.a];
  const SolverBody& b = bodies[r.b];
  std::array<double, 3> masses;
  for (int k = 1; k < 3; ++k) {
    r.spin_a[k] = (r.moves & 1) ? Vec3(a.inverse_inertia * r.lever_a[k]) : Vec3::Zero();
    r.spin_b[k] = (r.moves & 2) ? Vec3(b.inverse_inertia * r.lever_b[k]) : Vec3::Zero();
    masses[k] = 1.0 / (a.inverse_mass + b.inverse_mass + r.lever_a[k].dot(r.spin_a[k]) +
                       r.lever_b[k].dot(r.spin_b[k]));
  }
  r.mass_u = masses[1];
  r.mass_v = masses[2];
  r.friction_ready = true;
}

// One contact's step of a sweep: its normal impulse, then its friction on the disc of the
// normal impulse, each accumulated and clamped. Specialised on which bodies move: a static
// partner's velocities are zero and stay zero, so the terms it would add are exactly zero and
// are left out (the same numbers, fewer loads; most contacts late in a run are with the
// ground or a sleeping body).
template <bool AMoves, bool BMoves, bool Capped>
inline void sweep_row(std::vector<SolverBody>& bodies, ContactRow& r) {
  SolverBody& a = bodies[r.a];
  SolverBody& b = bodies[r.b];
  Vec3 va = Vec3::Zero(), wa = Vec3::Zero(), vb = Vec3::Zero(), wb = Vec3::Zero();
  if constexpr (AMoves) {
    va = a.velocity;
    wa = a.omega;
  }
  if constexpr (BMoves) {
    vb = b.velocity;
    wb = b.omega;
  }
  // The speed of b relative to a along direction k. A static side's terms are +0 (zero levers
  // times zero velocities): left out where that leaves every result, signed zeros included, as
  // it was (x - (+0) is x), kept as +0 where it does not (-0 + (+0) is +0).
  auto speed_along = [&](const Vec3& direction, int k) {
    double s;
    if constexpr (AMoves && BMoves)
      s = direction.dot(vb - va) + r.lever_b[k].dot(wb) - r.lever_a[k].dot(wa);
    else if constexpr (BMoves)
      s = direction.dot(vb) + r.lever_b[k].dot(wb);
    else
      s = direction.dot(vb - va) + 0.0 - r.lever_a[k].dot(wa);
    return s;
  };
  const double vn = speed_along(r.normal, 0);
  const double accumulated =
      std::max(r.normal_impulse + (r.target_speed - vn) * r.mass_normal, 0.0);
  const double dn = accumulated - r.normal_impulse;
  // A contact held apart with nothing to undo (most speculative ones, sweep after sweep):
  // no impulse changes, so no velocity does.
  if (dn == 0.0 && accumulated == 0.0 && r.friction_u == 0.0 && r.friction_v == 0.0) return;
  r.normal_impulse = accumulated;
  if constexpr (AMoves) {
    va -= (dn * r.inverse_mass_a) * r.normal;
    wa -= dn * r.spin_a[0];
  }
  if constexpr (BMoves) {
    vb += (dn * r.inverse_mass_b) * r.normal;
    wb += dn * r.spin_b[0];
  }
  // Friction on the disc of the normal impulse (none without one: a gap, or a contact pulled
  // apart, which is most speculative contacts; skipped, it spares the clamp's root).
  // (Capped: the friction bound may not grow with the normal impulse beyond friction_cap.)
  const double limit =
      r.friction * (Capped ? std::min(r.normal_impulse, r.friction_cap) : r.normal_impulse);
  double fu = 0.0, fv = 0.0;
  if (limit > 0.0) {
    if (!r.friction_ready) prepare_friction(bodies, r);
    fu = r.friction_u - speed_along(r.u, 1) * r.mass_u;
    fv = r.friction_v - speed_along(r.v, 2) * r.mass_v;
    clamp_to_friction_disc(fu, fv, limit);
  }
  const double du = fu - r.friction_u, dv = fv - r.friction_v;
  r.friction_u = fu;
  r.friction_v = fv;
  const Vec3 push = du * r.u + dv * r.v;
  // Nothing is written to a static partner (zero inverse mass and inertia: its velocities do
  // not change). The engine's static partners are all one solver body: a store there chained
  // every contact with a static partner to the one before it through memory, and the sweep's
  // contacts could not overlap in the processor.
  if constexpr (AMoves) {
    a.velocity = va - r.inverse_mass_a * push;
    a.omega = wa - du * r.spin_a[1] - dv * r.spin_a[2];
  }
  if constexpr (BMoves) {
    b.velocity = vb + r.inverse_mass_b * push;
    b.omega = wb + du * r.spin_b[1] + dv * r.spin_b[2];
  }
}

// The kinetic energy of the island's bodies, their mass (added to `mass`), and their
// velocities and world inertias kept in `buffers` for keep_passive. (Out of line, as is
// keep_passive: in the solve they pushed the sweeps' vector arithmetic out of GCC's inlining
// budget, 3 % more instructions on the brick wall.)
[[gnu::noinline]] double start_energy(const std::vector<SolverBody>& bodies,
                                      const std::vector<std::uint32_t>& island,
                                      PairSolveBuffers& buffers, double& mass) {
  const std::size_t size = island.size();
  buffers.start_velocity.resize(size);
  buffers.start_omega.resize(size);
  buffers.inertia.resize(size);
  double energy = 0.0;
  if (buffers.slot.size() < bodies.size()) buffers.slot.resize(bodies.size());
  for (std::size_t k = 0; k < size; ++k) {
    const SolverBody& body = bodies[island[k]];
    buffers.slot[island[k]] = static_cast<std::uint32_t>(k);
    buffers.start_velocity[k] = body.velocity;
    buffers.start_omega[k] = body.omega;
    const bool turns = body.inverse_inertia != Mat3::Zero();
    buffers.inertia[k] = turns ? Mat3(body.inverse_inertia.inverse()) : Mat3::Zero();
    mass += 1.0 / body.inverse_mass;
    energy += 0.5 * body.velocity.squaredNorm() / body.inverse_mass +
              0.5 * body.omega.dot(buffers.inertia[k] * body.omega);
  }
  return energy;
}

// Passivity: contacts (restitution at most 1, friction, gaps closed no faster than they allow)
// take kinetic energy from an island, never give it. A solve that gives more than 1 % and
// `slack` (a step's gravity, J) has failed, and its impulses are scaled down until it does
// not: the contacts are linear in the step, and a sliver spun to hundreds of rad/s by striking
// a wall turns a radian or more in one; without this, its next contact sent it off at 4 km/s
// and 7 million rad/s (window.json's fragments against a wall, docs/simulator.md). Measured on
// the brick wall and the stacking tests, no island gained more than 0.015 %.
[[gnu::noinline]] void keep_passive(std::vector<SolverBody>& bodies,
                                    const std::vector<std::uint32_t>& island,
                                    std::vector<ContactRow>& rows, PairSolveBuffers& buffers,
                                    double energy_before, double slack) {
  // The energy with the velocity changes scaled by s: before + s cross + s^2 square.
  double cross = 0.0, square = 0.0;
  for (std::size_t k = 0; k < island.size(); ++k) {
    const SolverBody& body = bodies[island[k]];
    const double m = 1.0 / body.inverse_mass;
    const Vec3 dv = body.velocity - buffers.start_velocity[k];
    const Vec3 dw = body.omega - buffers.start_omega[k];
    const Mat3& inertia = buffers.inertia[k];
    cross += m * buffers.start_velocity[k].dot(dv) + buffers.start_omega[k].dot(inertia * dw);
    square += 0.5 * (m * dv.squaredNorm() + dw.dot(inertia * dw));
  }
  const double allowed = 1.01 * energy_before + slack;
  if (!(energy_before + cross + square > allowed && square > 0.0)) return;
  // The positive root of square s^2 + cross s + (before - allowed) = 0 (below 1: E(1) is above
  // what is allowed, E(0) below).
  const double s = (-cross + std::sqrt(cross * cross + 4.0 * square * (allowed - energy_before))) /
                   (2.0 * square);
  for (std::size_t k = 0; k < island.size(); ++k) {
    SolverBody& body = bodies[island[k]];
    body.velocity = buffers.start_velocity[k] + s * (body.velocity - buffers.start_velocity[k]);
    body.omega = buffers.start_omega[k] + s * (body.omega - buffers.start_omega[k]);
  }
  for (ContactRow& r : rows) {
    r.normal_impulse *= s;
    r.friction_u *= s;
    r.friction_v *= s;
  }
  ++buffers.energy_limited;
}

// Turns the solve leaves to the position pass exactly rather than linearly, rad: the linear
// part of a turn th moves a point at arm r by up to r th^2 / 2 more than the turn does, 0.5 um
// at 1e-3 rad on a 1 m arm, a thousandth of the slop.
constexpr double kExactTurn_rad = 1e-3;

// Limits on the motion the solve leaves each body of the island (scaling a velocity down takes
// energy, never gives). Turns: the most a body may turn in a step with the spin the contacts
// left it, rad, unless it turned faster before: a quarter turn, Box2D's b2_maxRotation. Contacts
// are found once a step; a sliver struck on an edge (a lever of a millimetre or two) is spun by the
// one impulse to thousands of rad/s, turning many times within the step, where in fact its next
// edge would meet the wall within a quarter turn and take the spin back out.
constexpr double kMaxContactTurn_rad = 0.25 * 3.14159265358979323846;

// The fastest any body of the island may leave the solve: twice the island's fastest body
// before it, plus a step's gravity (a heavy body striking a light one at rest, perfectly
// elastic, gives it twice its speed). A guard, not a law (a column of ever lighter bodies
// passes more on).
double speed_bound(const PairSolveBuffers& buffers, std::size_t island_size, double dt,
                   double gravity_m_s2) {
  double fastest = 0.0;
  for (std::size_t k = 0; k < island_size; ++k)
    fastest = std::max(fastest, buffers.start_velocity[k].norm());
  return 2.0 * fastest + gravity_m_s2 * dt;
}

[[gnu::noinline]] void limit_motion(std::vector<SolverBody>& bodies,
                                    const std::vector<std::uint32_t>& island,
                                    PairSolveBuffers& buffers, double dt, double gravity_m_s2) {
  // Speeds: none leaves faster than speed_bound. In a pile of a pane's pieces pressed against
  // a wall, the unconverged sweeps gave specks of under a microgram hundreds of m/s within the
  // 1 % of the island's energy allowed above.
  const double bound = speed_bound(buffers, island.size(), dt, gravity_m_s2);
  for (std::size_t k = 0; k < island.size(); ++k) {
    Vec3& velocity = bodies[island[k]].velocity;
    const double speed = velocity.norm();
    if (!(speed > bound)) continue;
    velocity *= bound / speed;
    ++buffers.speed_limited;
  }
  for (std::size_t k = 0; k < island.size(); ++k) {
    Vec3& omega = bodies[island[k]].omega;
    const double spin = omega.norm();
    const double limit = std::max(buffers.start_omega[k].norm(), kMaxContactTurn_rad / dt);
    if (!(spin > limit)) continue;
    omega *= limit / spin;
    ++buffers.spin_limited;
  }
}

// The turn each body of the island makes when the caller redoes the step with the solved
// velocities (its change of angular velocity times dt, about its centre of mass), and for those
// that turn by more than kExactTurn_rad, the turn's rotation less the identity.
[[gnu::noinline]] void redo_turns(const std::vector<SolverBody>& bodies,
                                  const std::vector<std::uint32_t>& island,
                                  PairSolveBuffers& buffers, double dt) {
  const std::size_t size = island.size();
  buffers.turn.resize(size);
  buffers.turn_minus_identity.resize(size);
  buffers.turned.assign(size, 0);
  for (std::size_t k = 0; k < size; ++k) {
    const Vec3 turn = (bodies[island[k]].omega - buffers.start_omega[k]) * dt;
    const double angle = turn.norm();
    if (!(angle > kExactTurn_rad)) continue;
    buffers.turn[k] = turn;
    buffers.turn_minus_identity[k] =
        Eigen::AngleAxisd(angle, turn / angle).toRotationMatrix() - Mat3::Identity();
    buffers.turned[k] = 1;
  }
}

// How much farther along `normal` the linear part of body k's redone turn moves a contact point
// at `arm` than the turn itself does, m (lever = arm x normal).
double turn_error(const Vec3& lever, const Vec3& arm, const Vec3& normal,
                  const PairSolveBuffers& buffers, std::size_t k) {
  return lever.dot(buffers.turn[k]) - normal.dot(buffers.turn_minus_identity[k] * arm);
}

// Points within this of touching at the start of the step are brought to rest by the exact
// sticking solve (the ground's margin, ground_contact.cpp).
constexpr double kStickingTouch_m = 1e-4;
constexpr std::size_t kMaxStickingPoints = 16;

// The exact sticking solve of the ground (sticking_impulses) for an island of one moving body,
// `x`, whose partners are all static (the ground, anchored, held and sleeping bodies): every
// contact touching at the start of the step, if none bounces, brought to rest at once. It holds
// if every impulse pushes and stays inside its Coulomb disc, and the body's motion after it
// (none, or a turn about one or two points) closes no other contact's gap faster than it may
// close within the step; then the body's velocities and the rows' impulses are set and it
// returns true. Otherwise nothing is changed and the sweeps decide. The sweeps converge to the
// same rest, but only to their tolerance (30 um/s), sweep after sweep.
[[gnu::noinline]] bool stick_alone(std::vector<SolverBody>& bodies, std::uint32_t x,
                                   std::span<const PairContact> contacts,
                                   std::vector<ContactRow>& rows, const Mat3& inertia, double dt) {
  SolverBody& body = bodies[x];
  if (body.inverse_inertia == Mat3::Zero()) return false;  // (no turning: the sweeps)
  std::array<std::uint32_t, kMaxStickingPoints> touching;
  std::array<Vec3, kMaxStickingPoints> arms;
  std::size_t count = 0;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const PairContact& c = contacts[i];
    if (c.depth_m + c.approach_before * dt < -kStickingTouch_m) continue;
    if (rows[i].target_speed > 0.0 || count == kMaxStickingPoints) return false;  // a bounce
    touching[count] = static_cast<std::uint32_t>(i);
    arms[count] = rows[i].a == x ? c.arm_a : c.arm_b;
    ++count;
  }
  const double mass = 1.0 / body.inverse_mass;
  std::array<Vec3, kMaxStickingPoints> forces;  // on the body
  Vec3 velocity_after, momentum_after;
  if (!sticking_impulses(
          arms.data(), count, mass, body.velocity, inertia * body.omega, [&] { return inertia; },
          forces.data(), velocity_after, momentum_after))
    return false;
  for (std::size_t k = 0; k < count; ++k) {
    const Vec3& n = rows[touching[k]].normal;
    const Vec3& f = forces[k];
    const double push = rows[touching[k]].b == x ? f.dot(n) : -f.dot(n);
    const double limit = rows[touching[k]].friction * push;
    if (!(push >= 0.0) || (f - f.dot(n) * n).squaredNorm() > limit * limit) return false;
  }
  const Vec3 omega_after = body.inverse_inertia * momentum_after;
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ContactRow& r = rows[i];
    const bool is_b = r.b == x;
    const Vec3 at =
        velocity_after + omega_after.cross(is_b ? contacts[i].arm_b : contacts[i].arm_a);
    const double closing = is_b ? r.normal.dot(at) : -r.normal.dot(at);
    if (closing < r.target_speed - 1e-12) return false;
  }
  body.velocity = velocity_after;
  body.omega = omega_after;
  for (ContactRow& r : rows)
    r.normal_impulse = r.friction_u = r.friction_v = 0.0;
  for (std::size_t k = 0; k < count; ++k) {
    ContactRow& r = rows[touching[k]];
    const Vec3 on_b = r.b == x ? forces[k] : Vec3(-forces[k]);
    r.normal_impulse = on_b.dot(r.normal);
    r.friction_u = on_b.dot(r.u);
    r.friction_v = on_b.dot(r.v);
  }
  return true;
}

// Sweeps over the rows until one changes no body's velocity by more than `converged` (at its
// farthest contact point), at most `iterations`; returns how many, and whether they `settled`.
template <bool Capped>
int sweep(std::vector<SolverBody>& bodies, const std::vector<std::uint32_t>& island,
          std::vector<ContactRow>& rows, double converged, int iterations, bool& settled) {
  for (std::uint32_t x : island) {
    bodies[x].swept_velocity = bodies[x].velocity;
    bodies[x].swept_omega = bodies[x].omega;
  }
  int sweeps = 0;
  settled = false;
  while (!settled && sweeps < iterations) {
    ++sweeps;
    for (ContactRow& r : rows) {
      switch (r.moves) {
        case 1:
          sweep_row<true, false, Capped>(bodies, r);
          break;
        case 2:
          sweep_row<false, true, Capped>(bodies, r);
          break;
        default:
          sweep_row<true, true, Capped>(bodies, r);
          break;
      }
    }
    // (Once one body has changed by the tolerance the sweep has not converged: the others'
    // changes are not measured, only recorded.)
    settled = true;
    for (std::uint32_t x : island) {
      SolverBody& body = bodies[x];
      if (settled && (body.velocity - body.swept_velocity).norm() +
                             (body.omega - body.swept_omega).norm() * body.reach_m >=
                         converged)
        settled = false;
      body.swept_velocity = body.velocity;
      body.swept_omega = body.omega;
    }
  }
  return sweeps;
}

}  // namespace

int solve_pair_contacts(std::vector<SolverBody>& bodies, std::span<PairContact> contacts,
                        const ContactImpulses& last, ContactImpulses& next,
                        const PairSolveSettings& settings, PairSolveBuffers& buffers) {
  const double dt = settings.dt_s;
  // Prepare (the caller sets each contact's arms from the centres of mass), straight into the
  // rows the sweeps read.
  std::vector<std::uint32_t>& island = buffers.island;  // the moving bodies
  island.clear();
  std::vector<ContactRow>& rows = buffers.rows;
  rows.resize(contacts.size());
  for (std::size_t i = 0; i < contacts.size(); ++i) {
    PairContact& c = contacts[i];
    ContactRow& r = rows[i];
    SolverBody& a = bodies[c.a];
    SolverBody& b = bodies[c.b];
    for (std::uint32_t x : {c.a, c.b})
      if (bodies[x].inverse_mass > 0.0 && !bodies[x].listed) {
        bodies[x].listed = true;
        island.push_back(x);
      }
    a.reach_m = std::max(a.reach_m, c.arm_a.norm());
    b.reach_m = std::max(b.reach_m, c.arm_b.norm());
    const Vec3& n = c.normal;
    r.a = c.a;
    r.b = c.b;
    r.inverse_mass_a = a.inverse_mass;
    r.inverse_mass_b = b.inverse_mass;
    r.normal = n;
    // A tangent basis from the normal (any: friction is clamped on the disc, and the warm start
    // is kept as a world vector).
    r.u = std::abs(n.x()) < 0.57 ? Vec3(Vec3::UnitX().cross(n).normalized())
                                 : Vec3(Vec3::UnitY().cross(n).normalized());
    r.v = n.cross(r.u);
    const std::array<Vec3, 3> directions = {n, r.u, r.v};
    // (A static partner's arm, levers and spins are zero: not multiplied out.)
    const bool a_moves = a.inverse_mass > 0.0, b_moves = b.inverse_mass > 0.0;
    r.moves = static_cast<std::uint8_t>((a_moves ? 1 : 0) | (b_moves ? 2 : 0));
    for (int k = 0; k < 3; ++k) {
      r.lever_a[k] = a_moves ? Vec3(c.arm_a.cross(directions[k])) : Vec3::Zero();
      r.lever_b[k] = b_moves ? Vec3(c.arm_b.cross(directions[k])) : Vec3::Zero();
    }
    r.spin_a[0] = a_moves ? Vec3(a.inverse_inertia * r.lever_a[0]) : Vec3::Zero();
    r.spin_b[0] = b_moves ? Vec3(b.inverse_inertia * r.lever_b[0]) : Vec3::Zero();
    r.mass_normal = 1.0 / (a.inverse_mass + b.inverse_mass + r.lever_a[0].dot(r.spin_a[0]) +
                           r.lever_b[0].dot(r.spin_b[0]));
    // The friction directions' spins and masses wait for prepare_friction; until then the
    // friction impulses are zero, and so are the spins they would give.
    r.spin_a[1] = r.spin_a[2] = r.spin_b[1] = r.spin_b[2] = Vec3::Zero();
    r.friction_ready = false;
    r.friction = c.friction;
    r.normal_impulse = r.friction_u = r.friction_v = 0.0;
    r.friction_cap = 0.0;
    const double approach = relative_speed(a, b, r, n, 0);
    c.approach_before = approach;
    // Restitution on the approach speed before this step's gravity: a body resting on another
    // gains g dt towards it every step, which must not become a bounce however long the step
    // (with 0.1 s steps that is 0.98 m/s, above the bounce threshold).
    const double impact = approach - c.gravity_speed_m_s;
    const double start_depth = c.depth_m + approach * dt;  // before this step's motion
    if (impact < -settings.bounce_threshold_m_s && c.depth_m >= 0.0)
      r.target_speed = -c.restitution * impact;  // met within the step, fast: a bounce
    else
      r.target_speed = std::min(start_depth, 0.0) / dt;  // a gap may close within the step
  }
  // The island's kinetic energy before the solve (passivity, below).
  double mass = 0.0;
  const double energy_before = start_energy(bodies, island, buffers, mass);
  // One body against static partners only: the ground's exact sticking solve, where it holds.
  const bool stuck =
      island.size() == 1 && stick_alone(bodies, island[0], contacts, rows, buffers.inertia[0], dt);
  // Warm start (not for a stuck body: its impulses are solved).
  for (std::size_t i = 0; i < contacts.size() && !stuck; ++i) {
    const Vec3* found = last.find(contacts[i].key);
    if (!found) continue;
    ContactRow& r = rows[i];
    const Vec3 j = settings.warm_start_scale * *found;
    r.normal_impulse = std::max(0.0, j.dot(r.normal));
    double fu = j.dot(r.u), fv = j.dot(r.v);
    const double limit = r.friction * r.normal_impulse;
    const double squared = fu * fu + fv * fv;
    if (squared > limit * limit) {
      const double scale = limit / std::sqrt(squared);
      fu *= scale;
      fv *= scale;
    }
    r.friction_u = fu;
    r.friction_v = fv;
    // Without a normal impulse the friction is zero too (its disc is a point): nothing to apply.
    if (!(r.normal_impulse > 0.0)) continue;
    prepare_friction(bodies, r);
    SolverBody& a = bodies[r.a];
    SolverBody& b = bodies[r.b];
    apply(a, b, r, r.normal, 0, r.normal_impulse);
    apply(a, b, r, r.u, 1, fu);
    apply(a, b, r, r.v, 2, fv);
  }
  // Sweeps, until one changes no body's velocity by more than the tolerance (at its farthest
  // contact point; PairSolveSettings). Judged on the bodies, not on each contact's impulse: where a
  // body rests on more points than it needs (four corners of a brick), the sweeps keep passing
  // impulse from one point to another long after the velocities have settled.
  double slowest = INFINITY;
  for (std::uint32_t x : island)
    slowest =
        std::min(slowest, bodies[x].velocity.norm() + bodies[x].omega.norm() * bodies[x].reach_m);
  const double converged = std::max(settings.converged_m_s, settings.converged_fraction * slowest);
  int sweeps = 0;
  bool settled = stuck;
  if (!stuck) sweeps = sweep<false>(bodies, island, rows, converged, settings.iterations, settled);
  // A solve that did not converge and left a body faster than speed_bound has run away: its
  // sweeps were driving impulses up, not settling them, and where they stopped is noise of
  // that size. Friction bounded by the normal impulse does this where it can press a contact
  // harder than the normal impulse pushes it apart (a sliver's corner dragged across a face,
  // pieces wedged in a pile: docs/simulator.md, *Runaway solves*): on window.json's pieces
  // piled against a wall, the sum of the normal impulses of one island of 76 000 points grew
  // from 18 to 81 N s in its 60 sweeps while its fastest body went from 49 to 774 m/s and
  // back, and pieces left the pile at up to 44 m/s from 14.7 m/s launches. Such an island is
  // solved again from its velocities before the solve (no warm start): first without friction
  // (normal impulses alone only push apart), then with friction capped at what each contact's
  // normal impulse from that first pass can bear, so that friction can no longer raise the
  // impulses that bound it.
  bool runaway = false;
  if (!settled) {
    const double bound = speed_bound(buffers, island.size(), dt, settings.gravity_m_s2);
    for (std::uint32_t x : island)
      runaway = runaway || bodies[x].velocity.norm() > bound;
  }
  if (runaway) {
    for (std::size_t k = 0; k < island.size(); ++k) {
      bodies[island[k]].velocity = buffers.start_velocity[k];
      bodies[island[k]].omega = buffers.start_omega[k];
    }
    for (ContactRow& r : rows)
      r.normal_impulse = r.friction_u = r.friction_v = r.friction_cap = 0.0;
    sweeps += sweep<true>(bodies, island, rows, converged, settings.iterations, settled);
    for (ContactRow& r : rows)
      r.friction_cap = r.normal_impulse;
    sweeps += sweep<true>(bodies, island, rows, converged, settings.iterations, settled);
    ++buffers.runaways;
  }
  keep_passive(bodies, island, rows, buffers, energy_before,
               mass * std::pow(settings.gravity_m_s2 * dt, 2));
  for (std::size_t i = 0; i < rows.size(); ++i) {
    const ContactRow& r = rows[i];
    contacts[i].normal_impulse = r.normal_impulse;
    next.add(contacts[i].key,
             r.normal_impulse * r.normal + r.friction_u * r.u + r.friction_v * r.v);
  }
  // Positions: the depth each contact has once the caller moves the bodies by their velocity
  // change over the step, then a few passes of shifts along the normals of the penetration
  // beyond the slop, in proportion to the inverse masses, each contact's depth corrected by the
  // shifts so far. Shifts move no velocity: they add no energy.
  limit_motion(bodies, island, buffers, dt, settings.gravity_m_s2);
  redo_turns(bodies, island, buffers, dt);
  for (std::size_t i = 0; i < rows.size(); ++i) {
    PairContact& c = contacts[i];
    const ContactRow& r = rows[i];
    const double speed = relative_speed(bodies[c.a], bodies[c.b], r, c.normal, 0);
    c.depth_after_m = c.depth_m - (speed - c.approach_before) * dt;
    // Where a body turns appreciably, its contact point moves by the turn itself, not by the
    // turn's linear part (a sliver spinning at 700 rad/s had a point predicted 2.8 m deep).
    if ((r.moves & 1) && buffers.turned[buffers.slot[c.a]])
      c.depth_after_m -= turn_error(r.lever_a[0], c.arm_a, c.normal, buffers, buffers.slot[c.a]);
    if ((r.moves & 2) && buffers.turned[buffers.slot[c.b]])
      c.depth_after_m += turn_error(r.lever_b[0], c.arm_b, c.normal, buffers, buffers.slot[c.b]);
  }
  for (int pass = 0; pass < 3; ++pass) {
    for (const PairContact& c : contacts) {
      SolverBody& a = bodies[c.a];
      SolverBody& b = bodies[c.b];
      const double weight = a.inverse_mass + b.inverse_mass;
      if (weight <= 0.0) continue;
      const double depth = c.depth_after_m - (b.position_shift - a.position_shift).dot(c.normal);
      if (depth <= settings.slop_m) continue;
      const double shift = settings.position_correction * (depth - settings.slop_m) / weight;
      a.position_shift -= shift * a.inverse_mass * c.normal;
      b.position_shift += shift * b.inverse_mass * c.normal;
    }
  }
  return sweeps;
}

}  // namespace brisance::dynamics
