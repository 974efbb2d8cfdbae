// sim/geometry/mesh: boxes, the closed-mesh check, exact mass properties and load panels.
#include "sim/geometry/mesh.hpp"

#include <algorithm>
#include <array>
#include <cassert>
#include <cmath>
#include <cstddef>
#include <limits>
#include <numeric>
#include <sstream>
#include <tuple>
#include <utility>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>

#include "sim/geometry/disjoint_sets.hpp"

namespace brisance::geometry {

namespace {

using Vec2 = Eigen::Vector2d;

// A triangle smaller than this fraction of the squared bounding-box diagonal is degenerate.
constexpr double kDegenerateAreaFraction = 1e-12;
// A mesh enclosing less than this fraction of the cubed bounding-box diagonal encloses nothing.
constexpr double kFlatVolumeFraction = 1e-12;
// Edge-connected triangles belong to one face when their unit normals agree within this angle…
constexpr double kCoplanarAngleRad = 1e-6;
// …and the vertices of each lie within this fraction of the mesh's bounding-box diagonal from the
// other's plane. For edge-adjacent triangles this is the stricter test on any face wider than a
// thousandth of the mesh: it keeps slight folds apart, but not rounding noise.
constexpr double kCoplanarOffsetFraction = 1e-9;

struct Box3 {
  Vec3 min = Vec3::Constant(std::numeric_limits<double>::infinity());
  Vec3 max = Vec3::Constant(-std::numeric_limits<double>::infinity());
  Vec3 centre() const { return 0.5 * (min + max); }
  double diagonal() const { return (max - min).norm(); }
};

// Bounding box of the vertices the triangles use (unused vertices do not count). Indices must be
// in range.
Box3 used_bounding_box(const TriangleMesh& mesh) {
  Box3 box;
  for (const auto& tri : mesh.triangles) {
    for (std::uint32_t index : tri) {
      assert(index < mesh.vertices.size());
      box.min = box.min.cwiseMin(mesh.vertices[index]);
      box.max = box.max.cwiseMax(mesh.vertices[index]);
    }
  }
  return box;
}

// Twice the vector area of a triangle: (b − a) × (c − a), along the outward normal for CCW.
Vec3 doubled_vector_area(const TriangleMesh& mesh, const std::array<std::uint32_t, 3>& tri) {
  const Vec3& a = mesh.vertices[tri[0]];
  return (mesh.vertices[tri[1]] - a).cross(mesh.vertices[tri[2]] - a);
}

double triangle_area(const TriangleMesh& mesh, const std::array<std::uint32_t, 3>& tri) {
  return 0.5 * doubled_vector_area(mesh, tri).norm();
}

// Signed volume enclosed by the triangles, with tetrahedra apexed at `apex` (any point works for
// a closed mesh; a nearby one keeps the sum accurate far from the origin).
double signed_volume(const TriangleMesh& mesh, const Vec3& apex) {
  double six_volume = 0.0;
  for (const auto& tri : mesh.triangles) {
    const Vec3 a = mesh.vertices[tri[0]] - apex;
    const Vec3 b = mesh.vertices[tri[1]] - apex;
    const Vec3 c = mesh.vertices[tri[2]] - apex;
    six_volume += a.dot(b.cross(c));
  }
  return six_volume / 6.0;
}

// One directed edge of a triangle, keyed by its undirected vertex pair.
struct EdgeUse {
  std::uint32_t low = 0;
  std::uint32_t high = 0;
  std::uint32_t triangle = 0;
  bool low_to_high = true;  // the triangle runs low → high
};

// Every edge use, sorted by vertex pair and then triangle index, so the uses of one undirected
// edge are adjacent.
std::vector<EdgeUse> sorted_edge_uses(const TriangleMesh& mesh) {
  std::vector<EdgeUse> uses;
  uses.reserve(3 * mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int corner = 0; corner < 3; ++corner) {
      const std::uint32_t from = tri[corner];
      const std::uint32_t to = tri[(corner + 1) % 3];
      uses.push_back(
          {std::min(from, to), std::max(from, to), static_cast<std::uint32_t>(t), from < to});
    }
  }
  std::sort(uses.begin(), uses.end(), [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.low, x.high, x.triangle) < std::tie(y.low, y.high, y.triangle);
  });
  return uses;
}

// The uses of the undirected edge {a, b} within sorted_edge_uses' result.
std::pair<std::size_t, std::size_t> edge_range(const std::vector<EdgeUse>& uses, std::uint32_t a,
                                               std::uint32_t b) {
  const EdgeUse key{std::min(a, b), std::max(a, b), 0, true};
  const auto by_pair = [](const EdgeUse& x, const EdgeUse& y) {
    return std::tie(x.low, x.high) < std::tie(y.low, y.high);
  };
  const auto [first, last] = std::equal_range(uses.begin(), uses.end(), key, by_pair);
  return {static_cast<std::size_t>(first - uses.begin()),
          static_cast<std::size_t>(last - uses.begin())};
}

// Why the edges do not close the surface consistently, naming the lowest-indexed triangle at
// fault, or nullopt if every undirected edge is used exactly twice, once in each direction.
std::optional<std::string> check_edges(const TriangleMesh& mesh) {
  const std::vector<EdgeUse> uses = sorted_edge_uses(mesh);
  // How many undirected edges are open (one triangle) and how many are shared by more than two,
  // so a message about the first one also says how much there is to mend.
  std::size_t open_edges = 0;
  std::size_t crowded_edges = 0;
  for (std::size_t first = 0; first < uses.size();) {
    std::size_t last = first + 1;
    while (last < uses.size() && uses[last].low == uses[first].low &&
           uses[last].high == uses[first].high)
      ++last;
    if (last - first == 1) ++open_edges;
    if (last - first > 2) ++crowded_edges;
    first = last;
  }
  const auto edges = [](std::size_t count) {
    return std::to_string(count) + (count == 1 ? " edge" : " edges");
  };
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const auto& tri = mesh.triangles[t];
    for (int corner = 0; corner < 3; ++corner) {
      const std::uint32_t from = tri[corner];
      const std::uint32_t to = tri[(corner + 1) % 3];
      const auto [first, last] = edge_range(uses, from, to);
      const std::size_t count = last - first;
      std::ostringstream message;
      if (count == 1) {
        message << "the mesh is open (" << edges(open_edges) << " open): edge (" << from << ", "
                << to << ") of triangle " << t << " belongs to no other triangle; close the holes";
        return message.str();
      }
      if (count > 2) {
        message << "the mesh is not manifold (" << edges(crowded_edges)
                << " shared by more than two triangles): edge (" << from << ", " << to
                << ") is shared by " << count << " triangles (";
        for (std::size_t u = first; u < last; ++u)
          message << (u == first ? "" : ", ") << "triangle " << uses[u].triangle;
        message << "); every edge must join exactly two triangles";
        return message.str();
      }
      if (uses[first].low_to_high == uses[first + 1].low_to_high) {
        const std::uint32_t other =
            uses[first].triangle == t ? uses[first + 1].triangle : uses[first].triangle;
        message << "triangle " << t << " and triangle " << other << " both run edge " << from
                << " -> " << to
                << " in the same direction: the winding is inconsistent; flip one of them so "
                   "that all triangles wind counter-clockwise seen from outside";
        return message.str();
      }
    }
  }
  return std::nullopt;
}

// A unit vector perpendicular to the unit vector n.
Vec3 any_perpendicular(const Vec3& n) {
  Eigen::Index least_aligned = 0;
  n.cwiseAbs().minCoeff(&least_aligned);
  return n.cross(Vec3::Unit(least_aligned)).normalized();
}

double cross2(const Vec2& o, const Vec2& a, const Vec2& b) {
  return (a.x() - o.x()) * (b.y() - o.y()) - (a.y() - o.y()) * (b.x() - o.x());
}

// Convex hull of 2D points, counter-clockwise, without collinear or repeated points (Andrew's
// monotone chain: A. M. Andrew, Inf. Process. Lett. 9(5), 1979).
std::vector<Vec2> convex_hull(std::vector<Vec2> points) {
  std::sort(points.begin(), points.end(), [](const Vec2& p, const Vec2& q) {
    return p.x() < q.x() || (p.x() == q.x() && p.y() < q.y());
  });
  if (points.size() < 3) return points;
  std::vector<Vec2> hull(2 * points.size());
  std::size_t size = 0;
  for (const Vec2& p : points) {  // lower chain
    while (size >= 2 && cross2(hull[size - 2], hull[size - 1], p) <= 0.0)
      --size;
    hull[size++] = p;
  }
  const std::size_t lower_size = size + 1;
  for (std::size_t i = points.size() - 1; i-- > 0;) {  // upper chain
    while (size >= lower_size && cross2(hull[size - 2], hull[size - 1], points[i]) <= 0.0)
      --size;
    hull[size++] = points[i];
  }
  hull.resize(size - 1);  // the last point repeats the first
  return hull;
}

// Minimal width of a set of 2D points: the smallest distance between two parallel lines that
// enclose them. It is attained with one line through an edge of the convex hull, so rotating
// calipers (Toussaint, "Solving geometric problems with the rotating calipers", 1983) find it in
// linear time over the hull.
double minimal_width(const std::vector<Vec2>& points) {
  const std::vector<Vec2> hull = convex_hull(points);
  const std::size_t n = hull.size();
  if (n < 3) return 0.0;
  double width = std::numeric_limits<double>::infinity();
  std::size_t far = 1;  // hull vertex farthest from the current edge; advances monotonically
  for (std::size_t i = 0; i < n; ++i) {
    const Vec2& a = hull[i];
    const Vec2& b = hull[(i + 1) % n];
    while (cross2(a, b, hull[(far + 1) % n]) > cross2(a, b, hull[far]))
      far = (far + 1) % n;
    width = std::min(width, cross2(a, b, hull[far]) / (b - a).norm());
  }
  return width;
}

// What make_panels knows about one triangle.
struct TriangleInfo {
  Vec3 unit_normal = Vec3::Zero();
  double area_m2 = 0.0;
  bool usable = false;  // false for a zero-area triangle, which has no normal and no panel
};

// Whether two edge-adjacent triangles lie in one plane (see the thresholds above).
bool coplanar(const TriangleMesh& mesh, std::size_t s, std::size_t t,
              const std::vector<TriangleInfo>& info, double offset_tolerance_m) {
  const Vec3& ns = info[s].unit_normal;
  const Vec3& nt = info[t].unit_normal;
  // atan2 keeps small angles accurate where acos of a dot product near 1 would not.
  if (std::atan2(ns.cross(nt).norm(), ns.dot(nt)) > kCoplanarAngleRad) return false;
  const auto off_plane = [&](std::size_t plane, std::size_t points) {
    const Vec3& origin = mesh.vertices[mesh.triangles[plane][0]];
    double worst = 0.0;
    for (std::uint32_t index : mesh.triangles[points])
      worst = std::max(worst, std::abs(info[plane].unit_normal.dot(mesh.vertices[index] - origin)));
    return worst;
  };
  return off_plane(s, t) <= offset_tolerance_m && off_plane(t, s) <= offset_tolerance_m;
}

// Groups of edge-connected coplanar triangles, each listed in triangle order, the groups ordered
// by their first triangle. Zero-area triangles belong to no group.
std::vector<std::vector<std::uint32_t>> coplanar_faces(const TriangleMesh& mesh,
                                                       const std::vector<TriangleInfo>& info,
                                                       double offset_tolerance_m) {
  DisjointSets sets(mesh.triangles.size());
  const std::vector<EdgeUse> uses = sorted_edge_uses(mesh);
  for (std::size_t first = 0; first < uses.size();) {
    std::size_t last = first + 1;
    while (last < uses.size() && uses[last].low == uses[first].low &&
           uses[last].high == uses[first].high)
      ++last;
    // Normally two triangles share an edge; try every pair so odd meshes still group sensibly.
    for (std::size_t i = first; i < last; ++i) {
      for (std::size_t j = i + 1; j < last; ++j) {
        const std::size_t s = uses[i].triangle;
        const std::size_t t = uses[j].triangle;
        if (s != t && info[s].usable && info[t].usable &&
            coplanar(mesh, s, t, info, offset_tolerance_m))
          sets.unite(s, t);
      }
    }
    first = last;
  }

  constexpr std::size_t kNoFace = std::numeric_limits<std::size_t>::max();
  std::vector<std::vector<std::uint32_t>> faces;
  std::vector<std::size_t> face_of_root(mesh.triangles.size(), kNoFace);
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    if (!info[t].usable) continue;
    const std::size_t root = sets.find(t);
    if (face_of_root[root] == kNoFace) {
      face_of_root[root] = faces.size();
      faces.emplace_back();
    }
    faces[face_of_root[root]].push_back(static_cast<std::uint32_t>(t));
  }
  return faces;
}

// Half the minimal width of a face's vertices measured in its plane: the clearing distance S.
// Rejected: extents along the principal axes of the face's area second moment, which are
// arbitrary for a square (its second moment is isotropic) and then give up to √2 too much.
double face_half_size(const TriangleMesh& mesh, const std::vector<std::uint32_t>& face,
                      const Vec3& normal, const Vec3& origin) {
  const Vec3 u = any_perpendicular(normal);
  const Vec3 v = normal.cross(u);
  std::vector<std::uint32_t> corners;
  corners.reserve(3 * face.size());
  for (std::uint32_t t : face)
    corners.insert(corners.end(), mesh.triangles[t].begin(), mesh.triangles[t].end());
  std::sort(corners.begin(), corners.end());
  corners.erase(std::unique(corners.begin(), corners.end()), corners.end());
  std::vector<Vec2> points;
  points.reserve(corners.size());
  for (std::uint32_t index : corners) {
    const Vec3 r = mesh.vertices[index] - origin;
    points.emplace_back(r.dot(u), r.dot(v));
  }
  return 0.5 * minimal_width(points);
}

// The triangles' normals and areas and their grouping into faces: what make_panels and
// count_panels both start from, so they cannot disagree about the faces.
struct PanelFaces {
  Box3 box;
  std::vector<TriangleInfo> info;
  std::vector<std::vector<std::uint32_t>> faces;
};

PanelFaces panel_faces(const TriangleMesh& mesh) {
  PanelFaces result;
  result.box = used_bounding_box(mesh);
  result.info.resize(mesh.triangles.size());
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    TriangleInfo& info = result.info[t];
    const Vec3 doubled = doubled_vector_area(mesh, mesh.triangles[t]);
    const double doubled_norm = doubled.norm();
    info.usable = doubled_norm > 0.0 && std::isfinite(doubled_norm);
    if (!info.usable) continue;
    info.unit_normal = doubled / doubled_norm;
    info.area_m2 = 0.5 * doubled_norm;
  }
  result.faces = coplanar_faces(mesh, result.info, kCoplanarOffsetFraction * result.box.diagonal());
  return result;
}

// A face's area (summed in triangle order), m^2.
struct FaceArea {
  double area_m2 = 0.0;
};

FaceArea face_area(const std::vector<std::uint32_t>& face, const std::vector<TriangleInfo>& info) {
  FaceArea result;
  for (std::uint32_t t : face) {
    result.area_m2 += info[t].area_m2;
  }
  return result;
}

// The panels of a face larger than max_panel_area_m2: a grid of equal rectangular cells in the
// face's plane, along the principal axes of its area and centred on its centroid, each cell's
// panel the part of the face inside it (its exact area and centroid, from the face's triangles
// clipped to the cell). The grid does not depend on how the face is triangulated, and it is
// symmetric wherever the face is, so a symmetric wave puts no torque on a symmetric face.
class FaceGrid {
 public:
  FaceGrid(const TriangleMesh& mesh, const std::vector<std::uint32_t>& face,
           const std::vector<TriangleInfo>& info, const Vec3& normal, const Vec3& centre,
           double max_panel_area_m2)
      : mesh_(mesh), face_(face), centre_(centre) {
    // Second moment of the face's area about its centroid in a plane basis (e1, e2), from
    // integral of x x^T over a triangle = A/12 (a a^T + b b^T + c c^T + s s^T), s = a + b + c.
    const Vec3 e1 = any_perpendicular(normal);
    const Vec3 e2 = normal.cross(e1);
    Eigen::Matrix2d second = Eigen::Matrix2d::Zero();
    for (std::uint32_t t : face) {
      Vec2 corner[3];
      for (int k = 0; k < 3; ++k) {
        const Vec3 r = mesh.vertices[mesh.triangles[t][static_cast<std::size_t>(k)]] - centre;
        corner[k] = Vec2(r.dot(e1), r.dot(e2));
      }
      const Vec2 sum = corner[0] + corner[1] + corner[2];
      second += info[t].area_m2 / 12.0 *
                (corner[0] * corner[0].transpose() + corner[1] * corner[1].transpose() +
                 corner[2] * corner[2].transpose() + sum * sum.transpose());
    }
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> solver(second);
    const Vec2 axis =
        solver.eigenvalues()(1) - solver.eigenvalues()(0) > 1e-9 * solver.eigenvalues()(1)
            ? Vec2(solver.eigenvectors().col(1))
            : Vec2(1.0, 0.0);  // no principal direction: any, say e1
    u_ = axis.x() * e1 + axis.y() * e2;
    v_ = normal.cross(u_);
    double half_u = 0.0, half_v = 0.0;
    for (std::uint32_t t : face) {
      for (std::uint32_t index : mesh.triangles[t]) {
        const Vec3 r = mesh.vertices[index] - centre;
        half_u = std::max(half_u, std::abs(r.dot(u_)));
        half_v = std::max(half_v, std::abs(r.dot(v_)));
      }
    }
    // Square-ish cells of side at most sqrt(max area), at most kMaxCellsPerFace of them.
    const double side = std::sqrt(max_panel_area_m2);
    const double most = static_cast<double>(kMaxCellsPerFace);
    double along_u = std::clamp(std::ceil(2.0 * half_u / side), 1.0, most);
    double along_v = std::clamp(std::ceil(2.0 * half_v / side), 1.0, most);
    while (along_u * along_v > most) {
      along_u = std::max(1.0, std::floor(along_u / 2.0));
      along_v = std::max(1.0, std::floor(along_v / 2.0));
    }
    cells_u_ = static_cast<std::size_t>(along_u);
    cells_v_ = static_cast<std::size_t>(along_v);
    origin_ = Vec2(-half_u, -half_v);
    cell_ = Vec2(2.0 * half_u / static_cast<double>(cells_u_),
                 2.0 * half_v / static_cast<double>(cells_v_));
  }

  // Calls visit(area, centroid) for each cell the face covers, in cell order.
  template <typename Visit>
  void for_each_panel(Visit&& visit) const {
    const std::size_t n = cells_u_ * cells_v_;
    std::vector<double> area(n, 0.0);
    std::vector<Vec2> moment(n, Vec2::Zero());
    for (std::uint32_t t : face_) {
      Polygon2 triangle;
      for (std::uint32_t index : mesh_.triangles[t]) {
        const Vec3 r = mesh_.vertices[index] - centre_;
        triangle.push(Vec2(r.dot(u_), r.dot(v_)) - origin_);
      }
      Vec2 low = triangle.point[0], high = triangle.point[0];
      for (std::size_t k = 1; k < 3; ++k) {
        low = low.cwiseMin(triangle.point[k]);
        high = high.cwiseMax(triangle.point[k]);
      }
      const std::size_t i0 = cell_index(low.x(), cell_.x(), cells_u_);
      const std::size_t i1 = cell_index(high.x(), cell_.x(), cells_u_);
      const std::size_t j0 = cell_index(low.y(), cell_.y(), cells_v_);
      const std::size_t j1 = cell_index(high.y(), cell_.y(), cells_v_);
      for (std::size_t j = j0; j <= j1; ++j) {
        for (std::size_t i = i0; i <= i1; ++i) {
          // The outer cells reach to infinity, so rounding at the face's rim loses nothing.
          const double x0 = i == 0 ? -INFINITY : static_cast<double>(i) * cell_.x();
          const double x1 = i + 1 == cells_u_ ? INFINITY : static_cast<double>(i + 1) * cell_.x();
          const double y0 = j == 0 ? -INFINITY : static_cast<double>(j) * cell_.y();
          const double y1 = j + 1 == cells_v_ ? INFINITY : static_cast<double>(j + 1) * cell_.y();
          Polygon2 piece = triangle;
          piece = clip(piece, 0, x0, +1.0);
          piece = clip(piece, 0, x1, -1.0);
          piece = clip(piece, 1, y0, +1.0);
          piece = clip(piece, 1, y1, -1.0);
          double doubled = 0.0;
          Vec2 six_moment = Vec2::Zero();
          for (std::size_t k = 0; k < piece.size; ++k) {
            const Vec2& a = piece.point[k];
            const Vec2& b = piece.point[(k + 1) % piece.size];
            const double cross = a.x() * b.y() - b.x() * a.y();
            doubled += cross;
            six_moment += cross * (a + b);
          }
          area[j * cells_u_ + i] += 0.5 * doubled;
          moment[j * cells_u_ + i] += six_moment / 6.0;
        }
      }
    }
    const double smallest = 1e-12 * cell_.x() * cell_.y();
    for (std::size_t c = 0; c < n; ++c) {
      if (!(area[c] > smallest)) continue;
      const Vec2 local = moment[c] / area[c] + origin_;
      visit(area[c], centre_ + local.x() * u_ + local.y() * v_);
    }
  }

 private:
  // A convex polygon of at most 7 corners (a triangle clipped by four half-planes).
  struct Polygon2 {
    Polygon2() { point.fill(Vec2::Zero()); }
    std::array<Vec2, 8> point;
    std::size_t size = 0;
    void push(const Vec2& p) { point[size++] = p; }
  };

  static std::size_t cell_index(double x, double cell, std::size_t cells) {
    const double i = std::floor(x / cell);
    if (!(i > 0.0)) return 0;
    return std::min(cells - 1, static_cast<std::size_t>(i));
  }

  // The part of `in` where sign * (p[axis] - bound) >= 0 (Sutherland–Hodgman, one edge).
  static Polygon2 clip(const Polygon2& in, int axis, double bound, double sign) {
    if (!std::isfinite(bound) || in.size == 0) return in;
    Polygon2 out;
    for (std::size_t k = 0; k < in.size; ++k) {
      const Vec2& a = in.point[k];
      const Vec2& b = in.point[(k + 1) % in.size];
      const double da = sign * (a[axis] - bound);
      const double db = sign * (b[axis] - bound);
      if (da >= 0.0) out.push(a);
      if ((da >= 0.0) != (db >= 0.0)) out.push(a + (b - a) * (da / (da - db)));
    }
    return out;
  }

  static constexpr std::size_t kMaxCellsPerFace = std::size_t{1} << 16;
  const TriangleMesh& mesh_;
  const std::vector<std::uint32_t>& face_;
  Vec3 centre_;
  Vec3 u_ = Vec3::UnitX();
  Vec3 v_ = Vec3::UnitY();
  Vec2 origin_ = Vec2::Zero();
  Vec2 cell_ = Vec2::Ones();
  std::size_t cells_u_ = 1;
  std::size_t cells_v_ = 1;
};

}  // namespace

TriangleMesh make_box(const Vec3& size_m) {
  assert(size_m.allFinite() && (size_m.array() > 0.0).all());
  const Vec3 half = 0.5 * size_m;
  TriangleMesh mesh;
  // Vertex i has x, y, z at +half where bits 0, 1, 2 of i are set, at −half otherwise.
  for (int i = 0; i < 8; ++i) {
    mesh.vertices.emplace_back((i & 1) ? half.x() : -half.x(), (i & 2) ? half.y() : -half.y(),
                               (i & 4) ? half.z() : -half.z());
  }
  // Each face as a quad counter-clockwise seen from outside, split along its first diagonal.
  constexpr std::array<std::array<std::uint32_t, 4>, 6> quads = {{
      {0, 4, 6, 2},  // −x
      {1, 3, 7, 5},  // +x
      {0, 1, 5, 4},  // −y
      {2, 6, 7, 3},  // +y
      {0, 2, 3, 1},  // −z
      {4, 5, 7, 6},  // +z
  }};
  for (const auto& q : quads) {
    mesh.triangles.push_back({q[0], q[1], q[2]});
    mesh.triangles.push_back({q[0], q[2], q[3]});
  }
  return mesh;
}

std::optional<std::string> check_closed_mesh(const TriangleMesh& mesh) {
  std::ostringstream message;
  if (mesh.triangles.empty()) return "the mesh has no triangles; give at least four";

  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    for (std::uint32_t index : mesh.triangles[t]) {
      if (index >= mesh.vertices.size()) {
        message << "triangle " << t << " uses vertex " << index << ", but the mesh has only "
                << mesh.vertices.size() << " vertices (indices start at 0)";
        return message.str();
      }
    }
  }

  for (std::size_t i = 0; i < mesh.vertices.size(); ++i) {
    if (!mesh.vertices[i].allFinite()) {
      const Vec3& p = mesh.vertices[i];
      message << "vertex " << i << " is not finite (" << p.x() << ", " << p.y() << ", " << p.z()
              << ")";
      return message.str();
    }
  }

  // Degeneracy relative to the mesh's size, so a millimetre-sized mesh is not rejected wholesale.
  const Box3 box = used_bounding_box(mesh);
  const double diagonal_m = box.diagonal();
  const double min_area_m2 = kDegenerateAreaFraction * diagonal_m * diagonal_m;
  for (std::size_t t = 0; t < mesh.triangles.size(); ++t) {
    const double area_m2 = triangle_area(mesh, mesh.triangles[t]);
    if (!(area_m2 > min_area_m2)) {
      message << "triangle " << t << " is degenerate: its area " << area_m2
              << " m^2 is below 1e-12 of the squared bounding-box diagonal; remove it or move "
                 "its vertices apart";
      return message.str();
    }
  }

  if (auto edge_problem = check_edges(mesh)) return edge_problem;

  const double volume_m3 = signed_volume(mesh, box.centre());
  const double min_volume_m3 = kFlatVolumeFraction * diagonal_m * diagonal_m * diagonal_m;
  if (volume_m3 < -min_volume_m3) {
    message << "the mesh is wound inward (signed volume " << volume_m3
            << " m^3): reverse the vertex order of every triangle so they wind "
               "counter-clockwise seen from outside";
    return message.str();
  }
  if (!(volume_m3 > min_volume_m3)) {
    message << "the mesh encloses no volume (signed volume " << volume_m3 << " m^3)";
    return message.str();
  }
  return std::nullopt;
}

// Exact mass properties by the divergence theorem: the solid is the signed sum of tetrahedra
// joining a fixed apex to each triangle (Eberly, "Polyhedral Mass Properties (Revisited)", 2002;
// Tonon, "Explicit exact formulas for the 3-D tetrahedron inertia tensor in terms of its vertex
// coordinates", J. Math. Stat. 1(1)). For a tetrahedron with vertices 0, a, b, c and signed
// volume V = a·(b×c)/6:
//   ∫ r dV = V (a + b + c)/4,    ∫ r rᵀ dV = V/20 (a aᵀ + b bᵀ + c cᵀ + s sᵀ),  s = a + b + c
// (Tonon's formulas for the moments and products, written as one covariance matrix). Two passes
// keep it accurate far from the origin: volume and centre of mass with the apex at the bounding-box
// centre, then the second moment with the apex at the centre of mass, so no large parallel-axis
// term is subtracted.
MassProperties mass_properties(const TriangleMesh& mesh, double density_kg_m3) {
  assert(std::isfinite(density_kg_m3) && density_kg_m3 > 0.0);
  const Vec3 reference = used_bounding_box(mesh).centre();

  double six_volume = 0.0;
  Vec3 twenty_four_first_moment = Vec3::Zero();  // 24 ∫ (r − reference) dV
  for (const auto& tri : mesh.triangles) {
    const Vec3 a = mesh.vertices[tri[0]] - reference;
    const Vec3 b = mesh.vertices[tri[1]] - reference;
    const Vec3 c = mesh.vertices[tri[2]] - reference;
    const double six_tet = a.dot(b.cross(c));
    six_volume += six_tet;
    twenty_four_first_moment += six_tet * (a + b + c);
  }
  assert(six_volume > 0.0);  // a closed, outward-wound mesh (see check_closed_mesh)

  MassProperties props;
  props.volume_m3 = six_volume / 6.0;
  props.mass_kg = density_kg_m3 * props.volume_m3;
  props.centre_of_mass = reference + twenty_four_first_moment / (4.0 * six_volume);

  Mat3 hundred_twenty_second_moment = Mat3::Zero();  // 120 ∫ (r − com)(r − com)ᵀ dV
  for (const auto& tri : mesh.triangles) {
    const Vec3 a = mesh.vertices[tri[0]] - props.centre_of_mass;
    const Vec3 b = mesh.vertices[tri[1]] - props.centre_of_mass;
    const Vec3 c = mesh.vertices[tri[2]] - props.centre_of_mass;
    const Vec3 s = a + b + c;
    hundred_twenty_second_moment += a.dot(b.cross(c)) * (a * a.transpose() + b * b.transpose() +
                                                         c * c.transpose() + s * s.transpose());
  }
  const Mat3 second_moment = hundred_twenty_second_moment / 120.0;
  // I = ρ ∫ (r·r E − r rᵀ) dV = ρ (tr(C) E − C).
  props.inertia_kg_m2 = density_kg_m3 * (second_moment.trace() * Mat3::Identity() - second_moment);
  return props;
}

namespace {

// A face's unit normal and area centroid (centroids summed relative to `reference`, for
// accuracy).
struct FaceFrame {
  Vec3 normal;
  Vec3 centre;
};

FaceFrame face_frame(const TriangleMesh& mesh, const std::vector<std::uint32_t>& face,
                     const std::vector<TriangleInfo>& info, double area_m2, const Vec3& reference) {
  Vec3 doubled_vector_area_sum = Vec3::Zero();
  Vec3 area_moment = Vec3::Zero();  // Σ area (centroid − reference)
  for (std::uint32_t t : face) {
    const auto& tri = mesh.triangles[t];
    const Vec3 centroid_from_reference =
        ((mesh.vertices[tri[0]] - reference) + (mesh.vertices[tri[1]] - reference) +
         (mesh.vertices[tri[2]] - reference)) /
        3.0;
    doubled_vector_area_sum += 2.0 * info[t].area_m2 * info[t].unit_normal;
    area_moment += info[t].area_m2 * centroid_from_reference;
  }
  return {doubled_vector_area_sum.normalized(), reference + area_moment / area_m2};
}

}  // namespace

std::vector<Panel> make_panels(const TriangleMesh& mesh, double max_panel_area_m2) {
  assert(max_panel_area_m2 > 0.0);  // also false for NaN
  std::vector<Panel> panels;
  if (mesh.triangles.empty()) return panels;

  const PanelFaces faces = panel_faces(mesh);
  const std::vector<TriangleInfo>& info = faces.info;
  for (const auto& face : faces.faces) {
    const FaceArea area = face_area(face, info);
    const FaceFrame frame = face_frame(mesh, face, info, area.area_m2, faces.box.centre());
    const double half_size_m = face_half_size(mesh, face, frame.normal, frame.centre);
    if (area.area_m2 <= max_panel_area_m2) {
      panels.push_back({frame.centre, frame.normal, area.area_m2, half_size_m});
      continue;
    }
    const FaceGrid grid(mesh, face, info, frame.normal, frame.centre, max_panel_area_m2);
    grid.for_each_panel([&](double area_m2, const Vec3& centroid) {
      panels.push_back({centroid, frame.normal, area_m2, half_size_m});
    });
  }
  return panels;
}

std::size_t count_panels(const TriangleMesh& mesh, double max_panel_area_m2) {
  assert(max_panel_area_m2 > 0.0);  // also false for NaN
  if (mesh.triangles.empty()) return 0;
  const PanelFaces faces = panel_faces(mesh);
  std::size_t count = 0;
  for (const auto& face : faces.faces) {
    const FaceArea area = face_area(face, faces.info);
    if (area.area_m2 <= max_panel_area_m2) {
      ++count;
      continue;
    }
    const FaceFrame frame = face_frame(mesh, face, faces.info, area.area_m2, faces.box.centre());
    const FaceGrid grid(mesh, face, faces.info, frame.normal, frame.centre, max_panel_area_m2);
    grid.for_each_panel([&](double, const Vec3&) { ++count; });
  }
  return count;
}

double surface_area(const TriangleMesh& mesh) {
  double area_m2 = 0.0;
  for (const auto& tri : mesh.triangles)
    area_m2 += triangle_area(mesh, tri);
  return area_m2;
}

}  // namespace brisance::geometry
