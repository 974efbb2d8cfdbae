#include "sim/engine/panes.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>

#include "sim/blast/blast_point.hpp"
#include "sim/engine/pane_pattern.hpp"
#include "sim/fracture/fragments.hpp"
#include "sim/fracture/nucleation.hpp"
#include "sim/fracture/pane.hpp"
#include "sim/geometry/polygon.hpp"
#include "sim/response/plate.hpp"
#include "sim/response/sdof.hpp"

namespace brisance::engine {

namespace {

using Vec2 = Eigen::Vector2d;
using Vec3 = Eigen::Vector3d;

// splitmix64: a pane's pattern seed from the scene's seed and the pane's object index, so two
// panes of one scene crack differently and a scene's seed changes all of them.
std::uint64_t mix_seed(std::uint64_t seed, std::uint64_t index) {
  std::uint64_t z = seed + 0x9E3779B97F4A7C15ULL * (index + 1);
  z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ULL;
  z = (z ^ (z >> 27)) * 0x94D049BB133111EBULL;
  return z ^ (z >> 31);
}

}  // namespace

blast::PanelLoadOptions pane_load_options(const scene::ObjectSpec& object,
                                          const scene::SimulationSpec& simulation,
                                          const PaneSize& size) {
  blast::PanelLoadOptions options;
  options.shape = simulation.pulse_shape;
  options.clearing = simulation.clearing;
  options.clearing_distance_m = pane_clearing_distance_m(size);
  options.drag_coefficient = object.drag_coefficient;
  return options;
}

// The load on the face of the pane that faces each charge, at the pane's centre: the front-face
// history the engine gives its fragments (pane_face_load: reflected at the angle of incidence,
// cleared from the pane's own edges as `options` say), arriving at the curves' arrival time,
// summed over the charges; and the largest of their peaks (the static model's load: peaks of
// several charges rarely coincide, so they are not added). The plate models take a uniform
// pressure, so the centre's value stands for the pane.
PaneLoad pane_load_at(const Vec3& centre, const Vec3& normal,
                      const std::vector<ChargeModel>& charges,
                      const blast::PanelLoadOptions& options, bool& out_of_range, Vec3& push) {
  PaneLoad load;
  push = -normal;
  for (const ChargeModel& c : charges) {
    const Vec3 d = centre - c.position;
    const double distance = std::max(d.norm(), 1e-3);
    const double cos_incidence = std::min(1.0, std::abs(normal.dot(d)) / distance);
    PaneFaceLoad face = pane_face_load(c.charge, distance, cos_incidence, options);
    out_of_range = out_of_range || !face.in_range;
    // The plate is pushed away from the charge with the largest peak.
    if (face.peak_pressure_pa > load.peak_pressure_pa)
      push = normal.dot(d) >= 0.0 ? normal : -normal;
    load.peak_pressure_pa = std::max(load.peak_pressure_pa, face.peak_pressure_pa);
    if (face.component.history.size() > 0) load.history.components.push_back(face.component);
  }
  // Only the arrivals' differences matter to the pane's peak stress: its clock starts at the
  // first, as `brisance fracture`'s pulse does, so one charge gives the CLI's numbers exactly.
  double first = INFINITY;
  for (const response::LoadComponent& c : load.history.components)
    first = std::min(first, c.arrival_s);
  for (response::LoadComponent& c : load.history.components)
    c.arrival_s -= first;
  if (std::isfinite(first)) load.clock_start_s = first;
  return load;
}

namespace {

// Where the pane's cracks start (issue 11): the point of the largest bending stress of the
// simply supported plate under the peak pressures over its face (fracture::
// largest_bending_stress), in pane coordinates from its lower-left corner. The pressures are
// sampled at the centres of kSamples x kSamples cells, each point taking the largest peak of the
// charges (as the pane's static load takes the largest peak), and summed to kTerms x kTerms sine
// terms. A face loaded alike everywhere (to 1e-9) cracks from its centre without the search.
Vec2 crack_origin(const scene::ObjectSpec& object, const Eigen::Quaterniond& q,
                  const std::vector<ChargeModel>& charges, const blast::PanelLoadOptions& options) {
  constexpr int kSamples = 32;
  constexpr int kTerms = 15;
  constexpr int kEvaluationCells = 16;
  const double width = object.box_size_m.x();
  const double height = object.box_size_m.y();
  const Vec2 centre(0.5 * width, 0.5 * height);
  const Vec3 normal = q * Vec3::UnitZ();
  const double dx = width / kSamples;
  const double dy = height / kSamples;
  std::vector<fracture::PointForce> forces;
  forces.reserve(kSamples * kSamples);
  double lowest = INFINITY;
  double highest = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    for (int j = 0; j < kSamples; ++j) {
      const Vec2 p((i + 0.5) * dx, (j + 0.5) * dy);
      const Vec3 world = object.position + q * Vec3(p.x() - centre.x(), p.y() - centre.y(), 0.0);
      double pressure = 0.0;
      for (const ChargeModel& c : charges) {
        const Vec3 d = world - c.position;
        const double distance = std::max(d.norm(), 1e-3);
        const double cos_incidence = std::min(1.0, std::abs(normal.dot(d)) / distance);
        pressure = std::max(
            pressure, pane_face_load(c.charge, distance, cos_incidence, options).peak_pressure_pa);
      }
      lowest = std::min(lowest, pressure);
      highest = std::max(highest, pressure);
      forces.push_back({p, pressure * dx * dy});
    }
  }
  if (!(highest > 0.0) || highest - lowest <= 1e-9 * highest) return centre;
  return fracture::largest_bending_stress(width, height, object.box_size_m.z(),
                                          response::PlateSpec{}.poissons_ratio, forces, kTerms,
                                          kEvaluationCells)
      .point_m;
}

double earliest_arrival_s(const Vec3& point, const std::vector<ChargeModel>& charges) {
  double earliest = INFINITY;
  for (const ChargeModel& c : charges)
    earliest = std::min(
        earliest,
        blast::blast_point(c.charge, std::max((point - c.position).norm(), 1e-3)).arrival_time_s);
  return earliest;
}

// Length of the polygon's outline that lies on the pane's border (pane coordinates), m.
double border_length(const geometry::Polygon& polygon, double width, double height) {
  const double eps = 1e-9 * std::max(width, height);
  const auto on_side = [&](const Vec2& a, const Vec2& b) {
    return (std::abs(a.x()) <= eps && std::abs(b.x()) <= eps) ||
           (std::abs(a.x() - width) <= eps && std::abs(b.x() - width) <= eps) ||
           (std::abs(a.y()) <= eps && std::abs(b.y()) <= eps) ||
           (std::abs(a.y() - height) <= eps && std::abs(b.y() - height) <= eps);
  };
  double length = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[(i + 1) % polygon.size()];
    if (on_side(a, b)) length += (b - a).norm();
  }
  return length;
}

double perimeter(const geometry::Polygon& polygon) {
  double length = 0.0;
  for (std::size_t i = 0; i < polygon.size(); ++i)
    length += (polygon[(i + 1) % polygon.size()] - polygon[i]).norm();
  return length;
}

constexpr double kOnePanelSize_m = 0.02;

// How the waves cross a fragment: the most by which its farthest corner lies farther from a
// charge than its nearest (the spread of path lengths, m; zero for a face square to the wave,
// its whole extent for one the wave runs along), and the nearest corner's distance, over the
// charges. `outline`: the fragment's corners in world coordinates.
struct WaveCrossing {
  double distance_spread_m = 0.0;
  double nearest_m = INFINITY;
};

WaveCrossing wave_crossing(const std::vector<Vec3>& outline,
                           const std::vector<ChargeModel>& charges) {
  WaveCrossing crossing;
  for (const ChargeModel& c : charges) {
    double nearest = INFINITY, farthest = 0.0;
    for (const Vec3& v : outline) {
      const double d = (v - c.position).norm();
      nearest = std::min(nearest, d);
      farthest = std::max(farthest, d);
    }
    crossing.distance_spread_m = std::max(crossing.distance_spread_m, farthest - nearest);
    crossing.nearest_m = std::min(crossing.nearest_m, nearest);
  }
  return crossing;
}

// Panels of both faces (front +z, its mirror on the back −z) with clearing distance S, and the
// faces plus side walls for the flight-drag shape. Polygon in the pane's centred frame.
void fragment_panels(const geometry::Polygon& polygon, double thickness, double pane_half_size,
                     bool own_clearing, const WaveCrossing& crossing, BodySource& body) {
  // A fragment under kOnePanelSize_m across takes its load on one panel a face
  // (docs/fracture.md, "Performance"): across it the wave's arrival differs by under 0.1 ms (the
  // slowest shock, the speed of sound, 343 m/s) against pulses of milliseconds, so its several
  // panels would carry the same pressure and give the same force and no torque about its
  // centroid. So does a larger one the waves cross within that much path, when that is also
  // under 1 % of its distance (the peak pressure, falling as R^-1.5 to R^-3, then varies by
  // under 3 % across it): one panel at the face's centroid gives the force of a pressure that
  // varies linearly across the face exactly and drops only that variation's small torque.
  // window.json's pane, 10 m from its charge and square to it, is crossed within 7.5 cm of path
  // per metre of a fragment's extent.
  // (The crossing first: it decides most pieces without the all-pairs scan of their corners.)
  const auto under_one_panel_size = [&] {
    for (const Vec2& a : polygon)
      for (const Vec2& b : polygon)
        if ((a - b).norm() > kOnePanelSize_m) return false;
    return true;
  };
  const bool one = (crossing.distance_spread_m <= kOnePanelSize_m &&
                    crossing.distance_spread_m <= 0.01 * crossing.nearest_m) ||
                   under_one_panel_size();
  std::vector<geometry::Panel> front = one ? geometry::front_panels(polygon, thickness, 1, 1)
                                           : geometry::front_panels(polygon, thickness);
  if (one) {
    // front_panels' count for it: its ear clipping's n - 2 triangles, within 5 to 16, a face.
    const auto full = std::clamp<std::size_t>(polygon.size() - 2, 5, 16);
    body.panels_merged = static_cast<std::uint32_t>(2 * (full - front.size()));
  }
  body.load_panels.reserve(2 * front.size());
  for (geometry::Panel panel : front) {
    if (!own_clearing) panel.face_half_size_m = pane_half_size;
    body.load_panels.push_back(panel);
    panel.centre.z() = -panel.centre.z();
    panel.outward_normal = -panel.outward_normal;
    body.load_panels.push_back(panel);
  }
  const double area = geometry::signed_area(polygon);
  const Vec2 c = geometry::centroid(polygon);
  body.drag_panels.push_back({Vec3(c.x(), c.y(), 0.5 * thickness), Vec3::UnitZ(), area, 0.0});
  body.drag_panels.push_back({Vec3(c.x(), c.y(), -0.5 * thickness), -Vec3::UnitZ(), area, 0.0});
  for (std::size_t i = 0; i < polygon.size(); ++i) {
    const Vec2& a = polygon[i];
    const Vec2& b = polygon[(i + 1) % polygon.size()];
    const Vec2 edge = b - a;
    const double length = edge.norm();
    if (length <= 0.0) continue;
    const Vec2 mid = 0.5 * (a + b);
    // Counter-clockwise outline: the outward normal of an edge is its direction turned clockwise.
    body.drag_panels.push_back({Vec3(mid.x(), mid.y(), 0.0),
                                Vec3(edge.y() / length, -edge.x() / length, 0.0),
                                length * thickness, 0.0});
  }
}

}  // namespace

PaneReport break_pane(const scene::ObjectSpec& object, std::size_t index,
                      const std::vector<ChargeModel>& charges,
                      const scene::SimulationSpec& simulation, std::vector<BodySource>& out,
                      bool& out_of_range, std::size_t& solver_warnings, Checkpoint& checkpoint) {
  const scene::FractureSpec& spec = *object.fracture;
  assert(object.shape == scene::ShapeType::box);
  const double width = object.box_size_m.x();
  const double height = object.box_size_m.y();
  const double thickness = object.box_size_m.z();
  const Eigen::Quaterniond q = object.orientation.normalized();
  const Vec3 normal = q * Vec3::UnitZ();

  PaneReport report;
  report.name = object.name;
  report.strength_pa = spec.strength_pa;
  const PaneSize size{width, height, thickness, object.mass_kg / (width * height * thickness)};
  const blast::PanelLoadOptions options = pane_load_options(object, simulation, size);
  Vec3 push;
  const PaneLoad load = pane_load_at(object.position, normal, charges, options, out_of_range, push);
  report.peak_pressure_pa = load.peak_pressure_pa;
  const PanePattern pattern_plan =
      pane_pattern(spec, size, load, spec.seed ? *spec.seed : mix_seed(simulation.seed, index));
  solver_warnings += pattern_plan.solver_warnings;
  const fracture::PaneFracture& response = pattern_plan.response;
  report.stress_pa = response.plate.stress_pa;
  report.deflection_m = response.plate.deflection_m;
  report.small_deflection = response.plate.small_deflection;
  report.critical_crack_length_m = response.critical_crack_length_m;
  report.forced = pattern_plan.forced;
  report.broken = response.breaks || report.forced;
  report.empirical_mean_area_m2 = fracture::empirical_fragment_area_m2(report.peak_pressure_pa);
  if (thickness > 7.62e-4 && report.peak_pressure_pa > 0.0)
    report.empirical_mean_speed_m_s =
        fracture::empirical_fragment_velocity_m_s(report.peak_pressure_pa, thickness);

  if (!report.broken) {
    // Skip what is not needed (decision 10): no pattern, the pane stays one body; in a frame
    // it does not move.
    BodySource pane = object_source(object, simulation.max_panel_area_m2);
    if (spec.framed) pane.anchored = true;
    out.push_back(std::move(pane));
    return report;
  }

  report.growth_length_m = pattern_plan.growth_length_m;
  report.growth_length_given = pattern_plan.growth_length_given;
  report.growth_length_clamped = pattern_plan.growth_length_clamped;
  fracture::FractureParams params = pattern_plan.params;
  if (params.initial.centres_m.empty())
    params.initial.centres_m.push_back(crack_origin(object, q, charges, options));
  report.crack_origin_m = {params.initial.centres_m.front().x(),
                           params.initial.centres_m.front().y()};
  assert(!fracture::validate(params));  // the scene's fracture spec was validated
  checkpoint.poll();
  const fracture::FracturePattern pattern = fracture::fracture(params, checkpoint.stop_request());
  if (pattern.stopped) throw RunCancelled{};

  report.first_body = static_cast<std::uint32_t>(out.size());
  report.fragment_count = pattern.fragments.size();
  const double density = object.mass_kg / (width * height * thickness);
  const Vec2 half(0.5 * width, 0.5 * height);
  const bool own_clearing = spec.clearing == scene::FractureSpec::Clearing::fragment;
  // Launch (docs/fracture.md, "Speed spread"): when the dynamic plate's stress reaches the
  // strength the pane cracks through, moving as its mode shape sin(pi x / W) sin(pi y / H) (the
  // shape of the one-term solution sim/response/plate is built on): fast at the centre, still
  // at the frame. The impulse its face took until then, i_b per area, is shared out in that
  // shape instead of per area: fragment k gains (i_b / (rho h)) (phi_k / phi_mean - 1) at release
  // on top of its own loads, phi_k the shape at its centroid and phi_mean its area-weighted mean
  // over the fragments, so the pane's momentum is unchanged.
  std::vector<double> mode(pattern.fragments.size(), 1.0);
  double mode_mean = 1.0;
  // Only where the face takes the whole push: a sheltered back (no rear load to net out) and
  // the pane's clearing (with the thesis's per-fragment clearing the pieces take their own
  // loads from the start, larger ones more).
  const bool inherits = response.breaks && response.plate.break_time_s >= 0.0 && !own_clearing &&
                        scene::is_sheltered(object.sheltered, q.inverse() * push);
  double break_speed = 0.0;  // i_b / (rho h), m/s
  if (inherits) {
    constexpr double kPi = 3.14159265358979323846;
    double weighted = 0.0, area = 0.0;
    for (std::size_t k = 0; k < pattern.fragments.size(); ++k) {
      const fracture::Fragment& piece = pattern.fragments[k];
      mode[k] = std::sin(kPi * std::clamp(piece.centroid_m.x() / width, 0.0, 1.0)) *
                std::sin(kPi * std::clamp(piece.centroid_m.y() / height, 0.0, 1.0));
      weighted += piece.area_m2 * mode[k];
      area += piece.area_m2;
    }
    mode_mean = weighted / area;
    break_speed =
        load.history.impulse_pa_s(0.0, response.plate.break_time_s) / (density * thickness);
  }
  // Fracture runs with the wave: the cracks start where and when the stress first reaches the
  // strength — at the pattern's nucleation point (crack_origin: where the plate's stress peaks
  // under the face's peak pressures; the centre for a uniform load), at the dynamic plate's
  // break time (the first arrival for the static
  // model or a forced break) — and run out at the terminal crack speed of glass. A fragment is
  // free only once the front has passed all of its outline (its cracks have closed around it).
  std::vector<Vec2> nuclei = params.initial.centres_m;
  if (nuclei.empty()) nuclei.push_back(half);
  const double cracks_start_s = load.clock_start_s + std::max(response.plate.break_time_s, 0.0);
  report.cracks_start_s = cracks_start_s;
  for (std::size_t k = 0; k < pattern.fragments.size(); ++k) {
    checkpoint.tick(256);
    const fracture::Fragment& piece = pattern.fragments[k];
    double closed_at_m = INFINITY;  // the front's run from the nearest nucleus around the piece
    for (const Vec2& nucleus : nuclei) {
      double farthest = 0.0;
      for (const Vec2& v : piece.polygon_m)
        farthest = std::max(farthest, (v - nucleus).norm());
      closed_at_m = std::min(closed_at_m, farthest);
    }
    geometry::Polygon local = geometry::remove_collinear(piece.polygon_m);
    for (Vec2& v : local)
      v -= half;
    BodySource body;
    body.name = object.name + "/f" + std::to_string(k);
    body.material = object.material;
    body.fragment = true;
    body.blocks = false;  // the glass the wave itself breaks shields nothing behind it
    body.frontal_area_m2 = piece.area_m2;
    body.unit_mass = geometry::prism_mass_properties(local, thickness, 1.0);
    std::vector<Vec3> outline;
    outline.reserve(local.size());
    for (const Vec2& v : local)
      outline.push_back(object.position + q * Vec3(v.x(), v.y(), 0.0));
    fragment_panels(local, thickness, options.clearing_distance_m, own_clearing,
                    wave_crossing(outline, charges), body);
    // The hold (docs/fracture.md): the crack faces' interlock over the crack's area, and the
    // glazing's grip along the frame.
    const double on_border = border_length(piece.polygon_m, width, height);
    const double crack_length = std::max(0.0, perimeter(piece.polygon_m) - on_border);
    double hold = spec.bond_strength_pa * crack_length * thickness;
    if (spec.framed) hold += spec.frame_strength_pa * spec.frame_bite_m * on_border;
    body.breakaway_hold_n = hold;
    const Vec3 centroid_world = object.position + q * Vec3(piece.centroid_m.x() - half.x(),
                                                           piece.centroid_m.y() - half.y(), 0.0);
    body.release_not_before_s =
        std::max(earliest_arrival_s(centroid_world, charges),
                 cracks_start_s + closed_at_m / fracture::kTerminalCrackSpeed_m_s);
    if (inherits && mode_mean > 0.0)
      body.release_velocity_m_s = break_speed * (mode[k] / mode_mean - 1.0) * push;
    body.mesh = geometry::extrude(local, thickness);
    body.position = object.position;
    body.orientation = object.orientation;
    body.mass_kg = density * body.unit_mass.volume_m3;
    body.friction = object.friction;
    body.drag_coefficient = object.drag_coefficient;
    body.rotates = object.rotates;
    body.sheltered = object.sheltered;
    out.push_back(std::move(body));
  }
  return report;
}

}  // namespace brisance::engine
