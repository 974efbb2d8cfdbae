// sim/dynamics/ground_contact: a body against the ground plane, in named stages —
//   prepare_contacts   push the body out; the touching hull points, their arms and approach speeds
//   solve_sticking     the exact solve that brings every touching point to rest at once
//   make_contacts      effective masses and each contact's target normal speed (restitution)
//   warm_start         last step's impulses, kept inside their Coulomb discs
//   solve_sweeps       sequential impulses with accumulated clamping
//   store_impulses     the impulses for the next step's warm start
// Every stage keeps the floating-point operations of the single function it came from, so
// results are bit-identical. The stages are forced inline into resolve_ground_contact: left to
// the compiler, the staged code ran 6 % more instructions than the single function did
// (callgrind, bench/sim/step_bench BM_Debris/1000: 863 M against 816 M; forced, 833 M of which
// 51 M in the 3x3 inverse of the sticking solve, which no longer fits the inlining budget).
#include "sim/dynamics/ground_contact.hpp"

#include <algorithm>
#include <array>
#include <cmath>

#include "sim/dynamics/coulomb.hpp"
#include "sim/dynamics/sticking.hpp"

namespace brisance::dynamics {

namespace {

constexpr double kContactMargin_m = 1e-4;     // points this close count as touching
constexpr double kBounceThreshold_m_s = 0.5;  // slower impacts do not bounce (no jitter)
constexpr int kIterations = 8;
constexpr std::size_t kMaxContacts = 16;

// `r`: the body's orientation as a matrix.
Mat3 inverse_inertia_world(const BodyModel& model, const Mat3& r) {
  if (!model.rotates) return Mat3::Zero();
  return r * model.inverse_inertia_body * r.transpose();
}

// The touching hull points (at most kMaxContacts), their arms from the centre of mass and
// their normal speeds before any impulse (for restitution); the body's rotation, world inverse
// inertia and angular velocity at contact.
struct TouchingPoints {
  std::array<std::size_t, kMaxContacts> points;
  std::array<Vec3, kMaxContacts> arms;
  std::array<double, kMaxContacts> approach;
  std::size_t count = 0;
  bool bounces = false;
  Mat3 rotation;
  Mat3 inverse_inertia;
  Vec3 omega;
};

// Stage 1. Returns false if the body does not touch the ground.
[[gnu::always_inline]] inline bool prepare_contacts(const BodyModel& model, BodyState& state,
                                                    const Ground& ground, ContactMemory* memory,
                                                    TouchingPoints& touching) {
  if (state.position.y() - model.bounding_radius_m > ground.height_m + kContactMargin_m)
    return false;
  const Mat3 r = state.orientation.toRotationMatrix();
  double lowest = INFINITY;
  for (const Vec3& p : model.hull_points)
    lowest = std::min(lowest, state.position.y() + r.row(1).dot(p));
  if (memory != nullptr) memory->impulses.resize(model.hull_points.size());
  if (lowest > ground.height_m + kContactMargin_m) {
    if (memory != nullptr)
      std::fill(memory->impulses.begin(), memory->impulses.end(), std::array<double, 3>{});
    return false;
  }
  if (lowest < ground.height_m) state.position.y() += ground.height_m - lowest;

  touching.rotation = r;
  touching.inverse_inertia = inverse_inertia_world(model, r);
  touching.omega = touching.inverse_inertia * state.angular_momentum;
  for (std::size_t i = 0; i < model.hull_points.size(); ++i) {
    const Vec3 arm = r * model.hull_points[i];
    const bool touches = state.position.y() + arm.y() <= ground.height_m + kContactMargin_m;
    if (!touches || touching.count == kMaxContacts) {
      if (memory != nullptr) memory->impulses[i] = {};
      continue;
    }
    const std::size_t k = touching.count;
    touching.points[k] = i;
    touching.arms[k] = arm;
    touching.approach[k] = (state.velocity + touching.omega.cross(arm)).y();
    touching.bounces = touching.bounces || touching.approach[k] < -kBounceThreshold_m_s;
    ++touching.count;
  }
  return true;
}

// Stage 2. Sticking: with no bounce, the contact may bring every touching point to rest at once
// (sticking_impulses). That is an exact solution of the contact problem when some set of
// contact impulses does it with each impulse pushing (not pulling) and inside its Coulomb disc,
// and it is the one the sweeps converge to, only slowly for a brick on a narrow face or an edge
// (measured: half the brick wall's contacts stopped at the sweep limit, 1e-5 m/s away). If the
// least-squares impulses pull or leave a disc anywhere, the sweeps decide (the body slides,
// tips or lifts). Returns true (state and memory updated) if it holds.
[[gnu::always_inline]] inline bool solve_sticking(const BodyModel& model, BodyState& state,
                                                  const Ground& ground, ContactMemory* memory,
                                                  const TouchingPoints& touching) {
  const std::size_t count = touching.count;
  const Mat3& r = touching.rotation;
  std::array<Vec3, kMaxContacts> forces;
  Vec3 velocity_after, momentum_after;
  const bool solved = sticking_impulses(
      touching.arms.data(), count, model.mass_kg, state.velocity, state.angular_momentum,
      [&] { return Mat3(r * model.inertia_body * r.transpose()); }, forces.data(), velocity_after,
      momentum_after);
  bool holds = solved;
  for (std::size_t i = 0; i < count && holds; ++i) {
    const Vec3& f = forces[i];
    const double limit = ground.friction * f.y();
    holds = f.y() >= 0.0 && f.x() * f.x() + f.z() * f.z() <= limit * limit;
  }
  if (!holds) return false;
  state.velocity = velocity_after;
  state.angular_momentum = momentum_after;
  if (memory != nullptr)
    for (std::size_t i = 0; i < count; ++i)
      memory->impulses[touching.points[i]] = {forces[i].y(), forces[i].x(), forces[i].z()};
  return true;
}

// Per contact, everything that stays fixed over the sweeps: for the normal and the two ground
// axes, the angular velocity one unit of impulse adds (I^-1 (r x axis)) and the effective mass,
// so a sweep is a few dot products (friction along the fixed x and z axes, clamped to the
// Coulomb disc).
struct Axis {
  Vec3 spin;            // I^-1 (arm x axis)
  double inverse_mass;  // 1/m + (arm x axis) . I^-1 (arm x axis)
};
struct Contact {
  std::size_t point;  // index into hull_points
  Vec3 arm;
  double target_speed;  // normal speed after the impulses: 0, or a bounce for fast impacts
  Axis normal, along_x, along_z;
  double normal_impulse = 0.0;
  double friction_x = 0.0, friction_z = 0.0;
};
using Contacts = std::array<Contact, kMaxContacts>;

// The velocities the impulses act on, world frame.
struct Velocities {
  Vec3 linear;
  Vec3 omega;
};

// Stage 3. Restitution: an impact faster than kBounceThreshold_m_s bounces back at
// restitution times its approach speed; slower ones stop (no jitter).
[[gnu::always_inline]] inline void make_contacts(const BodyModel& model, const Ground& ground,
                                                 const TouchingPoints& touching,
                                                 Contacts& contacts) {
  auto axis = [&](const Vec3& arm, const Vec3& direction) {
    const Vec3 lever = arm.cross(direction);
    const Vec3 spin = touching.inverse_inertia * lever;
    return Axis{spin, model.inverse_mass + lever.dot(spin)};
  };
  for (std::size_t i = 0; i < touching.count; ++i) {
    const Vec3& arm = touching.arms[i];
    const double approach = touching.approach[i];
    const double target = approach < -kBounceThreshold_m_s ? -ground.restitution * approach : 0.0;
    contacts[i] = Contact{
        touching.points[i],      arm, target, axis(arm, Vec3::UnitY()), axis(arm, Vec3::UnitX()),
        axis(arm, Vec3::UnitZ())};
  }
}

[[gnu::always_inline]] inline void push(const BodyModel& model, Velocities& v,
                                        const Vec3& direction, const Axis& a, double impulse) {
  v.linear += impulse * model.inverse_mass * direction;
  v.omega += impulse * a.spin;
}

// Stage 4. Warm start: last step's impulses (friction kept inside the Coulomb disc).
[[gnu::always_inline]] inline void warm_start(const BodyModel& model, const Ground& ground,
                                              const ContactMemory& memory, std::size_t count,
                                              Contacts& contacts, Velocities& v) {
  for (std::size_t i = 0; i < count; ++i) {
    Contact& c = contacts[i];
    const auto& last = memory.impulses[c.point];
    c.normal_impulse = std::max(0.0, last[0]);
    const double limit = ground.friction * c.normal_impulse;
    const double squared = last[1] * last[1] + last[2] * last[2];
    const double scale = squared > limit * limit ? limit / std::sqrt(squared) : 1.0;
    c.friction_x = last[1] * scale;
    c.friction_z = last[2] * scale;
    push(model, v, Vec3::UnitY(), c.normal, c.normal_impulse);
    push(model, v, Vec3::UnitX(), c.along_x, c.friction_x);
    push(model, v, Vec3::UnitZ(), c.along_z, c.friction_z);
  }
}

// Stage 5. Sequential impulses with accumulated clamping, until a sweep changes velocities by
// under 1 um/s or kIterations sweeps.
[[gnu::always_inline]] inline void solve_sweeps(const BodyModel& model, const Ground& ground,
                                                std::size_t count, Contacts& contacts,
                                                Velocities& v) {
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    double largest_change = 0.0;  // N s, this sweep
    for (std::size_t i = 0; i < count; ++i) {
      Contact& c = contacts[i];
      // Normal: no approach, or a bounce for fast impacts.
      const double vn = v.linear.y() + v.omega.z() * c.arm.x() - v.omega.x() * c.arm.z();
      const double accumulated =
          std::max(c.normal_impulse + (c.target_speed - vn) / c.normal.inverse_mass, 0.0);
      const double dn = accumulated - c.normal_impulse;
      c.normal_impulse = accumulated;
      push(model, v, Vec3::UnitY(), c.normal, dn);
      // Coulomb friction against the sliding velocity, within mu times the normal impulse.
      const Vec3 slip = v.linear + v.omega.cross(c.arm);
      double fx = c.friction_x - slip.x() / c.along_x.inverse_mass;
      double fz = c.friction_z - slip.z() / c.along_z.inverse_mass;
      clamp_to_friction_disc(fx, fz, ground.friction * c.normal_impulse);
      const double dx = fx - c.friction_x, dz = fz - c.friction_z;
      c.friction_x = fx;
      c.friction_z = fz;
      push(model, v, Vec3::UnitX(), c.along_x, dx);
      push(model, v, Vec3::UnitZ(), c.along_z, dz);
      largest_change = std::max({largest_change, std::abs(dn), std::abs(dx), std::abs(dz)});
    }
    // Converged: a further sweep would change velocities by under 1 um/s.
    if (largest_change * model.inverse_mass < 1e-6) break;
  }
}

// Stage 6. The swept impulses applied to the body and kept for the next step.
[[gnu::always_inline]] inline void store_impulses(std::size_t count, const Contacts& contacts,
                                                  const Velocities& v, BodyState& state,
                                                  ContactMemory* memory) {
  // The angular impulse is linear in the contact impulses: summed once from their totals.
  Vec3 angular_impulse = Vec3::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    const Contact& c = contacts[i];
    angular_impulse += c.arm.cross(Vec3(c.friction_x, c.normal_impulse, c.friction_z));
  }
  state.velocity = v.linear;
  state.angular_momentum += angular_impulse;
  if (memory != nullptr)
    for (std::size_t i = 0; i < count; ++i)
      memory->impulses[contacts[i].point] = {contacts[i].normal_impulse, contacts[i].friction_x,
                                             contacts[i].friction_z};
}

}  // namespace

bool resolve_ground_contact(const BodyModel& model, BodyState& state, const Ground& ground,
                            ContactMemory* memory) {
  TouchingPoints touching;
  if (!prepare_contacts(model, state, ground, memory, touching)) return false;
  if (!touching.bounces && model.rotates && touching.count > 0 &&
      solve_sticking(model, state, ground, memory, touching))
    return true;
  Contacts contacts;
  make_contacts(model, ground, touching, contacts);
  Velocities velocities{state.velocity, touching.omega};
  if (memory != nullptr) warm_start(model, ground, *memory, touching.count, contacts, velocities);
  solve_sweeps(model, ground, touching.count, contacts, velocities);
  store_impulses(touching.count, contacts, velocities, state, memory);
  return true;
}

}  // namespace brisance::dynamics
