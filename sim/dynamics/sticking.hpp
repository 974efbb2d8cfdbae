// sim/dynamics/sticking: the exact solve that brings every touching point of one body to rest
// at once, shared by the ground's solve and the body pairs' (a body whose partners are all
// static). Inline: the ground's solve runs it for every resting body in every step.
#pragma once

#include <cstddef>

#include "sim/dynamics/rigid_body.hpp"

namespace brisance::dynamics {

// The impulses at the touching points (`arms` from the centre of mass, world) that bring them
// all to rest: with three or more points not on one line the body stops, sum F_i = -m v and
// sum r_i x F_i = -L, and of the impulse sets that do it the least-squares one is taken; on
// one point the body turns about it keeping its angular momentum about it, on two about their
// edge keeping its angular momentum about the edge. `inertia()` gives the world inertia (asked
// only for one or two points). Returns false where the points cannot do it (three or more on
// one line, two coinciding); the caller then checks that every impulse pushes and stays in
// its Coulomb disc.
template <class WorldInertia>
[[gnu::always_inline]] inline bool sticking_impulses(const Vec3* arms, std::size_t count,
                                                     double mass_kg, const Vec3& velocity,
                                                     const Vec3& angular_momentum,
                                                     WorldInertia inertia, Vec3* forces,
                                                     Vec3& velocity_after, Vec3& momentum_after) {
  velocity_after = Vec3::Zero();
  momentum_after = Vec3::Zero();
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
    const Vec3 impulse = -mass_kg * velocity;
    const Vec3 torque = -angular_momentum - centroid.cross(impulse);  // about c
    // Points (nearly) on one line cannot take a torque about that line.
    const double scale = spread.trace() / 3.0;
    if (!(spread.determinant() > 1e-6 * scale * scale * scale)) return false;
    const Vec3 twist = spread.inverse() * torque;
    const Vec3 share = impulse / n;
    for (std::size_t i = 0; i < count; ++i)
      forces[i] = share + twist.cross(arms[i] - centroid);
    return true;
  }
  if (count == 0) return false;
  // Turning about the first point p: angular momentum about p, L - r x m v, is kept, with the
  // inertia about p (parallel axes); the centre then moves at r x w.
  const Vec3& arm = arms[0];
  const Mat3 world = inertia();
  Mat3 about_point = world - mass_kg * arm * arm.transpose();
  about_point.diagonal().array() += mass_kg * arm.squaredNorm();
  const Vec3 momentum_about = angular_momentum - arm.cross(mass_kg * velocity);
  Vec3 omega_after = Vec3::Zero();
  const Vec3 edge = count == 2 ? Vec3(arms[1] - arm) : Vec3::Zero();
  if (count == 1) {
    omega_after = about_point.inverse() * momentum_about;
  } else if (edge.squaredNorm() > 1e-12) {
    const Vec3 axis = edge.normalized();
    omega_after = (axis.dot(momentum_about) / axis.dot(about_point * axis)) * axis;
  } else {
    return false;
  }
  velocity_after = arm.cross(omega_after);
  momentum_after = world * omega_after;
  const Vec3 impulse = mass_kg * (velocity_after - velocity);
  if (count == 1) {
    forces[0] = impulse;
  } else {
    // The second point takes the torque about the first; the pair shares the push along their
    // edge equally.
    const Vec3 torque = momentum_after - angular_momentum - arm.cross(impulse);
    const Vec3 axis = edge.normalized();
    forces[1] = torque.cross(edge) / edge.squaredNorm() + 0.5 * impulse.dot(axis) * axis;
    forces[0] = impulse - forces[1];
  }
  return true;
}

}  // namespace brisance::dynamics
