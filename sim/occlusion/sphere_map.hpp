// sim/occlusion/sphere_map: the icosahedral pixelisation of the sphere of directions around a
// charge (thesis §4.2.1, fig. 4.3). Each of the 20 faces of a regular icosahedron is rastered
// into rows of square-ish pixels (the thesis's reference is 32 pixels along a face's base and 28
// rows); a direction belongs to the face whose centre is nearest (the faces' central projections
// tile the sphere) and to the pixel its gnomonic projection falls in. Pixels are numbered
// 0..pixel_count()-1 across all faces, and every pixel knows its neighbours across face edges, so
// distances on the map do not stop at the seams of the planar fold-out.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <vector>

#include <Eigen/Core>

namespace brisance::occlusion {

using Vec3 = Eigen::Vector3d;
using Vec2 = Eigen::Vector2d;

class SphereMap {
 public:
  // columns: pixels along a face's base; rows: pixel rows from base to apex. Both >= 2.
  SphereMap(int columns, int rows);

  int columns() const { return columns_; }
  int rows() const { return rows_; }
  std::uint32_t pixel_count() const { return static_cast<std::uint32_t>(pixel_face_.size()); }

  // The pixel a direction (any length > 0) falls in.
  std::uint32_t pixel_of(const Vec3& direction) const;
  // Unit direction through the centre of a pixel.
  const Vec3& pixel_direction(std::uint32_t pixel) const { return pixel_direction_[pixel]; }
  // The up to four edge neighbours of a pixel (across face edges too).
  std::span<const std::uint32_t> neighbours(std::uint32_t pixel) const;

  // Face geometry, for rasterising: the face's unit centre direction, the distance of its plane
  // from the centre (the icosahedron is inscribed in the unit sphere), and its plane's 2D frame
  // (origin at the face's first corner, axis_u along its base, axis_v towards its apex).
  struct Face {
    Vec3 centre_direction;
    double plane_distance = 0.0;
    Vec3 origin;
    Vec3 axis_u;
    Vec3 axis_v;
    double cos_angular_radius = 0.0;  // cos of the angle from centre_direction to a corner
  };
  static constexpr int kFaces = 20;
  const Face& face(int f) const { return faces_[static_cast<std::size_t>(f)]; }
  double edge_length() const { return edge_; }
  double pixel_width() const { return pixel_width_; }
  double pixel_height() const { return pixel_height_; }

  // The pixels of face f in row j (rows are alike on every face): columns first_column(j) ..
  // last_column(j), numbered consecutively from row_start(f, j).
  int first_column(int row) const { return row_first_[static_cast<std::size_t>(row)]; }
  int last_column(int row) const { return row_last_[static_cast<std::size_t>(row)]; }
  std::uint32_t row_start(int f, int row) const {
    return face_start_[static_cast<std::size_t>(f)] + row_offset_[static_cast<std::size_t>(row)];
  }
  // The 2D centre (in the face plane's frame) of column i, row j.
  Vec2 cell_centre(int column, int row) const {
    return {(column + 0.5) * pixel_width_, (row + 0.5) * pixel_height_};
  }

 private:
  int face_of(const Vec3& direction) const;
  std::uint32_t pixel_in_face(int f, const Vec3& direction) const;

  int columns_;
  int rows_;
  double edge_ = 0.0;
  double pixel_width_ = 0.0;
  double pixel_height_ = 0.0;
  std::array<Face, kFaces> faces_{};
  std::vector<int> row_first_, row_last_;           // per row, same for every face
  std::vector<std::uint32_t> row_offset_;           // per row, pixels before it in a face
  std::array<std::uint32_t, kFaces> face_start_{};  // first pixel of each face
  std::vector<std::uint8_t> pixel_face_;
  std::vector<Vec3> pixel_direction_;
  std::vector<std::uint32_t> neighbour_start_;  // CSR into neighbour_
  std::vector<std::uint32_t> neighbour_;
};

}  // namespace brisance::occlusion
