// sim/geometry: triangle meshes, their exact mass properties and the load panels cut from them.
// Units: metres, kilograms; every quantity is in the mesh's own frame unless stated.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace brisance::geometry {

using Vec3 = Eigen::Vector3d;
using Mat3 = Eigen::Matrix3d;

// A closed triangle mesh; triangles wind counter-clockwise seen from outside (outward normals).
struct TriangleMesh {
  std::vector<Vec3> vertices;                           // m, mesh frame
  std::vector<std::array<std::uint32_t, 3>> triangles;  // vertex indices
};

// A box of full edge lengths size (x, y, z), centred on the origin, 8 vertices and 12 triangles.
TriangleMesh make_box(const Vec3& size_m);

// Why a mesh cannot be simulated, or nullopt if it can: indices out of range, degenerate
// (zero-area) triangles, edges not shared by exactly two triangles (open or non-manifold),
// inconsistent winding, or inward winding (negative volume). The message names the first
// offending triangle or edge by index.
std::optional<std::string> check_closed_mesh(const TriangleMesh& mesh);

// Volume, centre of mass and inertia of a closed mesh of uniform density, computed exactly from
// its triangles (divergence theorem over signed tetrahedra).
struct MassProperties {
  double volume_m3 = 0.0;
  double mass_kg = 0.0;
  Vec3 centre_of_mass = Vec3::Zero();  // mesh frame
  Mat3 inertia_kg_m2 = Mat3::Zero();   // about the centre of mass, axes of the mesh frame
};
MassProperties mass_properties(const TriangleMesh& mesh, double density_kg_m3);

// A planar piece of the surface that the blast loads (thesis §3.5.1).
struct Panel {
  Vec3 centre = Vec3::Zero();           // area centroid, mesh frame
  Vec3 outward_normal = Vec3::UnitZ();  // unit
  double area_m2 = 0.0;
  // Half the smaller extent of the face the panel was cut from, m: the clearing distance S
  // of thesis eq. 2.31 for this face.
  double face_half_size_m = 0.0;
};

// Panels of a closed mesh: edge-connected coplanar triangles (normals within 1e-6 rad) are
// grouped into faces; a face no larger than max_panel_area_m2 is one panel, a larger one is cut
// into panels of at most that area by a grid along the principal axes of its area, centred on
// its centroid (each panel the part of the face in one cell, with its exact area and centroid),
// so a large face close to a charge is loaded panel by panel and the panels do not depend on how
// the face is triangulated. Panel areas sum to the mesh's surface area.
std::vector<Panel> make_panels(const TriangleMesh& mesh, double max_panel_area_m2);

// make_panels(mesh, max_panel_area_m2).size(), without making the panels: for limits checks.
std::size_t count_panels(const TriangleMesh& mesh, double max_panel_area_m2);

// Total surface area, m^2.
double surface_area(const TriangleMesh& mesh);

}  // namespace brisance::geometry
