// sim/engine/model (private to the engine): what prepare builds and stepping reads — the body
// sources prepare starts from, the read-only Model (STYLE.md §1: it owns its values and points
// nowhere into the scene), the one charge → blast charge conversion, the warning log, and the
// prepare stages. Each stage lives in its own file:
//   body_sources.cpp       scene objects and broken panes → one uniform list of bodies to create
//   panes.cpp              breaking one pane into fragment sources (DESIGN.md decision 9)
//   prepare_holds.cpp      friction holds: the weight each body carries (thesis §3.6)
//   clearing_surfaces.cpp  clearing distances shared across contiguous coplanar surfaces
//   prepare_shielding.cpp  each panel's shielding from each charge (sim/occlusion, thesis ch. 4)
//   prepare.cpp            bodies, panels, charges and the arrival-ordered panel events
// A new prepare-time system is one more stage that fills one more per-panel field of the Model,
// as shielding does.
#pragma once

#include <cmath>
#include <cstdint>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "sim/blast/blast_point.hpp"
#include "sim/blast/panel_load.hpp"
#include "sim/dynamics/ground_contact.hpp"
#include "sim/dynamics/rigid_body.hpp"
#include "sim/engine/interrupt.hpp"
#include "sim/engine/result.hpp"
#include "sim/geometry/mesh.hpp"
#include "sim/scene/scene.hpp"

namespace brisance::engine {

// The one text of the blast_out_of_range warning, raised while breaking panes and while loading.
inline constexpr const char* kBlastOutOfRangeMessage =
    "a panel lies outside the Kingery-Bulmash fitted range (Z 0.05-40 m/kg^(1/3)); its load is "
    "continued from the range's end (see docs/blast-model.md)";

using dynamics::Quat;
using dynamics::Vec3;

// The blast charge a scene charge detonates (TNT equivalent W = mass × factor, DESIGN.md
// decision 1).
blast::Charge blast_charge(const scene::ChargeSpec& spec);

// One body to create. Scene objects and the fragments of broken panes alike: prepare builds
// every body from this list the same way.
struct BodySource {
  std::string name;
  std::string material;                 // the materials table's name, or "" (given density)
  geometry::TriangleMesh mesh;          // shape frame
  Vec3 position = Vec3::Zero();         // world position of the shape's origin, m
  Quat orientation = Quat::Identity();  // shape to world, as given (not normalised)
  double mass_kg = 0.0;
  double friction = 0.5;
  double drag_coefficient = 1.0;
  bool anchored = false;
  bool blocks = true;  // may shield others (a broken pane's fragments do not)
  bool rotates = true;
  std::uint8_t sheltered = 0;                // scene::ObjectSpec::sheltered, in the shape frame
  geometry::MassProperties unit_mass;        // at 1 kg/m^3, shape frame
  std::vector<geometry::Panel> load_panels;  // shape frame
  std::vector<geometry::Panel> drag_panels;  // for the flight-drag shape; empty: load_panels
  std::uint32_t panels_merged = 0;           // load panels not made (a small fragment: one a face)
  // A hold that breaks once and for all (a fragment's frame grip and crack interlock), N;
  // none: friction on what the body rests on.
  std::optional<double> breakaway_hold_n;
  double release_not_before_s = 0.0;  // a fragment: the first wave at its centroid, s
  // A fragment of a pane the dynamic plate broke (docs/fracture.md, "Launch"): the velocity
  // added when it breaks free (world, m/s), which shares the impulse the pane took before it
  // cracked through out as the plate's mode shape, not per area. Sums to no momentum over
  // the pane's fragments.
  Vec3 release_velocity_m_s = Vec3::Zero();
  // Fragments of a broken pane: their clearing distance is their pane's choice, never shared
  // with their coplanar neighbours; their release and launch are reported.
  bool fragment = false;
  double frontal_area_m2 = 0.0;  // fragments only
};

struct BodySources {
  std::vector<BodySource> bodies;
  std::vector<PaneReport> reports;                            // one per breakable pane
  std::vector<std::pair<std::string, std::string>> warnings;  // code, message
};

enum class Motion : std::uint8_t {
  anchored,  // never moves
  held,      // resting, held by friction until its load beats mu N (thesis §3.6)
  awake,     // integrated every step
  asleep,    // came to rest on the ground; woken by a new load
};

// A panel in its body's frame, relative to the body's centre of mass.
struct PanelModel {
  std::uint32_t body;
  Vec3 centre;
  Vec3 normal;  // outward, unit
  double area_m2;
  double clearing_distance_m;  // S of the surface the panel lies in
  double extent_m;             // the panel's own size, sqrt(area): a side face's rise
  bool sheltered;              // nothing reaches it from behind (a room behind a window)
};

struct ChargeModel {
  Vec3 position;  // world, m
  blast::Charge charge;
  double reach_m = INFINITY;  // how far its wave travels within the run (blast::wave_reach_m)
};

// The wave of one charge reaching one panel (thesis §3.5.3): on its front, its side or its rear
// (blast::FaceKind, decided when the wave arrives). The arrival time comes from the
// Kingery–Bulmash fit at the panel's starting distance rather than from integrating U; for a
// rear face that distance runs straight through the body, which is the length of the body the
// wave wrapped around (thesis §2.6.4, "Rear Face").
struct PanelEvent {
  double arrival_time_s;
  std::uint32_t panel;
  std::uint32_t charge;
};

// The run's clock: how long, how often a frame, how the step is chosen.
struct Timing {
  double duration_s = 2.0;
  double frame_rate_hz = 30.0;
  std::optional<double> time_step_s;  // fixed step; absent: adaptive from `tolerance`
  double tolerance = 1e-3;
  bool sleep = true;  // bodies at rest on the ground stop being integrated
  // Bodies take substeps of their own where their spin (WorldSettings::max_turn_per_substep_rad)
  // or their approach to the ground needs them: the step no longer shrinks with the fastest
  // spinner or the fastest body near the ground.
  bool body_substeps = false;
  // Bodies turn in substeps of their own (WorldSettings::max_turn_per_substep_rad) and the
  // fastest spinner no longer shortens the step: with body_substeps, and with contacts between
  // bodies under semi_implicit_euler (a brick spun up by an impact held every body's contact
  // solve to its steps: 122 of the brick wall's 332 steps).
  bool turn_substeps = false;
};

// Contacts between bodies (`simulation.collisions`).
enum class Collisions : std::uint8_t { automatic, on, off };

// An anchored body off the ground that touches movable bodies (not fragments) at the start, and
// those bodies.
struct EmbeddedAnchor {
  std::uint32_t body;
  std::vector<std::uint32_t> neighbours;
};

// Everything that does not change while stepping (STYLE.md §1), per body in body order.
struct Model {
  std::vector<dynamics::BodyModel> bodies;
  // Panels whose centre lies inside a charge (a TNT sphere of its equivalent mass): the scene put
  // the charge into an object; counted for a warning.
  std::uint64_t panels_inside_charges = 0;
  std::vector<dynamics::BodyState> initial_states;  // at rest, the scene's poses
  std::vector<Vec3> centre_of_mass;  // shape frame: from the shape's origin to the centre of mass
  std::vector<double> hold_force_n;  // mu N, N: own weight plus the weight resting on it
  std::vector<std::uint8_t>
      supported;  // held on other bodies: friction resists its loads (eq. 2.40)
  std::vector<Motion> initial_motion;
  std::vector<double> friction;  // each body's coefficient, for contacts between bodies
  // The standing bodies each body rests on at the start (Footing::supports): with collisions on,
  // a held body whose supports have all been released is released too.
  std::vector<std::vector<std::uint32_t>> supports;
  // Anchored bodies set into movable ones (a window's frame in a brick wall), with the movable
  // bodies they touch at the start (embedded_anchors): if all of those are blown away, the
  // anchored body is left floating, and the run says so.
  std::vector<EmbeddedAnchor> embedded_anchors;
  // Fragments of broken panes (thesis §6.7): whether a body is one, and the earliest time it
  // may break free (the wave's arrival at its centroid; 0 for others).
  std::vector<std::uint8_t> fragment;
  std::vector<double> release_not_before_s;
  // Per body: the velocity a fragment gains when it breaks free (BodySource; 0 for others).
  std::vector<Vec3> release_velocity_m_s;
  std::vector<PanelModel> panels;
  std::vector<ChargeModel> charges;
  std::vector<PanelEvent> events;  // ascending arrival time
  // Per panel: some charge's wave reaches it only after the run, so it has no event from that
  // charge (prepare_events); with no other charge's load it counts as not reached.
  std::vector<std::uint8_t> panel_beyond_reach;
  // The shielding of each panel from each charge (thesis ch. 4), charge-major (charge c, panel
  // p at c * panels.size() + p), in [0, 1]; empty: nothing shields anything. Front faces take
  // their own; side and rear faces their body's area-weighted mean (body_shielding, c *
  // bodies.size() + b): the side-on pressure around a body nearly balances, and the pixel noise
  // of per-panel values on opposite faces would turn it into a sideways push.
  std::vector<float> shielding;
  std::vector<float> body_shielding;
  dynamics::WorldSettings world;
  std::optional<dynamics::Ground> ground;
  blast::PanelLoadOptions load_options;
  double rotation_factor = 1.0;
  Collisions collisions = Collisions::off;
  Timing timing;
};

class WarningLog {
 public:
  void add(const std::string& code, const std::string& message, std::uint64_t count = 1) {
    auto [it, inserted] = warnings_.try_emplace(code, Warning{code, message, 0});
    it->second.count += count;
  }
  std::vector<Warning> list() const {
    std::vector<Warning> out;
    for (const auto& [code, warning] : warnings_)
      out.push_back(warning);
    return out;
  }

 private:
  std::map<std::string, Warning> warnings_;
};

// World-axis bounding box of a body at its starting pose.
struct Box {
  Vec3 min;
  Vec3 max;
};
Box world_box(const BodySource& source);

// The run's size as its bodies are created (budget.hpp): counts and an estimate of the bytes the
// run will hold for them, checked against the budget at each add (budget.cpp).
class BudgetTally {
 public:
  BudgetTally(const RunBudget& budget, const scene::Scene& scene);
  // What a body's cost follows: the sizes of its mesh, panels and name, and whether it moves.
  struct BodySize {
    std::uint64_t vertices = 0;
    std::uint64_t triangles = 0;
    std::uint64_t load_panels = 0;
    std::uint64_t drag_panels = 0;
    std::uint64_t name_bytes = 0;
    bool anchored = false;
    bool fragment = false;  // a piece of a broken pane (counted against max_fragments)
  };
  static BodySize size_of(const BodySource& source);
  // A body the run creates: counted, then checked; throws RunOverBudget past a limit or the
  // memory budget.
  void add(const BodySource& source) { add(size_of(source)); }
  // `copies` bodies of one size at once (the estimate before a run, budget_estimate.cpp).
  void add(const BodySize& size, std::uint64_t copies = 1);
  // The bytes a body of this size costs the run, frames included (budget.cpp).
  std::uint64_t bytes_of(const BodySize& size) const;
  std::uint64_t bytes() const { return bytes_; }

 private:
  void check() const;

  RunBudget budget_;
  std::uint64_t frames_ = 0;   // stored frames, the first at t = 0 included
  std::uint64_t charges_ = 0;  // panel events and shielding are per panel and charge
  std::uint64_t bodies_ = 0;
  std::uint64_t fragments_ = 0;
  std::uint64_t panels_ = 0;
  std::uint64_t bytes_ = 0;
};

// --- Prepare stages, in the order prepare runs them ---

// Every body the run creates: scene objects as they are, breakable panes broken or not. Polls
// `checkpoint` per object and while a pane breaks.
// `tally`, if given, counts every body made and stops the run past its budget.
BodySources body_sources(const scene::Scene& scene, Checkpoint& checkpoint,
                         BudgetTally* tally = nullptr);
inline BodySources body_sources(const scene::Scene& scene) {
  Checkpoint never;
  return body_sources(scene, never);
}

// The normal force each body presses down with at the start: its own weight plus its share of
// the bodies resting on it, N (prepare_holds.cpp).
std::vector<double> supported_weights(const std::vector<BodySource>& sources, double gravity);

// What each body stands on at the start (prepare_holds.cpp). A friction hold needs something to
// hold on to (issue 13): the ground (its bottom within 5 mm), an anchored body, a fragment's
// frame grip, or a body that itself stands, resting under it by the rule of supported_weights.
// A body that stands on nothing falls from the start.
struct Footing {
  std::vector<std::uint8_t> standing;
  std::vector<std::vector<std::uint32_t>> supports;  // the standing bodies it rests on
};
Footing footing(const std::vector<BodySource>& sources, std::optional<double> ground_height_m);

// The anchored bodies set into movable ones at the start (prepare_holds.cpp): within 5 mm of
// them, boxes overlapping across the gap, and not standing on the ground themselves.
std::vector<EmbeddedAnchor> embedded_anchors(const std::vector<BodySource>& sources,
                                             std::optional<double> ground_height_m,
                                             Checkpoint& checkpoint);

// Widens each panel's clearing distance to the contiguous coplanar surface it lies in
// (clearing_surfaces.cpp).
void share_clearing_across_surfaces(const std::vector<BodySource>& sources, Model& model,
                                    Checkpoint& checkpoint);

// Each panel's shielding from each charge, once per charge before stepping (the wave outruns
// the debris, thesis §4.2.2): fills model.shielding, or leaves it empty where the scene asks for
// none or nothing can shadow anything (prepare_shielding.cpp).
void prepare_shielding(const scene::SimulationSpec& simulation,
                       const std::vector<BodySource>& sources, Model& model, Stats& stats,
                       Checkpoint& checkpoint);

// The read-only model; moves each source's mesh into `bodies` (the result's body list). The
// shielding stage's wall-clock time goes to `shielding_wall_time_s`, s, if given. Every stage
// polls `checkpoint` (RunCancelled unwinds out of it).
Model prepare(const scene::Scene& scene, std::vector<BodySource>& sources,
              std::vector<BodyInfo>& bodies, Stats& stats, Checkpoint& checkpoint,
              double* shielding_wall_time_s = nullptr);
inline Model prepare(const scene::Scene& scene, std::vector<BodySource>& sources,
                     std::vector<BodyInfo>& bodies, Stats& stats) {
  Checkpoint never;
  return prepare(scene, sources, bodies, stats, never);
}

// The pose of a body's shape origin from the state of its centre of mass.
Pose origin_pose(const Model& model, std::size_t body, const dynamics::BodyState& state);

}  // namespace brisance::engine
