// sim/geometry/polygon: 2D simple polygons (the outlines of fracture fragments) — area,
// centroid, simplicity, point location, ear-clipping triangulation, extrusion to a prism mesh,
// closed-form prism mass properties (thesis §§6.3–6.4) and front-face load panels (thesis §6.2).
// Units: metres; polygons lie in the xy plane, a prism spans z in [−thickness/2, +thickness/2].
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

#include "sim/geometry/mesh.hpp"

namespace brisance::geometry {

using Vec2 = Eigen::Vector2d;
// Vertices in order, the first not repeated at the end. Either orientation unless stated.
using Polygon = std::vector<Vec2>;

// Shoelace area: positive for counter-clockwise vertices, m^2.
double signed_area(std::span<const Vec2> polygon);
// Area centroid (thesis eqs. 6.7–6.8). The polygon must have non-zero area.
Vec2 centroid(std::span<const Vec2> polygon);

// True if the polygon has at least three vertices, non-zero area, no zero-length edge, and no
// two edges meet except adjacent edges at their shared vertex (collinear consecutive vertices are
// allowed; an edge folding back over its neighbour is not).
bool is_simple(std::span<const Vec2> polygon);

// Whether p lies inside the polygon (even-odd crossing rule). Points exactly on the boundary may
// go either way.
bool contains(std::span<const Vec2> polygon, const Vec2& p);

// The polygon without vertices that lie on the straight line through their neighbours (within a
// relative tolerance of 1e-12 of the edge lengths), which is what crack polylines on a grid and
// fragment outlines with T-junctions produce a lot of. Keeps at least three vertices.
Polygon remove_collinear(std::span<const Vec2> polygon);

// Counter-clockwise triangles of a simple polygon (ear clipping, O(n^2)); indices into the
// polygon. Collinear vertices are skipped (they get no triangle of their own), so the triangles
// cover the polygon exactly but a collinear vertex need not be a triangle corner.
std::vector<std::array<std::uint32_t, 3>> triangulate(std::span<const Vec2> polygon);

// The closed prism of the polygon between z = −thickness/2 and +thickness/2, outward CCW winding
// (passes check_closed_mesh). Collinear vertices are dropped first so the caps and the side walls
// share every edge.
TriangleMesh extrude(std::span<const Vec2> polygon, double thickness_m);

// Mass properties of that prism in closed form (thesis eqs. 6.1–6.10, evaluated with Green's
// theorem over the polygon's edges rather than per triangle: the same integrals). The centre of
// mass has z = 0.
MassProperties prism_mass_properties(std::span<const Vec2> polygon, double thickness_m,
                                     double density_kg_m3);

// Load panels for the front face (z = +thickness/2, outward normal +Z) of the prism: at least
// min_panels (thesis §6.2 uses five) and at most max(min_panels, max_panels), with areas summing
// to the polygon's area. Panels are the triangulation's triangles, the largest split in half
// until there are enough; with too many, runs of consecutive triangles are merged (area-weighted
// centre), like the thesis's every-third-triangle sampling. face_half_size_m is half the minimal
// width of the polygon (the clearing distance S).
std::vector<Panel> front_panels(std::span<const Vec2> polygon, double thickness_m,
                                std::size_t min_panels = 5, std::size_t max_panels = 16);

// Smallest distance between two parallel lines enclosing the polygon, m.
double minimal_width(std::span<const Vec2> polygon);

}  // namespace brisance::geometry
