#include "sim/dynamics/rigid_body.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>

namespace brisance::dynamics {

namespace {

Mat3 inverse_inertia_world(const BodyModel& model, const Quat& orientation) {
  if (!model.rotates) return Mat3::Zero();
  const Mat3 r = orientation.toRotationMatrix();
  return r * model.inverse_inertia_body * r.transpose();
}

// omega = R I_b^-1 R^T L, as matrix-vector products (the hot path of every step).
Vec3 omega_of(const BodyModel& model, const Mat3& r, const Vec3& angular_momentum) {
  if (!model.rotates) return Vec3::Zero();
  const Vec3 local = r.transpose().lazyProduct(angular_momentum);
  const Vec3 spin = model.diagonal_inertia
                        ? Vec3(model.inverse_inertia_diagonal.cwiseProduct(local))
                        : Vec3(model.inverse_inertia_body.lazyProduct(local));
  return r.lazyProduct(spin);
}

Vec3 omega_of(const BodyModel& model, const Quat& orientation, const Vec3& angular_momentum) {
  if (!model.rotates) return Vec3::Zero();
  return omega_of(model, orientation.toRotationMatrix(), angular_momentum);
}

// The rotation by the rotation vector w * dt, as a unit quaternion (exact for constant w).
Quat rotation_over(const Vec3& omega, double dt) {
  const double angle_squared = omega.squaredNorm() * dt * dt;
  if (angle_squared < 1e-2) {
    // Below 0.1 rad (every adaptive step) the Taylor series of cos(a/2) and sin(a/2)/a to
    // a^4 is exact to 3e-12 and saves the sine and cosine; the caller renormalises.
    // (Multiplications by reciprocals, not divisions: this runs twice in every body's step.)
    const double a2 = angle_squared;
    const double c = 1.0 - a2 * (1.0 / 8.0) + a2 * a2 * (1.0 / 384.0);
    const double s = (0.5 - a2 * (1.0 / 48.0) + a2 * a2 * (1.0 / 3840.0)) * dt;
    return Quat(c, s * omega.x(), s * omega.y(), s * omega.z());
  }
  const double angle = std::sqrt(angle_squared);
  return Quat(Eigen::AngleAxisd(angle, omega / (angle / dt)));
}

// dq/dt = 1/2 (0, w) q with w in the world frame.
Eigen::Vector4d quaternion_rate(const Quat& q, const Vec3& omega) {
  const Quat rate = Quat(0.0, omega.x(), omega.y(), omega.z()) * q;
  return 0.5 * rate.coeffs();
}

// Quadratic drag along the velocity, integrated exactly for straight-line motion:
// dv/dt = -k v^2 gives v(dt) = v / (1 + k v dt), stable for any step (thesis eq. 3.2).
// `rotation` is the body's orientation as a matrix (shared with the rotation step).
void apply_drag(const BodyModel& model, const Mat3& rotation, BodyState& state,
                const WorldSettings& world, double dt) {
  if (world.air_density_kg_m3 <= 0.0) return;
  const double speed = state.velocity.norm();
  if (speed <= 0.0) return;
  const Vec3 direction_body = rotation.transpose().lazyProduct(state.velocity * (1.0 / speed));
  const double area = model.drag_shape.projected_area_m2(direction_body);
  const double k =
      0.5 * world.air_density_kg_m3 * model.drag_coefficient * area * model.inverse_mass;
  state.velocity *= 1.0 / (1.0 + k * speed * dt);
}

// Returns the angular velocity the step turned the body with (world frame).
Vec3 integrate_rotation(const BodyModel& model, const Mat3& start_rotation, BodyState& state,
                        const StepLoads& loads, const WorldSettings& world, double dt) {
  if (!model.rotates) {
    state.angular_momentum.setZero();
    return Vec3::Zero();
  }
  // Not spinning and not being spun: the orientation cannot change.
  if (state.angular_momentum.isZero(0.0) && loads.angular_impulse.isZero(0.0)) return Vec3::Zero();
  Vec3 turned = Vec3::Zero();
  switch (world.integrator) {
    case Integrator::explicit_euler: {
      // Thesis eqs. 3.3-3.4: I w' = tau - w x (I w), stepped explicitly in (q, w).
      const Mat3 r = state.orientation.toRotationMatrix();
      const Mat3 inertia = r * model.inertia_body * r.transpose();
      const Mat3 inverse = r * model.inverse_inertia_body * r.transpose();
      const Vec3 omega = inverse * state.angular_momentum;
      const Vec3 torque = loads.angular_impulse / dt;
      const Vec3 next_omega = omega + dt * (inverse * (torque - omega.cross(inertia * omega)));
      state.orientation = (rotation_over(omega, dt) * state.orientation).normalized();
      const Mat3 r1 = state.orientation.toRotationMatrix();
      state.angular_momentum = r1 * model.inertia_body * r1.transpose() * next_omega;
      turned = omega;
      break;
    }
    case Integrator::semi_implicit_euler: {
      // Momentum first (like the velocity), then the orientation turned by the angular velocity
      // at the half step: a plain first-order turn drifts 15 % in energy within 10 s near the
      // intermediate axis at 6 rad/s and 1 ms steps; the midpoint turn costs one more rotation.
      state.angular_momentum += loads.angular_impulse;
      const Vec3 start_omega = omega_of(model, start_rotation, state.angular_momentum);
      const Quat half = rotation_over(start_omega, 0.5 * dt) * state.orientation;
      const Vec3 omega = omega_of(model, half, state.angular_momentum);
      state.orientation = rotation_over(omega, dt) * state.orientation;
      state.orientation.coeffs() *= 1.0 / state.orientation.norm();  // one division, not four
      turned = omega;
      break;
    }
    case Integrator::rk4: {
      // The step's angular impulse spread evenly: L(s) = L0 + (s / dt) dL; RK4 on q.
      const Vec3 l0 = state.angular_momentum;
      const Vec3 dl = loads.angular_impulse;
      const Quat q0 = state.orientation;
      auto rate = [&](const Eigen::Vector4d& coeffs, double s) {
        Quat q(coeffs);
        q.normalize();
        const Vec3 omega = omega_of(model, q, l0 + (s / dt) * dl);
        return quaternion_rate(q, omega);
      };
      const Eigen::Vector4d y0 = q0.coeffs();
      const Eigen::Vector4d k1 = rate(y0, 0.0);
      const Eigen::Vector4d k2 = rate(y0 + 0.5 * dt * k1, 0.5 * dt);
      const Eigen::Vector4d k3 = rate(y0 + 0.5 * dt * k2, 0.5 * dt);
      const Eigen::Vector4d k4 = rate(y0 + dt * k3, dt);
      state.orientation = Quat(Eigen::Vector4d(y0 + dt / 6.0 * (k1 + 2.0 * k2 + 2.0 * k3 + k4)));
      state.orientation.normalize();
      state.angular_momentum = l0 + dl;
      turned = omega_of(model, state.orientation, state.angular_momentum);
      break;
    }
  }
  if (world.angular_damping_per_s > 0.0)
    state.angular_momentum *= std::exp(-world.angular_damping_per_s * dt);
  return turned;
}

}  // namespace

void DragShape::add_face(const Vec3& unit_normal, double area_m2) {
  if (face_count < kInlineFaces)
    faces[face_count] = area_m2 * unit_normal;
  else
    more_faces.push_back(area_m2 * unit_normal);
  ++face_count;
}

double DragShape::projected_area_m2(const Vec3& direction_body) const {
  if (face_count == 0) return mean_area_m2;
  double area = 0.0;
  for (std::size_t i = 0; i < std::min(face_count, kInlineFaces); ++i)
    area += std::abs(faces[i].dot(direction_body));
  for (const Vec3& face : more_faces)
    area += std::abs(face.dot(direction_body));
  return area;
}

void set_inertia(BodyModel& model, const Mat3& inertia_kg_m2) {
  model.inertia_body = inertia_kg_m2;
  model.inverse_inertia_body = inertia_kg_m2.inverse();
  const double scale = inertia_kg_m2.diagonal().cwiseAbs().maxCoeff();
  const Mat3 off_diagonal = inertia_kg_m2 - Mat3(inertia_kg_m2.diagonal().asDiagonal());
  model.diagonal_inertia = off_diagonal.cwiseAbs().maxCoeff() <= 1e-14 * scale;
  model.inverse_inertia_diagonal = model.inverse_inertia_body.diagonal();
}

Vec3 angular_velocity(const BodyModel& model, const BodyState& state) {
  if (state.angular_momentum.isZero(0.0)) return Vec3::Zero();
  return omega_of(model, state.orientation, state.angular_momentum);
}

double kinetic_energy(const BodyModel& model, const BodyState& state) {
  const double linear = 0.5 * model.mass_kg * state.velocity.squaredNorm();
  return linear + 0.5 * angular_velocity(model, state).dot(state.angular_momentum);
}

Vec3 integrate(const BodyModel& model, BodyState& state, const StepLoads& loads,
               const WorldSettings& world, double dt) {
  assert(dt > 0.0);
  const Vec3 velocity_change = loads.impulse * model.inverse_mass + world.gravity_m_s2 * dt;
  const Mat3 rotation = state.orientation.toRotationMatrix();  // at the start of the step
  switch (world.integrator) {
    case Integrator::explicit_euler: {
      // Thesis §3.5: constant acceleration over the step, velocity first, then the displacement
      // from the average of the old and new velocities.
      const Vec3 start_velocity = state.velocity;
      state.velocity += velocity_change;
      apply_drag(model, rotation, state, world, dt);
      state.position += 0.5 * (start_velocity + state.velocity) * dt;
      break;
    }
    case Integrator::semi_implicit_euler:
      state.velocity += velocity_change;
      apply_drag(model, rotation, state, world, dt);
      state.position += state.velocity * dt;
      break;
    case Integrator::rk4:
      // Gravity and the load are integrated exactly: the load moves the body by its first moment.
      state.position += state.velocity * dt + 0.5 * world.gravity_m_s2 * dt * dt +
                        loads.impulse_moment * model.inverse_mass;
      state.velocity += velocity_change;
      apply_drag(model, rotation, state, world, dt);
      break;
  }
  if (world.linear_damping_per_s > 0.0)
    state.velocity *= std::exp(-world.linear_damping_per_s * dt);
  return integrate_rotation(model, rotation, state, loads, world, dt);
}

bool resolve_ground_contact(const BodyModel& model, BodyState& state, const Ground& ground,
                            ContactMemory* memory) {
  constexpr double kContactMargin_m = 1e-4;     // points this close count as touching
  constexpr double kBounceThreshold_m_s = 0.5;  // slower impacts do not bounce (no jitter)
  constexpr int kIterations = 8;
  constexpr std::size_t kMaxContacts = 16;
  const Vec3 up = Vec3::UnitY();
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

  // The touching hull points (at most kMaxContacts), their arms from the centre of mass and
  // their normal speeds before any impulse (for restitution).
  std::array<std::size_t, kMaxContacts> points;
  std::array<Vec3, kMaxContacts> arms;
  std::array<double, kMaxContacts> approach;
  std::size_t count = 0;
  const Mat3 inverse = inverse_inertia_world(model, state.orientation);
  Vec3 omega = inverse * state.angular_momentum;
  bool bounces = false;
  for (std::size_t i = 0; i < model.hull_points.size(); ++i) {
    const Vec3 arm = r * model.hull_points[i];
    const bool touching = state.position.y() + arm.y() <= ground.height_m + kContactMargin_m;
    if (!touching || count == kMaxContacts) {
      if (memory != nullptr) memory->impulses[i] = {};
      continue;
    }
    points[count] = i;
    arms[count] = arm;
    approach[count] = (state.velocity + omega.cross(arm)).y();
    bounces = bounces || approach[count] < -kBounceThreshold_m_s;
    ++count;
  }

  // Sticking: with no bounce, the contact may bring every touching point to rest at once. That
  // is an exact solution of the contact problem when some set of contact impulses does it with
  // each impulse pushing (not pulling) and inside its Coulomb disc, and it is the one the sweeps
  // below converge to, only slowly for a brick on a narrow face or an edge (measured: half the
  // brick wall's contacts stopped at the sweep limit, 1e-5 m/s away). With three or more points
  // not on one line the body stops: sum F_i = -m v, sum r_i x F_i = -L. On one point it turns
  // about it and keeps its angular momentum about it; on two, it turns about their edge and
  // keeps its angular momentum about the edge. Of the impulse sets that do it, the
  // least-squares one is tried; if it pulls or leaves a disc anywhere, the sweeps decide (the
  // body slides, tips or lifts).
  if (!bounces && model.rotates && count > 0) {
    std::array<Vec3, kMaxContacts> forces;
    Vec3 velocity_after = Vec3::Zero();
    Vec3 momentum_after = Vec3::Zero();
    bool solved = false;
    if (count >= 3) {
      // About the points' centroid c: F_i = J / n + t x (r_i - c) with S t = H_c,
      // S = sum |r_i - c|^2 I - (r_i - c)(r_i - c)^T.
      const double n = static_cast<double>(count);
      Vec3 centroid = Vec3::Zero();
      for (std::size_t i = 0; i < count; ++i)
        centroid += arms[i];
      centroid /= n;
      Mat3 spread = Mat3::Zero();
      for (std::size_t i = 0; i < count; ++i) {
        const Vec3 d = arms[i] - centroid;
        spread -= d * d.transpose();
        spread.diagonal().array() += d.squaredNorm();
      }
      const Vec3 impulse = -model.mass_kg * state.velocity;
      const Vec3 torque = -state.angular_momentum - centroid.cross(impulse);  // about c
      // Points (nearly) on one line cannot take a torque about that line.
      const double scale = spread.trace() / 3.0;
      if (spread.determinant() > 1e-6 * scale * scale * scale) {
        const Vec3 twist = spread.inverse() * torque;
        const Vec3 share = impulse / n;
        for (std::size_t i = 0; i < count; ++i)
          forces[i] = share + twist.cross(arms[i] - centroid);
        solved = true;
      }
    } else {
      // Turning about the first point p: angular momentum about p, L - r x m v, is kept, with
      // the inertia about p (parallel axes); the centre then moves at r x w.
      const Vec3& arm = arms[0];
      const Mat3 inertia = r * model.inertia_body * r.transpose();
      Mat3 about_point = inertia - model.mass_kg * arm * arm.transpose();
      about_point.diagonal().array() += model.mass_kg * arm.squaredNorm();
      const Vec3 momentum_about =
          state.angular_momentum - arm.cross(model.mass_kg * state.velocity);
      Vec3 omega_after = Vec3::Zero();
      const Vec3 edge = count == 2 ? Vec3(arms[1] - arm) : Vec3::Zero();
      if (count == 1) {
        omega_after = about_point.inverse() * momentum_about;
        solved = true;
      } else if (edge.squaredNorm() > 1e-12) {
        const Vec3 axis = edge.normalized();
        omega_after = (axis.dot(momentum_about) / axis.dot(about_point * axis)) * axis;
        solved = true;
      }
      if (solved) {
        velocity_after = arm.cross(omega_after);
        momentum_after = inertia * omega_after;
        const Vec3 impulse = model.mass_kg * (velocity_after - state.velocity);
        if (count == 1) {
          forces[0] = impulse;
        } else {
          // The second point takes the torque about the first; the pair shares the push along
          // their edge equally.
          const Vec3 torque = momentum_after - state.angular_momentum - arm.cross(impulse);
          const Vec3 axis = edge.normalized();
          forces[1] = torque.cross(edge) / edge.squaredNorm() + 0.5 * impulse.dot(axis) * axis;
          forces[0] = impulse - forces[1];
        }
      }
    }
    bool holds = solved;
    for (std::size_t i = 0; i < count && holds; ++i) {
      const Vec3& f = forces[i];
      const double limit = ground.friction * f.y();
      holds = f.y() >= 0.0 && f.x() * f.x() + f.z() * f.z() <= limit * limit;
    }
    if (holds) {
      state.velocity = velocity_after;
      state.angular_momentum = momentum_after;
      if (memory != nullptr)
        for (std::size_t i = 0; i < count; ++i)
          memory->impulses[points[i]] = {forces[i].y(), forces[i].x(), forces[i].z()};
      return true;
    }
  }

  // Sequential impulses. Per contact, everything that stays fixed over the sweeps: for the
  // normal and the two ground axes, the angular velocity one unit of impulse adds
  // (I^-1 (r x axis)) and the effective mass, so a sweep is a few dot products (friction along
  // the fixed x and z axes, clamped to the Coulomb disc).
  struct Axis {
    Vec3 spin;            // I^-1 (arm x axis)
    double inverse_mass;  // 1/m + (arm x axis) . I^-1 (arm x axis)
  };
  struct Contact {
    std::size_t point;  // index into hull_points
    Vec3 arm;
    double approach_speed;  // normal speed before the impulses, for restitution
    Axis normal, along_x, along_z;
    double normal_impulse = 0.0;
    double friction_x = 0.0, friction_z = 0.0;
  };
  std::array<Contact, kMaxContacts> contacts;
  auto axis = [&](const Vec3& arm, const Vec3& direction) {
    const Vec3 lever = arm.cross(direction);
    const Vec3 spin = inverse * lever;
    return Axis{spin, model.inverse_mass + lever.dot(spin)};
  };
  for (std::size_t i = 0; i < count; ++i)
    contacts[i] = Contact{points[i],
                          arms[i],
                          approach[i],
                          axis(arms[i], up),
                          axis(arms[i], Vec3::UnitX()),
                          axis(arms[i], Vec3::UnitZ())};
  Vec3 linear = state.velocity;
  auto push = [&](const Vec3& direction, const Axis& a, double impulse) {
    linear += impulse * model.inverse_mass * direction;
    omega += impulse * a.spin;
  };
  if (memory != nullptr) {
    // Warm start: last step's impulses (friction kept inside the Coulomb disc).
    for (std::size_t i = 0; i < count; ++i) {
      Contact& c = contacts[i];
      const auto& last = memory->impulses[c.point];
      c.normal_impulse = std::max(0.0, last[0]);
      const double limit = ground.friction * c.normal_impulse;
      const double squared = last[1] * last[1] + last[2] * last[2];
      const double scale = squared > limit * limit ? limit / std::sqrt(squared) : 1.0;
      c.friction_x = last[1] * scale;
      c.friction_z = last[2] * scale;
      push(up, c.normal, c.normal_impulse);
      push(Vec3::UnitX(), c.along_x, c.friction_x);
      push(Vec3::UnitZ(), c.along_z, c.friction_z);
    }
  }
  for (int iteration = 0; iteration < kIterations; ++iteration) {
    double largest_change = 0.0;  // N s, this sweep
    for (std::size_t i = 0; i < count; ++i) {
      Contact& c = contacts[i];
      // Normal: no approach, or a bounce for fast impacts.
      const double vn = linear.y() + omega.z() * c.arm.x() - omega.x() * c.arm.z();
      const double target =
          c.approach_speed < -kBounceThreshold_m_s ? -ground.restitution * c.approach_speed : 0.0;
      const double accumulated =
          std::max(c.normal_impulse + (target - vn) / c.normal.inverse_mass, 0.0);
      const double dn = accumulated - c.normal_impulse;
      c.normal_impulse = accumulated;
      push(up, c.normal, dn);
      // Coulomb friction against the sliding velocity, within mu times the normal impulse.
      // (Squared magnitudes: std::hypot's overflow guard cost more than the rest of the sweep.)
      const Vec3 v = linear + omega.cross(c.arm);
      double fx = c.friction_x - v.x() / c.along_x.inverse_mass;
      double fz = c.friction_z - v.z() / c.along_z.inverse_mass;
      const double limit = ground.friction * c.normal_impulse;
      const double squared = fx * fx + fz * fz;
      if (squared > limit * limit) {
        const double scale = limit / std::sqrt(squared);
        fx *= scale;
        fz *= scale;
      }
      const double dx = fx - c.friction_x, dz = fz - c.friction_z;
      c.friction_x = fx;
      c.friction_z = fz;
      push(Vec3::UnitX(), c.along_x, dx);
      push(Vec3::UnitZ(), c.along_z, dz);
      largest_change = std::max({largest_change, std::abs(dn), std::abs(dx), std::abs(dz)});
    }
    // Converged: a further sweep would change velocities by under 1 um/s.
    if (largest_change * model.inverse_mass < 1e-6) break;
  }
  // The angular impulse is linear in the contact impulses: summed once from their totals.
  Vec3 angular_impulse = Vec3::Zero();
  for (std::size_t i = 0; i < count; ++i) {
    const Contact& c = contacts[i];
    angular_impulse += c.arm.cross(Vec3(c.friction_x, c.normal_impulse, c.friction_z));
  }
  state.velocity = linear;
  state.angular_momentum += angular_impulse;
  if (memory != nullptr)
    for (std::size_t i = 0; i < count; ++i)
      memory->impulses[contacts[i].point] = {contacts[i].normal_impulse, contacts[i].friction_x,
                                             contacts[i].friction_z};
  return true;
}

}  // namespace brisance::dynamics
