// sim/occlusion/shielding: see shielding.hpp.
#include "sim/occlusion/shielding.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <limits>
#include <numbers>

#include <Eigen/Geometry>

namespace brisance::occlusion {
namespace {

constexpr double kReferenceColumns = 32.0;  // thesis §4.2.1: b is counted in these pixels
constexpr double kInfinity = std::numeric_limits<double>::infinity();

// One pixel of an object's projection: the nearest and farthest surface along the pixel's ray.
struct MaskPixel {
  std::uint32_t pixel;
  double near_m;
  double far_m;
};

// Dense per-pixel scratch with a touched list, so rasterising one object costs what it covers.
class DepthScratch {
 public:
  explicit DepthScratch(std::uint32_t pixels)
      : near_(pixels, kInfinity), far_(pixels, -kInfinity) {}
  void add(std::uint32_t pixel, double depth_m) {
    if (near_[pixel] == kInfinity) touched_.push_back(pixel);
    near_[pixel] = std::min(near_[pixel], depth_m);
    far_[pixel] = std::max(far_[pixel], depth_m);
  }
  // Moves the touched pixels out (sorted by pixel) and resets them.
  std::vector<MaskPixel> take() {
    std::sort(touched_.begin(), touched_.end());
    std::vector<MaskPixel> out;
    out.reserve(touched_.size());
    for (std::uint32_t p : touched_) {
      out.push_back({p, near_[p], far_[p]});
      near_[p] = kInfinity;
      far_[p] = -kInfinity;
    }
    touched_.clear();
    return out;
  }

 private:
  std::vector<double> near_, far_;
  std::vector<std::uint32_t> touched_;
};

// floor(x) as an int, clamped to [lo, hi] before the conversion: a clipped vertex on the face's
// horizon (dot(p, n) = eps) projects some 1e10 pixels out, beyond int (found by tests/fuzz under
// UBSan; x86 made it INT_MIN, which dropped the triangle from the face).
int floor_to_int(double x, int lo, int hi) {
  return static_cast<int>(
      std::clamp(std::floor(x), static_cast<double>(lo), static_cast<double>(hi)));
}

// Rasterises one triangle (vertices relative to the charge) into every face it reaches: the
// triangle is clipped to the face's half-space, projected centrally onto the face plane (great
// circles become straight lines there), and each pixel whose centre lies inside gets the depth of
// the triangle along that pixel's ray.
void rasterise_triangle(const SphereMap& map, const std::array<Vec3, 3>& tri,
                        std::span<const int> faces, DepthScratch& scratch) {
  const Vec3 normal = (tri[1] - tri[0]).cross(tri[2] - tri[0]);
  if (normal.squaredNorm() == 0.0) return;
  const double plane = normal.dot(tri[0]);
  const double scale = std::max({tri[0].norm(), tri[1].norm(), tri[2].norm()});
  for (int f : faces) {
    const SphereMap::Face& face = map.face(f);
    // Clip against dot(p, n) >= eps (Sutherland–Hodgman, one plane).
    const double eps = 1e-9 * scale;
    std::array<Vec3, 4> poly{};
    int count = 0;
    for (int i = 0; i < 3; ++i) {
      const Vec3& a = tri[static_cast<std::size_t>(i)];
      const Vec3& b = tri[static_cast<std::size_t>((i + 1) % 3)];
      const double da = a.dot(face.centre_direction) - eps;
      const double db = b.dot(face.centre_direction) - eps;
      if (da >= 0) poly[static_cast<std::size_t>(count++)] = a;
      if ((da >= 0) != (db >= 0))
        poly[static_cast<std::size_t>(count++)] = a + (b - a) * (da / (da - db));
    }
    if (count < 3) continue;
    std::array<Vec2, 4> uv{};
    double umin = kInfinity, umax = -kInfinity, vmin = kInfinity, vmax = -kInfinity;
    for (int i = 0; i < count; ++i) {
      const Vec3& p = poly[static_cast<std::size_t>(i)];
      const Vec3 rel = p * (face.plane_distance / p.dot(face.centre_direction)) - face.origin;
      Vec2& q = uv[static_cast<std::size_t>(i)];
      q = Vec2(rel.dot(face.axis_u), rel.dot(face.axis_v));
      umin = std::min(umin, q.x());
      umax = std::max(umax, q.x());
      vmin = std::min(vmin, q.y());
      vmax = std::max(vmax, q.y());
    }
    const int row_lo = floor_to_int(vmin / map.pixel_height() - 0.5, 0, map.rows());
    const int row_hi = floor_to_int(vmax / map.pixel_height() - 0.5, -2, map.rows() - 2) + 1;
    if (row_lo > row_hi) continue;
    // The polygon's winding in the face plane depends on which side faces the charge.
    double area2 = 0.0;
    for (int i = 0; i < count; ++i) {
      const Vec2& a = uv[static_cast<std::size_t>(i)];
      const Vec2& b = uv[static_cast<std::size_t>((i + 1) % count)];
      area2 += a.x() * b.y() - a.y() * b.x();
    }
    if (area2 == 0.0) continue;
    const double sign = area2 > 0 ? 1.0 : -1.0;
    for (int j = row_lo; j <= row_hi; ++j) {
      const int col_lo =
          floor_to_int(umin / map.pixel_width() - 0.5, map.first_column(j), map.last_column(j) + 1);
      const int col_hi = floor_to_int(umax / map.pixel_width() - 0.5, map.first_column(j) - 2,
                                      map.last_column(j) - 1) +
                         1;
      for (int i = col_lo; i <= col_hi; ++i) {
        const Vec2 c = map.cell_centre(i, j);
        bool inside = true;
        for (int e = 0; e < count && inside; ++e) {
          const Vec2& a = uv[static_cast<std::size_t>(e)];
          const Vec2& b = uv[static_cast<std::size_t>((e + 1) % count)];
          inside =
              sign * ((b.x() - a.x()) * (c.y() - a.y()) - (b.y() - a.y()) * (c.x() - a.x())) >= 0.0;
        }
        if (!inside) continue;
        const std::uint32_t pixel =
            map.row_start(f, j) + static_cast<std::uint32_t>(i - map.first_column(j));
        const Vec3& ray = map.pixel_direction(pixel);
        const double along = normal.dot(ray);
        const double depth = along != 0.0 ? plane / along : tri[0].norm();
        scratch.add(pixel, depth > 0.0 ? depth : 0.0);
      }
    }
  }
}

// The faces an object's bounding cone can reach.
std::vector<int> faces_reached(const SphereMap& map, const Vec3& centre, double radius) {
  std::vector<int> faces;
  const double distance = centre.norm();
  if (distance <= radius * 1.0000001) {
    for (int f = 0; f < SphereMap::kFaces; ++f)
      faces.push_back(f);
    return faces;
  }
  const double cone = std::asin(radius / distance);
  const Vec3 axis = centre / distance;
  for (int f = 0; f < SphereMap::kFaces; ++f) {
    const SphereMap::Face& face = map.face(f);
    const double face_radius = std::acos(face.cos_angular_radius);
    const double apart = std::acos(std::clamp(axis.dot(face.centre_direction), -1.0, 1.0));
    if (apart <= cone + face_radius + 1e-6) faces.push_back(f);
  }
  return faces;
}

struct Bounds {
  Vec3 centre;  // relative to the charge
  double radius;
};

Bounds bounds_of(const Object& object, const Vec3& charge) {
  Vec3 lo = Vec3::Constant(kInfinity), hi = Vec3::Constant(-kInfinity);
  for (const Vec3& v : object.vertices) {
    lo = lo.cwiseMin(v);
    hi = hi.cwiseMax(v);
  }
  const Vec3 centre = (lo + hi) / 2.0;
  double radius = 0.0;
  for (const Vec3& v : object.vertices)
    radius = std::max(radius, (v - centre).norm());
  return {centre - charge, radius};
}

std::vector<MaskPixel> project(const SphereMap& map, const Vec3& charge, const Object& object,
                               DepthScratch& scratch) {
  if (object.vertices.empty()) return {};
  const Bounds bounds = bounds_of(object, charge);
  const std::vector<int> faces = faces_reached(map, bounds.centre, bounds.radius);
  for (const auto& t : object.triangles) {
    const std::array<Vec3, 3> tri = {object.vertices[t[0]] - charge, object.vertices[t[1]] - charge,
                                     object.vertices[t[2]] - charge};
    rasterise_triangle(map, tri, faces, scratch);
  }
  std::vector<MaskPixel> mask = scratch.take();
  if (mask.empty()) {
    // Smaller than a pixel: it still covers the pixel of its centre.
    double near = kInfinity, far = 0.0;
    for (const Vec3& v : object.vertices) {
      near = std::min(near, (v - charge).norm());
      far = std::max(far, (v - charge).norm());
    }
    mask.push_back({map.pixel_of(bounds.centre), near, far});
  }
  return mask;
}

// Distance-from-edge numbering of a set of pixels (thesis fig. 4.4): pixels of the set with a
// neighbour outside it are 1, the next ring inwards 2, and so on (breadth-first over the map's
// neighbours, across face edges). A set with no edge (it covers the whole sphere) is numbered
// with the largest value the map can hold, so it shields completely.
class EdgeNumbering {
 public:
  explicit EdgeNumbering(const SphereMap& map) : map_(map), number_(map.pixel_count(), 0) {}

  void number(std::span<const std::uint32_t> pixels) {
    for (std::uint32_t p : members_)
      number_[p] = 0;
    members_.assign(pixels.begin(), pixels.end());
    constexpr std::uint16_t kUnnumbered = std::numeric_limits<std::uint16_t>::max();
    for (std::uint32_t p : members_)
      number_[p] = kUnnumbered;
    queue_.clear();
    for (std::uint32_t p : members_) {
      for (std::uint32_t n : map_.neighbours(p)) {
        if (number_[n] == 0) {
          number_[p] = 1;
          queue_.push_back(p);
          break;
        }
      }
    }
    if (queue_.empty()) {
      const auto whole = static_cast<std::uint16_t>(2 * (map_.rows() + map_.columns()));
      for (std::uint32_t p : members_)
        number_[p] = whole;
      return;
    }
    for (std::size_t head = 0; head < queue_.size(); ++head) {
      const std::uint32_t p = queue_[head];
      for (std::uint32_t n : map_.neighbours(p)) {
        if (number_[n] == kUnnumbered) {
          number_[n] = static_cast<std::uint16_t>(number_[p] + 1);
          queue_.push_back(n);
        }
      }
    }
  }
  std::uint16_t at(std::uint32_t pixel) const { return number_[pixel]; }

 private:
  const SphereMap& map_;
  std::vector<std::uint16_t> number_;
  std::vector<std::uint32_t> members_;
  std::vector<std::uint32_t> queue_;
};

// The objects covering each pixel, with their depths there (compressed rows by pixel).
struct PixelTable {
  struct Entry {
    std::uint32_t object;
    double near_m;
    double far_m;
  };
  std::vector<std::uint32_t> start;
  std::vector<Entry> entries;

  std::span<const Entry> at(std::uint32_t pixel) const {
    return {entries.data() + start[pixel], entries.data() + start[pixel + 1]};
  }
};

PixelTable pixel_table(std::uint32_t pixels, const std::vector<std::vector<MaskPixel>>& masks) {
  PixelTable table;
  table.start.assign(pixels + 1, 0);
  for (const auto& mask : masks) {
    for (const MaskPixel& m : mask)
      ++table.start[m.pixel + 1];
  }
  for (std::uint32_t p = 0; p < pixels; ++p)
    table.start[p + 1] += table.start[p];
  table.entries.resize(table.start[pixels]);
  std::vector<std::uint32_t> fill(table.start.begin(), table.start.end() - 1);
  for (std::uint32_t o = 0; o < masks.size(); ++o) {
    for (const MaskPixel& m : masks[o])
      table.entries[fill[m.pixel]++] = {o, m.near_m, m.far_m};
  }
  return table;
}

double mean_near(const std::vector<MaskPixel>& mask) {
  double sum = 0.0;
  for (const MaskPixel& m : mask)
    sum += m.near_m;
  return sum / static_cast<double>(mask.size());
}

double mean_far(const std::vector<MaskPixel>& mask) {
  double sum = 0.0;
  for (const MaskPixel& m : mask)
    sum += m.far_m;
  return sum / static_cast<double>(mask.size());
}

}  // namespace

double attenuation(double blocking_factor, double radial_separation, double blocking_offset,
                   double separation_slope) {
  const double x = blocking_factor / (blocking_offset + separation_slope * radial_separation);
  if (x >= 1.0) return 0.0;
  if (x <= 0.0) return 1.0;
  return x * x * x - 2.0 * std::pow(x, 1.5) + 1.0;
}

Shielding compute_shielding(const SphereMap& map, const Vec3& charge,
                            std::span<const Object> objects, std::span<const Panel> panels,
                            const Settings& settings) {
  assert(map.columns() == settings.face_columns && map.rows() == settings.face_rows);
  const double to_reference = kReferenceColumns / map.columns();
  const auto n = static_cast<std::uint32_t>(objects.size());
  Shielding out;
  out.objects.resize(n);
  out.panel_attenuation.assign(panels.size(), 1.0);

  // Information gathering (thesis §4.2.2): every object that blocks or receives is projected
  // on its own.
  DepthScratch scratch(map.pixel_count());
  std::vector<std::vector<MaskPixel>> masks(n);
  for (std::uint32_t o = 0; o < n; ++o) {
    if (objects[o].blocks || objects[o].receives)
      masks[o] = project(map, charge, objects[o], scratch);
    out.objects[o].mask_pixels = static_cast<std::uint32_t>(masks[o].size());
  }
  const PixelTable table = pixel_table(map.pixel_count(), masks);

  // Occlusion lists, pixel by pixel rather than object pair by object pair: at each pixel, a
  // blocking object entirely in front of a receiving one (its rear no farther than the other's
  // front) occludes it.
  std::vector<std::pair<std::uint32_t, std::uint32_t>> occludes;  // (shadowed, occluder)
  for (std::uint32_t p = 0; p < map.pixel_count(); ++p) {
    const auto here = table.at(p);
    if (here.size() < 2) continue;
    for (const auto& shadowed : here) {
      if (!objects[shadowed.object].receives) continue;
      for (const auto& occluder : here) {
        if (occluder.object == shadowed.object || !objects[occluder.object].blocks) continue;
        if (occluder.far_m <= shadowed.near_m + settings.depth_tolerance_m)
          occludes.emplace_back(shadowed.object, occluder.object);
      }
    }
  }
  std::sort(occludes.begin(), occludes.end());
  occludes.erase(std::unique(occludes.begin(), occludes.end()), occludes.end());
  for (const auto& [shadowed, occluder] : occludes)
    out.objects[shadowed].occluders.push_back(occluder);

  // Attenuation (thesis §4.2.2, "Determine Attenuation"): objects with the same occluders share
  // one numbered map, so they are visited grouped by their occluder lists.
  std::vector<std::uint32_t> order;
  for (std::uint32_t o = 0; o < n; ++o) {
    if (!out.objects[o].occluders.empty()) order.push_back(o);
  }
  std::stable_sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return out.objects[a].occluders < out.objects[b].occluders;
  });
  std::vector<std::vector<std::uint32_t>> panels_of(n);
  for (std::uint32_t k = 0; k < panels.size(); ++k)
    panels_of[panels[k].object].push_back(k);

  EdgeNumbering numbering(map);
  std::vector<std::uint32_t> united;
  const std::vector<std::uint32_t>* numbered_for = nullptr;
  std::vector<std::uint32_t> disc;
  for (std::uint32_t o : order) {
    ObjectShielding& result = out.objects[o];
    ++out.objects_occluded;
    if (numbered_for == nullptr || *numbered_for != result.occluders) {
      united.clear();
      for (std::uint32_t a : result.occluders) {
        for (const MaskPixel& m : masks[a])
          united.push_back(m.pixel);
      }
      std::sort(united.begin(), united.end());
      united.erase(std::unique(united.begin(), united.end()), united.end());
      numbering.number(united);
      numbered_for = &result.occluders;
      ++out.occlusion_maps;
    }

    // Whole object: the thesis's b (mean number under its mask) and k (from the mean front of
    // the object to the mean rear of its nearest occluder, over the object's distance).
    double sum = 0.0;
    for (const MaskPixel& m : masks[o])
      sum += numbering.at(m.pixel);
    result.blocking_factor = sum / static_cast<double>(masks[o].size()) * to_reference;
    const double front = mean_near(masks[o]);
    double nearest_rear = -kInfinity, any_rear = -kInfinity;
    for (std::uint32_t a : result.occluders) {
      const double rear = mean_far(masks[a]);
      any_rear = std::max(any_rear, rear);
      if (rear <= front + settings.depth_tolerance_m) nearest_rear = std::max(nearest_rear, rear);
    }
    if (nearest_rear == -kInfinity) nearest_rear = any_rear;
    result.radial_separation = front > 0.0 ? std::max(0.0, front - nearest_rear) / front : 0.0;
    result.attenuation = attenuation(result.blocking_factor, result.radial_separation,
                                     settings.blocking_offset, settings.separation_slope);

    for (std::uint32_t k : panels_of[o]) {
      if (!settings.per_panel) {
        out.panel_attenuation[k] = result.attenuation;
        continue;
      }
      // The pixels the panel covers: a disc of its area around its centre's direction.
      const Vec3 towards = panels[k].centre - charge;
      const double distance = towards.norm();
      if (distance == 0.0) continue;
      const Vec3 axis = towards / distance;
      const double cos_radius = std::cos(std::min(
          std::sqrt(panels[k].area_m2 / std::numbers::pi) / distance, std::numbers::pi / 2));
      disc.assign(1, map.pixel_of(axis));
      for (std::size_t head = 0; head < disc.size(); ++head) {
        for (std::uint32_t nb : map.neighbours(disc[head])) {
          if (map.pixel_direction(nb).dot(axis) >= cos_radius &&
              std::find(disc.begin(), disc.end(), nb) == disc.end())
            disc.push_back(nb);
        }
      }
      // b and k as for the object, read where an occluder stands in front of the panel itself.
      double panel_sum = 0.0, separation_sum = 0.0;
      int shadowed_pixels = 0;
      for (std::uint32_t p : disc) {
        if (numbering.at(p) == 0) continue;
        double rear = -kInfinity;
        for (const auto& entry : table.at(p)) {
          if (entry.far_m <= distance + settings.depth_tolerance_m &&
              std::binary_search(result.occluders.begin(), result.occluders.end(), entry.object))
            rear = std::max(rear, entry.far_m);
        }
        if (rear == -kInfinity) continue;
        panel_sum += numbering.at(p);
        separation_sum += std::max(0.0, distance - rear) / distance;
        ++shadowed_pixels;
      }
      if (shadowed_pixels == 0) continue;
      const double b = panel_sum / static_cast<double>(disc.size()) * to_reference;
      const double k_sep = separation_sum / shadowed_pixels;
      out.panel_attenuation[k] =
          attenuation(b, k_sep, settings.blocking_offset, settings.separation_slope);
    }
  }
  return out;
}

bool footprints_may_overlap(const Vec3& charge, std::span<const Object> objects) {
  struct Cone {
    Vec3 axis;
    double half_angle;
    double lo, hi;  // polar-angle interval about the sweep axis
    bool blocks, receives;
  };
  std::vector<Cone> cones;
  int wanted_blockers = 0, wanted_receivers = 0;
  for (const Object& object : objects) {
    if (object.vertices.empty() || (!object.blocks && !object.receives)) continue;
    const Bounds b = bounds_of(object, charge);
    const double distance = b.centre.norm();
    Cone c{};
    c.axis = distance > 0 ? Vec3(b.centre / distance) : Vec3(Vec3::UnitX());
    c.half_angle = distance <= b.radius ? std::numbers::pi : std::asin(b.radius / distance);
    c.blocks = object.blocks;
    c.receives = object.receives;
    wanted_blockers += object.blocks;
    wanted_receivers += object.receives;
    cones.push_back(c);
  }
  if (wanted_blockers == 0 || wanted_receivers == 0 || cones.size() < 2) return false;
  // Sweep and prune on the polar angle about the axis along which the cones spread most.
  Vec3 spread = Vec3::Zero();
  for (const Cone& c : cones)
    spread += c.axis.cwiseAbs2();
  Vec3 mean = Vec3::Zero();
  for (const Cone& c : cones)
    mean += c.axis;
  mean /= static_cast<double>(cones.size());
  Eigen::Index axis_index = 0;
  (spread / static_cast<double>(cones.size()) - mean.cwiseAbs2()).maxCoeff(&axis_index);
  for (Cone& c : cones) {
    const double theta = std::acos(std::clamp(c.axis[axis_index], -1.0, 1.0));
    c.lo = theta - c.half_angle;
    c.hi = theta + c.half_angle;
  }
  std::sort(cones.begin(), cones.end(), [](const Cone& a, const Cone& b) { return a.lo < b.lo; });
  for (std::size_t i = 0; i < cones.size(); ++i) {
    for (std::size_t j = i + 1; j < cones.size() && cones[j].lo <= cones[i].hi; ++j) {
      const Cone& a = cones[i];
      const Cone& b = cones[j];
      if (!((a.blocks && b.receives) || (b.blocks && a.receives))) continue;
      const double apart = std::acos(std::clamp(a.axis.dot(b.axis), -1.0, 1.0));
      if (apart <= a.half_angle + b.half_angle) return true;
    }
  }
  return false;
}

}  // namespace brisance::occlusion
