// sim/occlusion/sphere_map: see sphere_map.hpp.
#include "sim/occlusion/sphere_map.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <utility>

#include <Eigen/Geometry>

namespace brisance::occlusion {
namespace {

// The 12 corners of a regular icosahedron on the unit sphere: cyclic permutations of
// (0, ±1, ±φ), normalised.
std::array<Vec3, 12> icosahedron_corners() {
  const double phi = (1.0 + std::sqrt(5.0)) / 2.0;
  std::array<Vec3, 12> v{};
  int k = 0;
  for (double s1 : {-1.0, 1.0}) {
    for (double s2 : {-1.0, 1.0}) {
      v[static_cast<std::size_t>(k++)] = Vec3(0, s1, s2 * phi).normalized();
      v[static_cast<std::size_t>(k++)] = Vec3(s1, s2 * phi, 0).normalized();
      v[static_cast<std::size_t>(k++)] = Vec3(s2 * phi, 0, s1).normalized();
    }
  }
  return v;
}

}  // namespace

SphereMap::SphereMap(int columns, int rows) : columns_(columns), rows_(rows) {
  assert(columns >= 2 && rows >= 2);
  const std::array<Vec3, 12> corners = icosahedron_corners();
  // Faces: the triples of corners that are pairwise one edge apart, wound counter-clockwise
  // seen from outside.
  double shortest = 1e9;
  for (std::size_t i = 0; i < 12; ++i) {
    for (std::size_t j = i + 1; j < 12; ++j)
      shortest = std::min(shortest, (corners[i] - corners[j]).norm());
  }
  edge_ = shortest;
  const auto adjacent = [&](std::size_t i, std::size_t j) {
    return (corners[i] - corners[j]).norm() < shortest * 1.001;
  };
  int f = 0;
  for (std::size_t i = 0; i < 12; ++i) {
    for (std::size_t j = i + 1; j < 12; ++j) {
      for (std::size_t k = j + 1; k < 12; ++k) {
        if (!adjacent(i, j) || !adjacent(j, k) || !adjacent(i, k)) continue;
        Vec3 a = corners[i], b = corners[j], c = corners[k];
        const Vec3 centre = (a + b + c) / 3.0;
        if ((b - a).cross(c - a).dot(centre) < 0) std::swap(b, c);
        Face& face = faces_[static_cast<std::size_t>(f++)];
        face.centre_direction = centre.normalized();
        face.plane_distance = a.dot(face.centre_direction);
        face.origin = a;
        face.axis_u = (b - a).normalized();
        face.axis_v = face.centre_direction.cross(face.axis_u);
        face.cos_angular_radius = a.dot(face.centre_direction);
      }
    }
  }
  assert(f == kFaces);

  pixel_width_ = edge_ / columns_;
  pixel_height_ = edge_ * std::sqrt(3.0) / 2.0 / rows_;
  // Row j covers heights [j, j+1] * pixel_height; its cells are those the triangle (base from
  // u = 0 to u = edge, apex at u = edge / 2) reaches anywhere in the row: widest at its bottom.
  std::uint32_t per_face = 0;
  for (int j = 0; j < rows_; ++j) {
    const double inset = j * pixel_height_ / std::sqrt(3.0);
    const int first = static_cast<int>(std::floor(inset / pixel_width_ + 1e-9));
    const int last = std::min(
        columns_ - 1, static_cast<int>(std::ceil((edge_ - inset) / pixel_width_ - 1e-9)) - 1);
    row_first_.push_back(first);
    row_last_.push_back(std::max(first, last));
    row_offset_.push_back(per_face);
    per_face += static_cast<std::uint32_t>(row_last_.back() - first + 1);
  }
  for (int face = 0; face < kFaces; ++face) {
    face_start_[static_cast<std::size_t>(face)] = per_face * static_cast<std::uint32_t>(face);
    const Face& fc = faces_[static_cast<std::size_t>(face)];
    for (int j = 0; j < rows_; ++j) {
      for (int i = first_column(j); i <= last_column(j); ++i) {
        const Vec2 uv = cell_centre(i, j);
        pixel_face_.push_back(static_cast<std::uint8_t>(face));
        pixel_direction_.push_back(
            (fc.origin + uv.x() * fc.axis_u + uv.y() * fc.axis_v).normalized());
      }
    }
  }

  // Neighbours: one cell step along each axis of the face plane, found by direction, so steps
  // that leave the face land in the neighbouring face. Made symmetric.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> links;
  for (int face = 0; face < kFaces; ++face) {
    const Face& fc = faces_[static_cast<std::size_t>(face)];
    for (int j = 0; j < rows_; ++j) {
      for (int i = first_column(j); i <= last_column(j); ++i) {
        const std::uint32_t here =
            row_start(face, j) + static_cast<std::uint32_t>(i - first_column(j));
        const Vec2 uv = cell_centre(i, j);
        const std::array<Vec2, 4> steps = {Vec2(pixel_width_, 0), Vec2(-pixel_width_, 0),
                                           Vec2(0, pixel_height_), Vec2(0, -pixel_height_)};
        for (const Vec2& step : steps) {
          const Vec2 p = uv + step;
          const std::uint32_t there = pixel_of(fc.origin + p.x() * fc.axis_u + p.y() * fc.axis_v);
          if (there == here) continue;
          links.emplace_back(here, there);
          links.emplace_back(there, here);
        }
      }
    }
  }
  std::sort(links.begin(), links.end());
  links.erase(std::unique(links.begin(), links.end()), links.end());
  neighbour_start_.assign(pixel_count() + 1, 0);
  for (const auto& [from, to] : links)
    ++neighbour_start_[from + 1];
  for (std::uint32_t p = 0; p < pixel_count(); ++p)
    neighbour_start_[p + 1] += neighbour_start_[p];
  neighbour_.reserve(links.size());
  for (const auto& link : links)
    neighbour_.push_back(link.second);
}

int SphereMap::face_of(const Vec3& direction) const {
  int best = 0;
  double best_dot = -2.0;
  for (int f = 0; f < kFaces; ++f) {
    const double d = direction.dot(faces_[static_cast<std::size_t>(f)].centre_direction);
    if (d > best_dot) {
      best_dot = d;
      best = f;
    }
  }
  return best;
}

std::uint32_t SphereMap::pixel_in_face(int f, const Vec3& direction) const {
  const Face& fc = faces_[static_cast<std::size_t>(f)];
  const Vec3 on_plane = direction * (fc.plane_distance / direction.dot(fc.centre_direction));
  const Vec3 rel = on_plane - fc.origin;
  const int j =
      std::clamp(static_cast<int>(std::floor(rel.dot(fc.axis_v) / pixel_height_)), 0, rows_ - 1);
  const int i = std::clamp(static_cast<int>(std::floor(rel.dot(fc.axis_u) / pixel_width_)),
                           first_column(j), last_column(j));
  return row_start(f, j) + static_cast<std::uint32_t>(i - first_column(j));
}

std::uint32_t SphereMap::pixel_of(const Vec3& direction) const {
  return pixel_in_face(face_of(direction), direction);
}

std::span<const std::uint32_t> SphereMap::neighbours(std::uint32_t pixel) const {
  return {neighbour_.data() + neighbour_start_[pixel],
          neighbour_.data() + neighbour_start_[pixel + 1]};
}

}  // namespace brisance::occlusion
