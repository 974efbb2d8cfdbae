// sim/fracture/patterns: radial-and-ring patterns of annealed panes, dice of tempered panes.
#include "sim/fracture/patterns.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <deque>
#include <numbers>
#include <random>
#include <set>

#include "sim/geometry/polygon.hpp"

namespace brisance::fracture {

namespace {

constexpr double kPi = std::numbers::pi;

// Uniform doubles in [0, 1) from the top 53 bits of a 64-bit Mersenne Twister (whose sequence
// the standard fixes), as the crack tree draws them: bit-identical on every platform.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  double symmetric() { return 2.0 * uniform() - 1.0; }  // [-1, 1)

 private:
  std::mt19937_64 engine_;
};

// How far a ray from `origin` at `angle` runs inside the pane [0, w] x [0, h].
double exit_distance(const Vec2& origin, double angle, double w, double h) {
  const double c = std::cos(angle);
  const double s = std::sin(angle);
  double t = INFINITY;
  if (c > 1e-12) t = std::min(t, (w - origin.x()) / c);
  if (c < -1e-12) t = std::min(t, -origin.x() / c);
  if (s > 1e-12) t = std::min(t, (h - origin.y()) / s);
  if (s < -1e-12) t = std::min(t, -origin.y() / s);
  return std::max(t, 0.0);
}

// The plate's surface stress shape at (x, y): its mode shape sin(pi x / W) sin(pi y / H), 1 at
// the centre (the one-term solution sim/response/plate is built on; its curvatures have the
// same shape).
double stress_shape(double x, double y, double w, double h) {
  return std::sin(kPi * std::clamp(x / w, 0.0, 1.0)) * std::sin(kPi * std::clamp(y / h, 0.0, 1.0));
}

// Along the ray at `angle` from `origin`: max_r r phi(r)^2 and the r where it peaks (the star
// stops branching there; docs/fracture.md).
struct RayProfile {
  double peak = 0.0;    // max_r r phi^2, m
  double peak_r = 0.0;  // its radius, m
  double length = 0.0;  // the ray's length inside the pane, m
};
RayProfile ray_profile(const Vec2& origin, double angle, double w, double h) {
  RayProfile out;
  out.length = exit_distance(origin, angle, w, h);
  constexpr int kSamples = 256;
  const Vec2 dir(std::cos(angle), std::sin(angle));
  for (int k = 1; k <= kSamples; ++k) {
    const double r = out.length * k / kSamples;
    const Vec2 p = origin + r * dir;
    const double phi = stress_shape(p.x(), p.y(), w, h);
    const double g = r * phi * phi;
    if (g > out.peak) {
      out.peak = g;
      out.peak_r = r;
    }
  }
  return out;
}

constexpr int kDirections = 720;

// A radial crack: vertices at increasing distance r from the origin.
struct Arm {
  double angle = 0.0;    // its direction out of the branching zone
  double birth_r = 0.0;  // where it branched off its parent (0: the first crack)
  int parent = -1;
  std::vector<Vec2> points;
  std::vector<double> radii;
};

// The point of an arm at distance r from the origin (on its polyline, so a crack ending there
// makes a T-junction), or false if the arm does not reach r.
bool point_at(const Arm& arm, double r, Vec2& out) {
  if (arm.radii.empty() || r < arm.radii.front() || r > arm.radii.back()) return false;
  const auto it = std::lower_bound(arm.radii.begin(), arm.radii.end(), r);
  const auto j = static_cast<std::size_t>(it - arm.radii.begin());
  if (j == 0) {
    out = arm.points.front();
    return true;
  }
  const double r0 = arm.radii[j - 1];
  const double r1 = arm.radii[j];
  const double s = r1 > r0 ? (r - r0) / (r1 - r0) : 0.0;
  out = arm.points[j - 1] + s * (arm.points[j] - arm.points[j - 1]);
  return true;
}

// Clips a polyline to the pane and appends the parts inside as crack segments; a part that
// leaves the pane ends exactly on its outline.
void add_clipped(const std::vector<Vec2>& line, double w, double h, CrackTree& tree) {
  const auto inside = [&](const Vec2& p) {
    return p.x() >= 0.0 && p.x() <= w && p.y() >= 0.0 && p.y() <= h;
  };
  // Liang–Barsky clip of one segment; false if nothing of it lies inside.
  const auto clip = [&](Vec2 a, Vec2 b, Vec2& ca, Vec2& cb) {
    double t0 = 0.0, t1 = 1.0;
    const Vec2 d = b - a;
    const double p[4] = {-d.x(), d.x(), -d.y(), d.y()};
    const double q[4] = {a.x(), w - a.x(), a.y(), h - a.y()};
    for (int k = 0; k < 4; ++k) {
      if (p[k] == 0.0) {
        if (q[k] < 0.0) return false;
        continue;
      }
      const double t = q[k] / p[k];
      if (p[k] < 0.0)
        t0 = std::max(t0, t);
      else
        t1 = std::min(t1, t);
      if (t0 > t1) return false;
    }
    ca = t0 > 0.0 ? a + t0 * d : a;
    cb = t1 < 1.0 ? a + t1 * d : b;
    for (Vec2* v : {&ca, &cb}) {
      v->x() = std::clamp(v->x(), 0.0, w);
      v->y() = std::clamp(v->y(), 0.0, h);
    }
    return true;
  };
  for (std::size_t k = 0; k + 1 < line.size(); ++k) {
    Vec2 a, b;
    if (!clip(line[k], line[k + 1], a, b)) continue;
    if (inside(line[k]) && inside(line[k + 1])) {
      a = line[k];
      b = line[k + 1];
    }
    if ((b - a).squaredNorm() > 0.0) tree.segments.push_back({a, b, 0});
  }
}

// The arms' segments in a uniform grid of buckets, to find where a growing arm runs into one.
class SegmentGrid {
 public:
  SegmentGrid(double w, double h, double cell)
      : nx_(std::max(1, static_cast<int>(std::ceil(w / cell)))),
        ny_(std::max(1, static_cast<int>(std::ceil(h / cell)))),
        sx_(nx_ / w),
        sy_(ny_ / h),
        buckets_(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_)) {}

  void add(const Vec2& a, const Vec2& b, int arm) {
    const auto id = static_cast<std::uint32_t>(segments_.size());
    segments_.push_back({a, b, arm});
    for_each_bucket(a, b, [&](std::vector<std::uint32_t>& bucket) { bucket.push_back(id); });
  }

  // The first point along a -> b (a excluded) where it meets a segment of another arm, as the
  // parameter t in (0, 1], or nothing (t > 1).
  double first_hit(const Vec2& a, const Vec2& b, int arm, Vec2& at) {
    double best = 2.0;
    const Vec2 d = b - a;
    for_each_bucket(a, b, [&](std::vector<std::uint32_t>& bucket) {
      for (const std::uint32_t id : bucket) {
        const Stored& s = segments_[id];
        if (s.arm == arm) continue;
        const Vec2 e = s.b - s.a;
        const double denom = d.x() * e.y() - d.y() * e.x();
        if (std::abs(denom) < 1e-300) continue;
        const Vec2 f = s.a - a;
        const double t = (f.x() * e.y() - f.y() * e.x()) / denom;
        const double u = (f.x() * d.y() - f.y() * d.x()) / denom;
        if (t > 1e-9 && t <= 1.0 && u >= 0.0 && u <= 1.0 && t < best) {
          best = t;
          at = s.a + u * e;  // on the hit segment: the arm ends in a T-junction
        }
      }
    });
    return best;
  }

 private:
  struct Stored {
    Vec2 a;
    Vec2 b;
    int arm;
  };
  template <class F>
  void for_each_bucket(const Vec2& a, const Vec2& b, F&& f) {
    const int x0 = std::clamp(static_cast<int>(std::min(a.x(), b.x()) * sx_), 0, nx_ - 1);
    const int x1 = std::clamp(static_cast<int>(std::max(a.x(), b.x()) * sx_), 0, nx_ - 1);
    const int y0 = std::clamp(static_cast<int>(std::min(a.y(), b.y()) * sy_), 0, ny_ - 1);
    const int y1 = std::clamp(static_cast<int>(std::max(a.y(), b.y()) * sy_), 0, ny_ - 1);
    for (int y = y0; y <= y1; ++y)
      for (int x = x0; x <= x1; ++x)
        f(buckets_[static_cast<std::size_t>(y) * static_cast<std::size_t>(nx_) +
                   static_cast<std::size_t>(x)]);
  }
  int nx_, ny_;
  double sx_, sy_;
  std::vector<std::vector<std::uint32_t>> buckets_;
  std::vector<Stored> segments_;
};

}  // namespace

double bending_crack_factor(double poisson_ratio) {
  return (1.0 + poisson_ratio) / (3.0 + poisson_ratio);
}

RadialStar radial_star(double width_m, double height_m, double centre_stress_pa,
                       double poisson_ratio, double branching_constant_pa_sqrt_m) {
  assert(width_m > 0.0 && height_m > 0.0 && branching_constant_pa_sqrt_m > 0.0);
  RadialStar star;
  const double sigma_e = bending_crack_factor(poisson_ratio) * std::max(centre_stress_pa, 0.0);
  if (!(sigma_e > 0.0)) return star;
  const double a_b = branching_constant_pa_sqrt_m;
  star.branching_length_m = (a_b / sigma_e) * (a_b / sigma_e);
  const Vec2 centre(0.5 * width_m, 0.5 * height_m);
  double integral = 0.0;
  for (int k = 0; k < kDirections; ++k) {
    const double angle = 2.0 * kPi * (k + 0.5) / kDirections;
    const RayProfile ray = ray_profile(centre, angle, width_m, height_m);
    integral += ray.peak * (2.0 * kPi / kDirections);
    star.branch_zone_m = std::max(star.branch_zone_m, ray.peak_r);
  }
  // rho(theta) = max_r r sigma_e(r)^2 / (pi A_b^2); n = its integral over the directions.
  star.count = integral * sigma_e * sigma_e / (kPi * a_b * a_b);
  return star;
}

std::vector<double> ring_radii_m(double pressure_pa, double strength_pa, double thickness_m,
                                 double max_radius_m) {
  std::vector<double> rings;
  if (!(pressure_pa > 0.0 && strength_pa > 0.0 && thickness_m > 0.0 && max_radius_m > 0.0))
    return rings;
  // sigma(x) t^2 / (6 p) = [x (x^2 - r0^2) / 2 - (x^3 - r0^3) / 3] / x, rising in x from 0 at r0.
  const double target = strength_pa * thickness_m * thickness_m / (6.0 * pressure_pa);
  const auto moment = [](double x, double r0) {
    return (0.5 * x * (x * x - r0 * r0) - (x * x * x - r0 * r0 * r0) / 3.0) / x;
  };
  double r0 = 0.0;
  while (rings.size() < static_cast<std::size_t>(FractureParams::kMaxRings)) {
    if (moment(max_radius_m, r0) < target) break;  // the petal holds to the frame
    double lo = r0, hi = max_radius_m;
    for (int i = 0; i < 100 && hi - lo > 1e-9 * max_radius_m; ++i) {
      const double mid = 0.5 * (lo + hi);
      (moment(mid, r0) < target ? lo : hi) = mid;
    }
    rings.push_back(hi);
    r0 = hi;
  }
  return rings;
}

double temper_energy_ratio() {
  // d_ref = 50 mm / sqrt(40) at sigma_m = 69 MPa / 2, K_c = 0.75 MPa m^0.5, nu = 0.2.
  const double d_ref = 0.05 / std::sqrt(kDiceReferenceCount);
  const double sigma_m = 0.5 * kDiceReferenceCompression_Pa;
  const double k_c = 0.75e6;
  return d_ref * (1.0 - kGlassPoissonRatio) * sigma_m * sigma_m / (2.5 * k_c * k_c);
}

double dice_cell_m(double surface_compression_pa, double fracture_toughness_pa_sqrt_m,
                   double poisson_ratio) {
  assert(surface_compression_pa > 0.0 && fracture_toughness_pa_sqrt_m > 0.0);
  const double sigma_m = 0.5 * surface_compression_pa;
  const double k_c = fracture_toughness_pa_sqrt_m;
  return 2.5 * temper_energy_ratio() * k_c * k_c / ((1.0 - poisson_ratio) * sigma_m * sigma_m);
}

CrackTree radial_ring_cracks(const FractureParams& params, const StopRequest& stop) {
  const auto stopped = [&] {
    CrackTree abandoned;
    abandoned.stopped = true;
    return abandoned;
  };
  const double w = params.width_m;
  const double h = params.height_m;
  const Vec2 origin =
      params.initial.centres_m.empty() ? Vec2(0.5 * w, 0.5 * h) : params.initial.centres_m.front();
  Random random(params.seed);
  const int n = std::clamp(params.radial.count, 2, FractureParams::kMaxRadialCracks);
  // Step along the cracks: fine enough for the wiggle and the rings, at most 5 mm.
  const double diagonal = std::hypot(w, h);
  const double step = std::min(0.005, diagonal / 200.0);

  // 1. The arms' directions: n quantiles of the star's density per radian, rho(theta) ~ max_r
  // r phi^2 along each direction (radial_star), each jittered within its share.
  std::vector<RayProfile> rays(kDirections);
  std::vector<double> cumulative(kDirections + 1, 0.0);
  const double offset = random.uniform() * 2.0 * kPi / kDirections;
  for (int k = 0; k < kDirections; ++k) {
    rays[k] = ray_profile(origin, offset + 2.0 * kPi * (k + 0.5) / kDirections, w, h);
    cumulative[k + 1] = cumulative[k] + std::max(rays[k].peak, 1e-12);
  }
  const double total = cumulative.back();
  const double start = random.uniform();
  // The arms' spacing varies as the branch angle does (thesis fig. 5.12: beta +- V/2), fork by
  // fork: a new arm splits the share of the gap it is born into within +- V / (2 beta) of its
  // nominal place, so the shares of later arms are products of their ancestors' splits.
  const double jitter =
      params.branch_angle_deg > 0.0
          ? std::min(1.0, 0.5 * params.angle_variance_deg / params.branch_angle_deg)
          : 0.0;
  std::vector<Arm> arms(static_cast<std::size_t>(n));
  std::vector<double> zone(static_cast<std::size_t>(n));  // the branching zone along each arm
  // u: each arm's place in the cumulative of rho (0..1 once round), increasing with the index.
  std::vector<double> u(static_cast<std::size_t>(n) + 1);

  // 2. Who branches off whom, where, and in which direction: the first crack runs both ways
  // through the origin (arms 0 and n/2); the gaps between born arms are then split
  // breadth-first, a new arm branching off one of the gap's two arms. The k-th arm is born
  // where the star has k arms, at k / n of its direction's branching zone (n(r) grows about
  // linearly there).
  std::vector<int> order;
  u[0] = start / n;
  u[static_cast<std::size_t>(n)] = u[0] + 1.0;
  order.push_back(0);
  arms[0].parent = -1;
  if (n > 1) {
    u[static_cast<std::size_t>(n / 2)] = u[0] + static_cast<double>(n / 2) / n;
    order.push_back(n / 2);
    arms[n / 2].parent = -1;
  }
  std::deque<std::pair<int, int>>
      gaps;  // (i, j): arms i < j (j may wrap past n) with none born between
  gaps.emplace_back(0, n / 2);
  gaps.emplace_back(n / 2, n);
  while (!gaps.empty()) {
    const auto [i, j] = gaps.front();
    gaps.pop_front();
    if (j - i < 2) continue;
    const int mid = (i + j) / 2;
    const int m = mid % n;
    const double nominal = static_cast<double>(mid - i) / (j - i);
    const double split = nominal + jitter * std::min(nominal, 1.0 - nominal) * random.symmetric();
    u[static_cast<std::size_t>(mid)] = u[i] + split * (u[j] - u[i]);
    arms[m].parent = random.uniform() < 0.5 ? i % n : j % n;
    order.push_back(m);
    gaps.emplace_back(i, mid);
    gaps.emplace_back(mid, j);
  }
  for (int i = 0; i < n; ++i) {
    const double target = std::fmod(u[i], 1.0) * total;
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
    const int k = std::clamp(static_cast<int>(it - cumulative.begin()) - 1, 0, kDirections - 1);
    const double within = (target - cumulative[k]) / (cumulative[k + 1] - cumulative[k]);
    arms[i].angle = offset + 2.0 * kPi * (k + within) / kDirections;
    zone[i] = rays[k].peak_r;
  }
  for (std::size_t rank = 2; rank < order.size(); ++rank) {
    const int m = order[rank];
    arms[m].birth_r = zone[m] * static_cast<double>(rank) / n;
  }

  // 3. Grow the arms in birth order, each from its branch point on its parent straight out in
  // its own direction (a branch leaves its parent at the angle between their directions, which
  // is at most half the branch angle once the star has more arms than 360 / (beta / 2) degrees,
  // larger only for the first few, born within a few branching lengths of the origin), to the
  // outline, wiggling as the crack tree's tips do: with probability P a step, a lateral offset
  // of at most step tan(D/2).
  const bool wiggles = params.wiggle_probability > 0.0 && params.wiggle_variance_deg > 0.0;
  const double wiggle_step = step * std::tan(0.25 * params.wiggle_variance_deg * kPi / 180.0);
  SegmentGrid grid(w, h, 4.0 * step);
  // Whether an arm ran out of the pane (it then bounds its sector beyond the outline too).
  std::vector<char> left_pane(arms.size(), 0);
  const auto grow = [&](int m) {
    Arm& arm = arms[static_cast<std::size_t>(m)];
    Vec2 at = origin;
    if (arm.parent >= 0 && !point_at(arms[static_cast<std::size_t>(arm.parent)], arm.birth_r, at))
      return;
    const Vec2 dir(std::cos(arm.angle), std::sin(arm.angle));
    const Vec2 side(-dir.y(), dir.x());
    arm.points.push_back(at);
    arm.radii.push_back((at - origin).norm());
    double lateral = 0.0;
    for (int k = 1; k < 100000; ++k) {
      if (wiggles && random.uniform() < params.wiggle_probability)
        lateral += wiggle_step * random.symmetric();
      Vec2 next = at + (k * step) * dir + lateral * side;
      // A crack that runs into another stops on it (thesis §5.4.1's hit rule).
      Vec2 hit = Vec2::Zero();
      const bool stops = grid.first_hit(arm.points.back(), next, m, hit) <= 1.0;
      if (stops) next = hit;
      grid.add(arm.points.back(), next, m);
      arm.points.push_back(next);
      // Distances from the origin, kept increasing for point_at (a wiggle may step back a hair).
      arm.radii.push_back(std::max((next - origin).norm(), arm.radii.back()));
      const bool out = next.x() <= 0.0 || next.x() >= w || next.y() <= 0.0 || next.y() >= h;
      if (out && !stops) left_pane[static_cast<std::size_t>(m)] = 1;
      if (stops || out) break;
    }
  };
  for (const int m : order) {
    if (stop && stop()) return stopped();
    grow(m);
  }

  // 4. Branching again: an arm that stopped on another (or was never born) leaves its share to
  // its neighbours, whose stress intensity rises as they run on. Outward, radius by radius, a
  // gap between running arms branches when it alone holds more than two arms' shares of the
  // star there, n (u_gap) (r phi^2 / peak) > 2 along its middle direction — each of its two tips
  // then has more than a whole share, so more than the branching intensity — with a new arm
  // split off as a fork splits its gap, born off one of the two at that radius. Capped at
  // kMaxRadialCracks arms in all.
  const double last_r =
      std::hypot(std::max(origin.x(), w - origin.x()), std::max(origin.y(), h - origin.y()));
  const auto ray_index = [&](double um) {
    const double target = std::fmod(um, 1.0) * total;
    const auto it = std::upper_bound(cumulative.begin(), cumulative.end(), target);
    const int k = std::clamp(static_cast<int>(it - cumulative.begin()) - 1, 0, kDirections - 1);
    return std::pair<int, double>(k,
                                  (target - cumulative[k]) / (cumulative[k + 1] - cumulative[k]));
  };
  u.resize(arms.size());
  std::vector<int> running;
  // Pairs of neighbours that have branched into their gap once: a branch that stops at once
  // (the wiggle runs it back into its parent) does not make the pair branch again and again.
  std::set<std::pair<int, int>> branched;
  for (double r = 4.0 * step; r < last_r; r += 2.0 * step) {
    if (stop && stop()) return stopped();
    running.clear();
    for (int m = 0; m < static_cast<int>(arms.size()); ++m) {
      const Arm& arm = arms[static_cast<std::size_t>(m)];
      if (arm.radii.empty() || arm.radii.front() > r) continue;
      if (arm.radii.back() > r || left_pane[static_cast<std::size_t>(m)]) running.push_back(m);
    }
    if (running.size() < 2) continue;
    std::sort(running.begin(), running.end(), [&](int a, int b) {
      return std::fmod(u[static_cast<std::size_t>(a)], 1.0) <
             std::fmod(u[static_cast<std::size_t>(b)], 1.0);
    });
    const std::size_t count = running.size();
    for (std::size_t s = 0; s < count; ++s) {
      if (arms.size() >= static_cast<std::size_t>(FractureParams::kMaxRadialCracks)) break;
      const int a = running[s];
      const int b = running[(s + 1) % count];
      const double ua = std::fmod(u[static_cast<std::size_t>(a)], 1.0);
      double gap = std::fmod(u[static_cast<std::size_t>(b)], 1.0) - ua;
      if (gap <= 0.0) gap += 1.0;
      const auto [k_mid, within_mid] = ray_index(ua + 0.5 * gap);
      const double mid_angle = offset + 2.0 * kPi * (k_mid + within_mid) / kDirections;
      const Vec2 at = origin + r * Vec2(std::cos(mid_angle), std::sin(mid_angle));
      if (at.x() <= 0.0 || at.x() >= w || at.y() <= 0.0 || at.y() >= h) continue;
      const double phi = stress_shape(at.x(), at.y(), w, h);
      if (!(gap * n * r * phi * phi > 2.0 * rays[static_cast<std::size_t>(k_mid)].peak)) continue;
      if (!branched.emplace(a, b).second) continue;
      // The new arm: the gap split as a fork splits it, off the neighbour that reaches r.
      const double split = 0.5 + 0.5 * jitter * random.symmetric();
      const int parent = random.uniform() < 0.5 ? a : b;
      Vec2 p;
      const int from = point_at(arms[static_cast<std::size_t>(parent)], r, p) ? parent
                       : point_at(arms[static_cast<std::size_t>(parent == a ? b : a)], r, p)
                           ? (parent == a ? b : a)
                           : -1;
      if (from < 0) continue;
      const auto [k, within] = ray_index(ua + split * gap);
      Arm arm;
      arm.angle = offset + 2.0 * kPi * (k + within) / kDirections;
      arm.parent = from;
      arm.birth_r = r;
      const int m = static_cast<int>(arms.size());
      arms.push_back(std::move(arm));
      u.push_back(ua + split * gap);
      left_pane.push_back(0);
      grow(m);
    }
  }

  CrackTree tree;
  for (const Arm& arm : arms)
    add_clipped(arm.points, w, h, tree);

  // 5. Rings: in each sector between neighbouring arms that exist at the ring's radius, a ring
  // piece from one arm to the other (its radius jittered by up to 4 % per sector, so the pieces
  // of neighbouring sectors meet an arm at different points, as in photographs).
  for (const double ring : params.radial.ring_radii_m) {
    if (stop && stop()) return stopped();
    // The arms that reach the ring, in the order of their angle there: an arm that stopped on
    // another or at the outline before it has no share of it.
    struct AtRing {
      const Arm* arm;
      double angle;
    };
    std::vector<AtRing> present;
    for (const Arm& arm : arms) {
      Vec2 p;
      if (point_at(arm, ring, p))
        present.push_back({&arm, std::atan2(p.y() - origin.y(), p.x() - origin.x())});
    }
    std::sort(present.begin(), present.end(),
              [](const AtRing& a, const AtRing& b) { return a.angle < b.angle; });
    const auto count = present.size();
    if (count < 2) continue;
    for (std::size_t s = 0; s < count; ++s) {
      const AtRing& a = present[s];
      const AtRing& b = present[(s + 1) % count];
      // Each sector's piece at its own radius (up to 4 % off the ring's), from arm to arm:
      // its ends slide along the arms to that radius.
      const double rho = ring * (1.0 + 0.04 * random.symmetric());
      Vec2 end_a, end_b;
      if (!point_at(*a.arm, rho, end_a)) point_at(*a.arm, ring, end_a);
      if (!point_at(*b.arm, rho, end_b)) point_at(*b.arm, ring, end_b);
      double angle_b = b.angle;
      while (angle_b <= a.angle)
        angle_b += 2.0 * kPi;
      const double sweep = angle_b - a.angle;
      const int pieces = std::max(1, static_cast<int>(std::ceil(rho * sweep / step)));
      std::vector<Vec2> line;
      line.reserve(static_cast<std::size_t>(pieces) + 1);
      for (int k = 0; k <= pieces; ++k) {
        const double t = a.angle + sweep * k / pieces;
        line.push_back(origin + rho * Vec2(std::cos(t), std::sin(t)));
      }
      line.front() = end_a;
      line.back() = end_b;
      add_clipped(line, w, h, tree);
    }
  }
  return tree;
}

FracturePattern dice_pattern(const FractureParams& params, const StopRequest& stop) {
  const double w = params.width_m;
  const double h = params.height_m;
  FracturePattern pattern;
  pattern.width_m = w;
  pattern.height_m = h;
  const auto stopped = [&] {
    FracturePattern abandoned;
    abandoned.width_m = w;
    abandoned.height_m = h;
    abandoned.stopped = true;
    return abandoned;
  };
  const int nx = std::max(1, static_cast<int>(std::lround(w / params.dice_cell_m)));
  const int ny = std::max(1, static_cast<int>(std::lround(h / params.dice_cell_m)));
  const double dx = w / nx;
  const double dy = h / ny;
  Random random(params.seed);
  // Grid nodes, jittered by up to 30 % of a cell (the outline's nodes only along it).
  const auto index = [&](int i, int j) {
    return static_cast<std::size_t>(j) * static_cast<std::size_t>(nx + 1) +
           static_cast<std::size_t>(i);
  };
  std::vector<Vec2> nodes(static_cast<std::size_t>(nx + 1) * static_cast<std::size_t>(ny + 1));
  for (int j = 0; j <= ny; ++j) {
    if (stop && stop()) return stopped();
    for (int i = 0; i <= nx; ++i) {
      double x = i * dx;
      double y = j * dy;
      const double jx = 0.3 * dx * random.symmetric();
      const double jy = 0.3 * dy * random.symmetric();
      if (i > 0 && i < nx) x += jx;
      if (j > 0 && j < ny) y += jy;
      if (i == nx) x = w;
      if (j == ny) y = h;
      nodes[index(i, j)] = {x, y};
    }
  }
  pattern.fragments.reserve(static_cast<std::size_t>(nx) * static_cast<std::size_t>(ny));
  for (int j = 0; j < ny; ++j) {
    if (stop && stop()) return stopped();
    for (int i = 0; i < nx; ++i) {
      Fragment cell;
      cell.polygon_m = {nodes[index(i, j)], nodes[index(i + 1, j)], nodes[index(i + 1, j + 1)],
                        nodes[index(i, j + 1)]};
      cell.area_m2 = geometry::signed_area(cell.polygon_m);
      cell.centroid_m = geometry::centroid(cell.polygon_m);
      pattern.fragments.push_back(std::move(cell));
    }
  }
  // Edges: each interior grid line piece is a crack, each outline piece a border edge.
  for (int j = 0; j <= ny; ++j) {
    for (int i = 0; i <= nx; ++i) {
      if (i < nx) {
        const std::array<Vec2, 2> e{nodes[index(i, j)], nodes[index(i + 1, j)]};
        (j == 0 || j == ny ? pattern.border_edges : pattern.crack_edges).push_back(e);
      }
      if (j < ny) {
        const std::array<Vec2, 2> e{nodes[index(i, j)], nodes[index(i, j + 1)]};
        (i == 0 || i == nx ? pattern.border_edges : pattern.crack_edges).push_back(e);
      }
    }
  }
  return pattern;
}

WindowCount fragments_per_window(const FracturePattern& pattern, double window_m, double margin_m) {
  WindowCount out;
  const double w = pattern.width_m;
  const double h = pattern.height_m;
  const double span_x = w - 2.0 * margin_m - window_m;
  const double span_y = h - 2.0 * margin_m - window_m;
  if (!(window_m > 0.0) || span_x < 0.0 || span_y < 0.0) return out;
  // Centroids bucketed by a grid of window_m / 4, then windows of 4 x 4 buckets.
  const double cell = 0.25 * window_m;
  const int bx = static_cast<int>(std::ceil(w / cell)) + 1;
  const int by = static_cast<int>(std::ceil(h / cell)) + 1;
  std::vector<std::size_t> counts(static_cast<std::size_t>(bx) * static_cast<std::size_t>(by), 0);
  const double x0 = margin_m;
  const double y0 = margin_m;
  for (const Fragment& f : pattern.fragments) {
    const double gx = std::floor((f.centroid_m.x() - x0) / cell);
    const double gy = std::floor((f.centroid_m.y() - y0) / cell);
    if (gx < 0.0 || gy < 0.0 || gx >= bx || gy >= by) continue;
    ++counts[static_cast<std::size_t>(gy) * static_cast<std::size_t>(bx) +
             static_cast<std::size_t>(gx)];
  }
  const int wx = static_cast<int>(std::floor(span_x / cell + 1e-9));
  const int wy = static_cast<int>(std::floor(span_y / cell + 1e-9));
  out.fewest = static_cast<std::size_t>(-1);
  for (int j = 0; j <= wy; ++j) {
    for (int i = 0; i <= wx; ++i) {
      std::size_t sum = 0;
      for (int v = 0; v < 4; ++v)
        for (int u = 0; u < 4; ++u)
          sum += counts[static_cast<std::size_t>(j + v) * static_cast<std::size_t>(bx) +
                        static_cast<std::size_t>(i + u)];
      out.fewest = std::min(out.fewest, sum);
      out.most = std::max(out.most, sum);
      ++out.windows;
    }
  }
  if (out.windows == 0) out.fewest = 0;
  return out;
}

}  // namespace brisance::fracture
