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
Vec3 omega_of(const BodyModel& model, const Quat& orientation, const Vec3& angular_momentum) {
  if (!model.rotates) return Vec3::Zero();
  const Mat3 r = orientation.toRotationMatrix();
  const Vec3 local = r.transpose().lazyProduct(angular_momentum);
  const Vec3 spin = model.diagonal_inertia
                        ? Vec3(model.inverse_inertia_diagonal.cwiseProduct(local))
                        : Vec3(model.inverse_inertia_body.lazyProduct(local));
  return r.lazyProduct(spin);
}

// The rotation by the rotation vector w * dt, as a unit quaternion (exact for constant w).
Quat rotation_over(const Vec3& omega, double dt) {
  const double angle_squared = omega.squaredNorm() * dt * dt;
  if (angle_squared < 1e-2) {
    // Below 0.1 rad (every adaptive step) the Taylor series of cos(a/2) and sin(a/2)/a to
    // a^4 is exact to 3e-12 and saves the sine and cosine; the caller renormalises.
    const double a2 = angle_squared;
    const double c = 1.0 - a2 / 8.0 + a2 * a2 / 384.0;
    const double s = (0.5 - a2 / 48.0 + a2 * a2 / 3840.0) * dt;
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
void apply_drag(const BodyModel& model, BodyState& state, const WorldSettings& world, double dt) {
  if (world.air_density_kg_m3 <= 0.0) return;
  const double speed = state.velocity.norm();
  if (speed <= 0.0) return;
  const Vec3 direction_body = state.orientation.conjugate() * (state.velocity / speed);
  const double area = model.drag_shape.projected_area_m2(direction_body);
  const double k =
      0.5 * world.air_density_kg_m3 * model.drag_coefficient * area * model.inverse_mass;
  state.velocity /= 1.0 + k * speed * dt;
}

// Returns the angular velocity the step turned the body with (world frame).
Vec3 integrate_rotation(const BodyModel& model, BodyState& state, const StepLoads& loads,
                        const WorldSettings& world, double dt) {
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
      const Vec3 start_omega = omega_of(model, state.orientation, state.angular_momentum);
      const Quat half = rotation_over(start_omega, 0.5 * dt) * state.orientation;
      const Vec3 omega = omega_of(model, half, state.angular_momentum);
      state.orientation = (rotation_over(omega, dt) * state.orientation).normalized();
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

double DragShape::projected_area_m2(const Vec3& direction_body) const {
  if (face_normals.empty()) return mean_area_m2;
  double area = 0.0;
  for (std::size_t i = 0; i < face_normals.size(); ++i)
    area += std::abs(face_normals[i].dot(direction_body)) * face_areas[i];
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
  switch (world.integrator) {
    case Integrator::explicit_euler: {
      // Thesis §3.5: constant acceleration over the step, velocity first, then the displacement
      // from the average of the old and new velocities.
      const Vec3 start_velocity = state.velocity;
      state.velocity += velocity_change;
      apply_drag(model, state, world, dt);
      state.position += 0.5 * (start_velocity + state.velocity) * dt;
      break;
    }
    case Integrator::semi_implicit_euler:
      state.velocity += velocity_change;
      apply_drag(model, state, world, dt);
      state.position += state.velocity * dt;
      break;
    case Integrator::rk4:
      // Gravity and the load are integrated exactly: the load moves the body by its first moment.
      state.position += state.velocity * dt + 0.5 * world.gravity_m_s2 * dt * dt +
                        loads.impulse_moment * model.inverse_mass;
      state.velocity += velocity_change;
      apply_drag(model, state, world, dt);
      break;
  }
  if (world.linear_damping_per_s > 0.0)
    state.velocity *= std::exp(-world.linear_damping_per_s * dt);
  return integrate_rotation(model, state, loads, world, dt);
}

bool resolve_ground_contact(const BodyModel& model, BodyState& state, const Ground& ground,
                            ContactMemory* memory) {
  constexpr double kContactMargin_m = 1e-4;     // points this close count as touching
  constexpr double kBounceThreshold_m_s = 0.5;  // slower impacts do not bounce (no jitter)
  constexpr int kIterations = 8;
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

  // Per contact, everything that stays fixed over the sweeps: for the normal and the two ground
  // axes, the angular velocity one unit of impulse adds (I^-1 (r x axis)) and the effective
  // mass, so a sweep is a few dot products (friction along the fixed x and z axes, clamped to the
  // Coulomb disc).
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
  std::array<Contact, 16> contacts;
  std::size_t count = 0;
  const Mat3 inverse = inverse_inertia_world(model, state.orientation);
  Vec3 omega = inverse * state.angular_momentum;
  auto axis = [&](const Vec3& arm, const Vec3& direction) {
    const Vec3 lever = arm.cross(direction);
    const Vec3 spin = inverse * lever;
    return Axis{spin, model.inverse_mass + lever.dot(spin)};
  };
  for (std::size_t i = 0; i < model.hull_points.size(); ++i) {
    const Vec3 arm = r * model.hull_points[i];
    const bool touching = state.position.y() + arm.y() <= ground.height_m + kContactMargin_m;
    if (!touching || count == contacts.size()) {
      if (memory != nullptr) memory->impulses[i] = {};
      continue;
    }
    contacts[count++] = Contact{i,
                                arm,
                                (state.velocity + omega.cross(arm)).y(),
                                axis(arm, up),
                                axis(arm, Vec3::UnitX()),
                                axis(arm, Vec3::UnitZ())};
  }
  Vec3 linear = state.velocity;
  Vec3 angular_impulse = Vec3::Zero();
  auto push = [&](const Contact& c, const Vec3& direction, const Axis& a, double impulse) {
    linear += impulse * model.inverse_mass * direction;
    omega += impulse * a.spin;
    angular_impulse += c.arm.cross(impulse * direction);
  };
  if (memory != nullptr) {
    // Warm start: last step's impulses (friction kept inside the Coulomb disc).
    for (std::size_t i = 0; i < count; ++i) {
      Contact& c = contacts[i];
      const auto& last = memory->impulses[c.point];
      c.normal_impulse = std::max(0.0, last[0]);
      const double limit = ground.friction * c.normal_impulse;
      const double magnitude = std::hypot(last[1], last[2]);
      const double scale = magnitude > limit && magnitude > 0.0 ? limit / magnitude : 1.0;
      c.friction_x = last[1] * scale;
      c.friction_z = last[2] * scale;
      push(c, up, c.normal, c.normal_impulse);
      push(c, Vec3::UnitX(), c.along_x, c.friction_x);
      push(c, Vec3::UnitZ(), c.along_z, c.friction_z);
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
      push(c, up, c.normal, dn);
      // Coulomb friction against the sliding velocity, within mu times the normal impulse.
      const Vec3 v = linear + omega.cross(c.arm);
      double fx = c.friction_x - v.x() / c.along_x.inverse_mass;
      double fz = c.friction_z - v.z() / c.along_z.inverse_mass;
      const double limit = ground.friction * c.normal_impulse;
      const double magnitude = std::hypot(fx, fz);
      if (magnitude > limit) {
        const double scale = magnitude > 0.0 ? limit / magnitude : 0.0;
        fx *= scale;
        fz *= scale;
      }
      const double dx = fx - c.friction_x, dz = fz - c.friction_z;
      c.friction_x = fx;
      c.friction_z = fz;
      push(c, Vec3::UnitX(), c.along_x, dx);
      push(c, Vec3::UnitZ(), c.along_z, dz);
      largest_change = std::max({largest_change, std::abs(dn), std::abs(dx), std::abs(dz)});
    }
    // Converged: a further sweep would change velocities by under 1 um/s.
    if (largest_change * model.inverse_mass < 1e-6) break;
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
