// sim/dynamics/body_contact: sequential impulses over contacts between bodies, in stages —
//   prepare    arms, tangents, effective masses, target normal speeds (restitution, gaps)
//   warm start last step's impulses by contact key, friction kept inside its Coulomb disc
//   sweeps     accumulated clamping, until a sweep changes no body's velocity by more than
//              30 um/s or 0.3 % of the island's slowest body's speed
//   positions  the penetration beyond the slop, removed by shifts along the normals
#include "sim/dynamics/body_contact.hpp"

#include <algorithm>
#include <cmath>

namespace brisance::dynamics {

namespace {

// The speed of b relative to a at the contact along direction k (0 normal, 1 u, 2 v).
inline double relative_speed(const SolverBody& a, const SolverBody& b, const PairContact& c,
                             const Vec3& direction, int k) {
  return direction.dot(b.velocity - a.velocity) + c.lever_b[k].dot(b.omega) -
         c.lever_a[k].dot(a.omega);
}

// An impulse j along direction k on b (and -j on a).
inline void apply(SolverBody& a, SolverBody& b, const PairContact& c, const Vec3& direction, int k,
                  double j) {
  a.velocity -= (j * a.inverse_mass) * direction;
  a.omega -= j * c.spin_a[k];
  b.velocity += (j * b.inverse_mass) * direction;
  b.omega += j * c.spin_b[k];
}

}  // namespace

int solve_pair_contacts(std::vector<SolverBody>& bodies, std::span<PairContact> contacts,
                        const ContactImpulses& last, ContactImpulses& next,
                        const PairSolveSettings& settings) {
  const double dt = settings.dt_s;
  // Prepare (the caller sets each contact's arms from the centres of mass).
  std::vector<std::uint32_t> island;  // the moving bodies
  for (PairContact& c : contacts) {
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
    // A tangent basis from the normal (any: friction is clamped on the disc, and the warm start
    // is kept as a world vector).
    c.tangent_u = std::abs(n.x()) < 0.57 ? Vec3(Vec3::UnitX().cross(n).normalized())
                                         : Vec3(Vec3::UnitY().cross(n).normalized());
    c.tangent_v = n.cross(c.tangent_u);
    const std::array<Vec3, 3> directions = {n, c.tangent_u, c.tangent_v};
    std::array<double, 3> masses;
    for (int k = 0; k < 3; ++k) {
      c.lever_a[k] = c.arm_a.cross(directions[k]);
      c.lever_b[k] = c.arm_b.cross(directions[k]);
      c.spin_a[k] = a.inverse_inertia * c.lever_a[k];
      c.spin_b[k] = b.inverse_inertia * c.lever_b[k];
      masses[k] = 1.0 / (a.inverse_mass + b.inverse_mass + c.lever_a[k].dot(c.spin_a[k]) +
                         c.lever_b[k].dot(c.spin_b[k]));
    }
    c.mass_normal = masses[0];
    c.mass_u = masses[1];
    c.mass_v = masses[2];
    const double approach = relative_speed(a, b, c, n, 0);
    c.approach_before = approach;
    // Restitution on the approach speed before this step's gravity: a body resting on another
    // gains g dt towards it every step, which must not become a bounce however long the step
    // (with 0.1 s steps that is 0.98 m/s, above the bounce threshold).
    const double impact = approach - c.gravity_speed_m_s;
    const double start_depth = c.depth_m + approach * dt;  // before this step's motion
    if (impact < -settings.bounce_threshold_m_s && c.depth_m >= 0.0)
      c.target_speed = -c.restitution * impact;  // met within the step, fast: a bounce
    else
      c.target_speed = std::min(start_depth, 0.0) / dt;  // a gap may close within the step
  }
  // Warm start.
  for (PairContact& c : contacts) {
    const auto found = last.find(c.key);
    if (found == last.end()) continue;
    const Vec3 j = settings.warm_start_scale * found->second;
    c.normal_impulse = std::max(0.0, j.dot(c.normal));
    double fu = j.dot(c.tangent_u), fv = j.dot(c.tangent_v);
    const double limit = c.friction * c.normal_impulse;
    const double squared = fu * fu + fv * fv;
    if (squared > limit * limit) {
      const double scale = limit / std::sqrt(squared);
      fu *= scale;
      fv *= scale;
    }
    c.friction_u = fu;
    c.friction_v = fv;
    apply(bodies[c.a], bodies[c.b], c, c.normal, 0, c.normal_impulse);
    apply(bodies[c.a], bodies[c.b], c, c.tangent_u, 1, fu);
    apply(bodies[c.a], bodies[c.b], c, c.tangent_v, 2, fv);
  }
  // Sweeps, until one changes no body's velocity by more than the tolerance (at its farthest
  // contact point; PairSolveSettings). Judged on the bodies, not on each contact's impulse: where a
  // body rests on more points than it needs (four corners of a brick), the sweeps keep passing
  // impulse from one point to another long after the velocities have settled.
  for (std::uint32_t x : island) {
    bodies[x].swept_velocity = bodies[x].velocity;
    bodies[x].swept_omega = bodies[x].omega;
  }
  // The sweeps read only what they need, packed per contact (the contacts themselves are four
  // times larger), and keep both bodies' velocities in locals while a contact is solved.
  struct Row {
    std::uint32_t a, b;
    double inverse_mass_a, inverse_mass_b;
    Vec3 normal, u, v;
    std::array<Vec3, 3> lever_a, lever_b, spin_a, spin_b;
    double mass_normal, mass_u, mass_v, target_speed, friction;
    double normal_impulse, friction_u, friction_v;
  };
  std::vector<Row> rows;
  rows.reserve(contacts.size());
  for (const PairContact& c : contacts)
    rows.push_back(Row{c.a, c.b, bodies[c.a].inverse_mass, bodies[c.b].inverse_mass, c.normal,
                       c.tangent_u, c.tangent_v, c.lever_a, c.lever_b, c.spin_a, c.spin_b,
                       c.mass_normal, c.mass_u, c.mass_v, c.target_speed, c.friction,
                       c.normal_impulse, c.friction_u, c.friction_v});
  double slowest = INFINITY;
  for (std::uint32_t x : island)
    slowest =
        std::min(slowest, bodies[x].velocity.norm() + bodies[x].omega.norm() * bodies[x].reach_m);
  const double converged = std::max(settings.converged_m_s, settings.converged_fraction * slowest);
  int sweeps = 0;
  while (sweeps < settings.iterations) {
    ++sweeps;
    for (Row& r : rows) {
      SolverBody& a = bodies[r.a];
      SolverBody& b = bodies[r.b];
      Vec3 va = a.velocity, wa = a.omega, vb = b.velocity, wb = b.omega;
      const double vn = r.normal.dot(vb - va) + r.lever_b[0].dot(wb) - r.lever_a[0].dot(wa);
      const double accumulated =
          std::max(r.normal_impulse + (r.target_speed - vn) * r.mass_normal, 0.0);
      const double dn = accumulated - r.normal_impulse;
      r.normal_impulse = accumulated;
      va -= (dn * r.inverse_mass_a) * r.normal;
      wa -= dn * r.spin_a[0];
      vb += (dn * r.inverse_mass_b) * r.normal;
      wb += dn * r.spin_b[0];
      const Vec3 slide = vb - va;
      double fu =
          r.friction_u - (r.u.dot(slide) + r.lever_b[1].dot(wb) - r.lever_a[1].dot(wa)) * r.mass_u;
      double fv =
          r.friction_v - (r.v.dot(slide) + r.lever_b[2].dot(wb) - r.lever_a[2].dot(wa)) * r.mass_v;
      const double limit = r.friction * r.normal_impulse;
      const double squared = fu * fu + fv * fv;
      if (squared > limit * limit) {
        const double scale = limit / std::sqrt(squared);
        fu *= scale;
        fv *= scale;
      }
      const double du = fu - r.friction_u, dv = fv - r.friction_v;
      r.friction_u = fu;
      r.friction_v = fv;
      const Vec3 push = du * r.u + dv * r.v;
      a.velocity = va - r.inverse_mass_a * push;
      a.omega = wa - du * r.spin_a[1] - dv * r.spin_a[2];
      b.velocity = vb + r.inverse_mass_b * push;
      b.omega = wb + du * r.spin_b[1] + dv * r.spin_b[2];
    }
    double largest = 0.0;
    for (std::uint32_t x : island) {
      SolverBody& body = bodies[x];
      largest = std::max(largest, (body.velocity - body.swept_velocity).norm() +
                                      (body.omega - body.swept_omega).norm() * body.reach_m);
      body.swept_velocity = body.velocity;
      body.swept_omega = body.omega;
    }
    if (largest < converged) break;
  }
  for (std::size_t i = 0; i < rows.size(); ++i) {
    contacts[i].normal_impulse = rows[i].normal_impulse;
    contacts[i].friction_u = rows[i].friction_u;
    contacts[i].friction_v = rows[i].friction_v;
  }
  for (const PairContact& c : contacts)
    next[c.key] =
        c.normal_impulse * c.normal + c.friction_u * c.tangent_u + c.friction_v * c.tangent_v;
  // Positions: the depth each contact has once the caller moves the bodies by their velocity
  // change over the step, then a few passes of shifts along the normals of the penetration
  // beyond the slop, in proportion to the inverse masses, each contact's depth corrected by the
  // shifts so far. Shifts move no velocity: they add no energy.
  for (PairContact& c : contacts) {
    const double speed = relative_speed(bodies[c.a], bodies[c.b], c, c.normal, 0);
    c.depth_after_m = c.depth_m - (speed - c.approach_before) * dt;
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
