// sim/dynamics/convex: the collision shapes of bodies and the narrowphase between two of them
// (issue 13). A body collides as a few convex pieces in its own frame:
//   - a convex mesh (a box) is one piece, its faces merged by plane;
//   - a prism that is not convex (a fragment of a pane, extruded from a concave outline) is the
//     prism of its outline's convex hull (see prism_piece in convex.cpp for the rejected
//     decomposition into one triangular prism per triangle of its cap);
//   - any other closed mesh is its convex hull (up to kMaxHullVertices vertices; beyond, its
//     bounding box). A convex decomposition (V-HACD and kin) is a project of its own and a
//     user's concave mesh is rare in a blast scene; the hull keeps debris out of it, at the
//     price of resting on its hull.
// The narrowphase is separating axes (face normals of both pieces, cross products of their
// edge directions); on a face axis the manifold is the other piece's most opposed face clipped
// to the sides of the reference face (the corners of the overlap, not only the vertices of
// either piece: two boxes offset across each other touch over a rectangle one of whose corners
// is neither's vertex), the same kind of point contact as the ground's. See docs/simulator.md
// ("Contacts between bodies") for the benchmark that chose it over libccd's GJK/EPA.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "sim/dynamics/rigid_body.hpp"
#include "sim/geometry/mesh.hpp"

namespace brisance::dynamics {

struct ConvexPiece {
  std::vector<Vec3> vertices;                      // body frame, from the centre of mass, m
  std::vector<Vec3> normals;                       // outward unit face normals, body frame
  std::vector<double> offsets;                     // face planes: normal . x <= offset, m
  std::vector<Vec3> edge_directions;               // unit, one per parallel class
  std::vector<std::array<std::uint8_t, 2>> edges;  // vertex index pairs of the hull's edges
  std::vector<std::vector<std::uint8_t>> faces;    // per face: its vertices, in order around it
  Vec3 centre = Vec3::Zero();                      // of the vertices' bounding sphere
  double radius_m = 0.0;                           // of that sphere
};

struct CollisionShape {
  std::vector<ConvexPiece> pieces;
  bool from_hull = false;  // a concave mesh stood in for by its convex hull (or its box)
};

inline constexpr std::size_t kMaxHullVertices = 64;

// The collision shape of a closed mesh whose centre of mass is `centre_of_mass` (mesh frame).
CollisionShape collision_shape(const geometry::TriangleMesh& mesh, const Vec3& centre_of_mass);

// A piece placed in the world: its vertices, normals and edge directions, world frame.
struct PlacedPiece {
  std::vector<Vec3> vertices;
  std::vector<Vec3> normals;
  std::vector<double> offsets;
  std::vector<Vec3> edge_directions;
  const ConvexPiece* piece = nullptr;  // for the edge list
  Vec3 min, max;                       // world box, m
};
void place(const ConvexPiece& piece, const Vec3& position, const Mat3& rotation, PlacedPiece& out);
// The world box of the piece placed so, exactly the one place() gives (min and max are grown,
// not reset): the broadphase needs every moving body's box each step, the narrowphase the
// placed piece only for the pairs whose boxes meet.
void grow_box(const ConvexPiece& piece, const Vec3& position, const Mat3& rotation, Vec3& min,
              Vec3& max);

// One contact point between piece a and piece b: the normal points from a to b.
struct ContactPoint {
  Vec3 point;             // world, m, midway between the surfaces
  double depth_m;         // penetration along the normal; negative: a gap within the margin
  std::uint32_t feature;  // which vertex of which piece: stable while the pieces stay in touch
};

struct Manifold {
  Vec3 normal = Vec3::UnitY();  // world, unit, from a to b
  std::vector<ContactPoint> points;
};

// The contact points of pieces a and b if they are within `margin_m` of each other (written to
// `out`, replacing what it held); returns whether they touch. `feature_base` tags the points
// of this pair of pieces (a multiple of 256). A face contact of more than four points is cut
// to four (extremes across the normal) unless `all_points` (the caller then cuts them itself,
// after filtering them). A face contact is clipped `side_margin_m` outside the reference
// face's sides (negative: `margin_m`). `step` is how b moved relative to a in the step that
// brought them here: pieces that overlap now but were apart before it get the normal of the
// face they came through last, not of the least overlap (which, past the middle of a thin
// body, points out of its far side); pieces apart now that surely met within the step (one
// passed right through the other) get the axis they met through, as deep as one is past it.
struct StepMotion {
  Vec3 moved = Vec3::Zero();  // b's displacement relative to a's, m
  double turned_m = 0.0;      // how far the turns of both can have moved a point, m
};
bool collide(const PlacedPiece& a, const PlacedPiece& b, double margin_m,
             std::uint32_t feature_base, Manifold& out, bool all_points = false,
             double side_margin_m = -1.0, const StepMotion& step = {});

// Whether pieces a and b are farther than `margin_m` apart along one of their separating axes
// (a negative margin: overlap by less than its size along one of them); the test of collide
// without its manifold, stopping at the first such axis.
bool separated(const PlacedPiece& a, const PlacedPiece& b, double margin_m);

}  // namespace brisance::dynamics
