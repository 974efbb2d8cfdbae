// sim/dynamics: rigid bodies — their read-only model, their state, and one integration step
// under gravity, flight drag, damping and the blast's load impulses (thesis ch. 3, DESIGN.md
// decision 7); ground contact is in ground_contact.hpp. Knows nothing of blasts or scenes: the
// engine hands it impulses.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace brisance::dynamics {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;
using Quat = Eigen::Quaterniond;

// Which scheme advances a body over a step (the default is chosen by the run-time-versus-error
// study in bench/).
enum class Integrator {
  explicit_euler,       // thesis §3.5: v += a dt, x += mean velocity dt; explicit omega form of
                        // Euler's equation for the rotation
  semi_implicit_euler,  // v first, then x with the new v; angular momentum form
  rk4,                  // loads by their exact first moment, RK4 for drag and rotation
};

// A direction-dependent frontal area for drag: A(d) = 1/2 sum |n_i . d| A_i over the faces of
// a convex body; for a body with many faces the mean projection (surface area / 4, Cauchy).
// The first faces live inside the shape, not on the heap: a free body's step reads them every
// time, and 10 000 bodies' faces scattered over the heap cost cache misses every step. Few
// enough for a small model (a box has 3 after merging; measured: 16 inline made 10 000 free
// bodies 15-20 % slower than 4).
struct DragShape {
  static constexpr std::size_t kInlineFaces = 4;
  std::size_t face_count = 0;  // none: mean_area_m2
  double mean_area_m2 = 0.0;
  // Body frame: unit normal times the face's share of the area (m^2; opposite faces merged,
  // so already halved), so that A(d) = sum |face_i . d|. Faces beyond kInlineFaces: more_faces.
  std::array<Vec3, kInlineFaces> faces = {Vec3::Zero(), Vec3::Zero(), Vec3::Zero(), Vec3::Zero()};
  std::vector<Vec3> more_faces;
  void add_face(const Vec3& unit_normal, double area_m2);
  double projected_area_m2(const Vec3& direction_body) const;
};

// What a body is, fixed while stepping. The fields a step reads come first, so a step touches
// as few cache lines of the model as it can.
struct BodyModel {
  double inverse_mass = 1.0;
  // Set when the body axes are principal axes (boxes, most symmetric shapes): the hot path then
  // multiplies by a diagonal. Use set_inertia() to keep these consistent.
  bool diagonal_inertia = true;
  bool rotates = true;
  Vec3 inverse_inertia_diagonal = Vec3::Ones();
  double drag_coefficient = 1.0;
  double bounding_radius_m = 0.0;  // from the centre of mass
  DragShape drag_shape;
  double mass_kg = 1.0;
  Mat3 inertia_body = Mat3::Identity();  // about the centre of mass, body axes
  Mat3 inverse_inertia_body = Mat3::Identity();
  std::vector<Vec3> hull_points;  // body frame, relative to the centre of mass
};

struct BodyState {
  Vec3 position = Vec3::Zero();          // centre of mass, world, m
  Vec3 velocity = Vec3::Zero();          // world, m/s
  Quat orientation = Quat::Identity();   // body to world
  Vec3 angular_momentum = Vec3::Zero();  // world, about the centre of mass, kg m^2/s
};

// What the blast does to a body over one step [t0, t0 + dt], all world frame.
struct StepLoads {
  Vec3 impulse = Vec3::Zero();          // integral of F dt, N s
  Vec3 angular_impulse = Vec3::Zero();  // integral of r x F dt, N m s
  Vec3 impulse_moment = Vec3::Zero();   // integral of (t0 + dt - t) F dt, N s^2 (rk4 only)
};

struct WorldSettings {
  Vec3 gravity_m_s2 = Vec3(0.0, -9.81, 0.0);
  double air_density_kg_m3 = 1.225;
  double linear_damping_per_s = 0.0;
  double angular_damping_per_s = 0.0;
  Integrator integrator = Integrator::semi_implicit_euler;
  // Semi-implicit Euler only: a body whose torque-free turn over a step exceeds this angle turns
  // in as many equal substeps as keep each under it, rad; 0: one turn per step (the global step
  // is then kept short enough for the fastest spinner).
  double max_turn_per_substep_rad = 0.0;
};

// Sets inertia_body, its inverse and the diagonal fast path from a body-frame inertia tensor.
void set_inertia(BodyModel& model, const Mat3& inertia_kg_m2);

Vec3 angular_velocity(const BodyModel& model, const BodyState& state);
double kinetic_energy(const BodyModel& model, const BodyState& state);

// Advances one free body by dt; returns the angular velocity it turned with (world frame), an
// estimate of the current one that costs nothing extra. Flight drag acts on the velocity
// relative to the air, which moves with air_velocity over the step (the blast wind; still air:
// zero, which gives the still-air drag exactly).
Vec3 integrate(const BodyModel& model, BodyState& state, const StepLoads& loads,
               const WorldSettings& world, double dt, const Vec3& air_velocity = Vec3::Zero());

}  // namespace brisance::dynamics
