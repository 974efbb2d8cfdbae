// sim/fracture: the fracture model of thesis ch. 5.4 (DESIGN.md decision 9) — a crack tree grown
// on the bit bucket (crack_tree), and the fragments it cuts a pane into (fragments). Standalone:
// no engine or scene coupling. Units: metres, pane coordinates with the origin at the pane's
// lower-left corner, x along the width, y along the height.
#pragma once

#include <cstddef>
#include <cstdint>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace brisance::fracture {

using Vec2 = Eigen::Vector2d;

// The initial micro-crack (thesis §5.4.1 and "Improving the Algorithm").
struct InitialCrack {
  enum class Shape { segment, cross };
  Shape shape = Shape::segment;
  double length_m = 0.02;  // full length L of the segment (of each bar of the X)
  double angle_deg = 0.0;  // direction of the (first) segment, from +x counter-clockwise
  // Nucleation points, m; empty means the pane's centre. Each further point gets its own crack
  // tree with a random direction drawn from the seed.
  std::vector<Vec2> centres_m;
};

// Everything that defines a crack pattern. Defaults: the thesis's window (fig. 5.14 style).
struct FractureParams {
  double width_m = 1.0;
  double height_m = 1.0;
  // The bit bucket: cells across the width and the height (thesis §5.4.2 used 2k × 2k).
  int grid_x = 2048;
  int grid_y = 2048;
  InitialCrack initial;
  // a_c: one tip forks every time the crack front has grown this far (thesis §5.4.1);
  // see critical_crack_length_m for the physical value (thesis eq. 5.5).
  double growth_length_m = 0.02;
  // Angle between the two branches of a fork; thesis §5.2.7: "on the order of fifteen degrees".
  double branch_angle_deg = 15.0;
  // Each fork's angle is branch_angle ± angle_variance/2, uniform (thesis fig. 5.12 used 34.5°).
  // A fork never opens less than kMinBranchAngleDeg.
  double angle_variance_deg = 0.0;
  // Every wiggle_length_m of a tip's growth (0: every growth_length_m, the thesis's "edge"), with
  // this probability the tip turns by a uniform angle in ±wiggle_variance/2 (thesis fig. 5.13).
  double wiggle_probability = 0.0;
  double wiggle_variance_deg = 0.0;
  double wiggle_length_m = 0.0;
  // Stop once the crack front has grown this far beyond the initial crack (0: until every tip
  // has stopped). A short limit gives the partial, directed patterns of creep (thesis fig. 5.16).
  double growth_limit_m = 0.0;
  std::uint64_t seed = 1;

  // Which pattern fracture() makes (sim/fracture/patterns.hpp, docs/fracture.md):
  //  - crack_tree: the thesis's crack tree above, grown on the bit bucket;
  //  - radial_ring: `radial.count` radial cracks branching out from the first nucleation point
  //    (the pane's centre if none) where the plate's stress lets them (patterns.hpp,
  //    radial_star), crossed by ring cracks at `radial.ring_radii_m` — annealed glass (uses the
  //    branch angle, the wiggle fields and the seed; not the grid or the growth length);
  //  - dice: roughly equiaxed cells `dice_cell_m` across, over the whole pane — tempered glass
  //    (uses the seed only).
  enum class Kind : std::uint8_t { crack_tree, radial_ring, dice };
  Kind kind = Kind::crack_tree;
  struct Radial {
    int count = 8;                     // radial cracks out of the branching zone, >= 2
    std::vector<double> ring_radii_m;  // ring cracks around the origin, increasing
  } radial;
  double dice_cell_m = 0.0;

  static constexpr double kMinBranchAngleDeg = 5.0;
  static constexpr int kMaxRadialCracks = 2048;
  static constexpr int kMaxRings = 64;
  // Dice patterns: at most this many cells (a 1.2 x 0.9 m pane at 4 mm cells has 67 500).
  static constexpr std::size_t kMaxDice = 400000;
  static constexpr int kMaxGridCells = 8192;  // per side
};

// Why the parameters cannot be grown, naming the field and the fix, or nullopt.
std::optional<std::string> validate(const FractureParams& params);

// Named presets for the thesis's figures (same pane, grid and seed fields as `base`).
FractureParams base_preset(double branch_angle_deg = 25.0);  // figs. 5.10 (25°), 5.11 (35°)
FractureParams angle_variance_preset();                      // fig. 5.12
FractureParams wiggle_preset();                              // fig. 5.13
FractureParams combined_preset();                            // fig. 5.14
FractureParams creep_preset();                               // fig. 5.16

// Critical crack length a = (1/π)(K_c/σ)², m: the crack length at which a stress σ makes the
// stress intensity K = σ√(πa) reach the fracture toughness K_c (thesis eq. 5.5).
double critical_crack_length_m(double k_c_pa_sqrt_m, double stress_pa);

// Why a tip stopped growing.
enum class TipEnd : std::uint8_t {
  growing,   // only while growing; never in a finished tree
  forked,    // it split into two children at its end node
  hit_edge,  // it ran into another crack (its end lies on that crack)
  border,    // it reached the pane's outline
  killed,    // it was inside a closed fragment (thesis §5.4.3)
  step_limit,
};

// A straight piece of crack, m.
struct CrackSegment {
  Vec2 start = Vec2::Zero();
  Vec2 end = Vec2::Zero();
  std::uint32_t tip = 0;  // the tip that grew it
};

// A propagating crack front between two nodes of the tree: a polyline of segments.
struct CrackTip {
  std::uint32_t start_node = 0;
  std::int32_t end_node = -1;  // the fork node, or −1
  std::vector<std::uint32_t> segments;
  TipEnd end = TipEnd::growing;
  std::int32_t hit_segment = -1;  // for hit_edge: the segment it ended on
};

struct CrackNode {
  Vec2 position = Vec2::Zero();
  std::int32_t parent_tip = -1;  // −1 for the root of a tree
  std::vector<std::uint32_t> child_tips;
};

struct CrackTree {
  std::vector<CrackSegment> segments;
  std::vector<CrackTip> tips;
  std::vector<CrackNode> nodes;
  // Counts for reports and tests.
  std::size_t steps = 0;
  std::size_t forks = 0;
  std::size_t hits = 0;
  std::size_t killed = 0;
  bool stopped = false;  // the stop request ended the growth: the tree is incomplete
};

// Polled during long work (every 64 growth steps); returning true abandons it. A cancel or a
// time limit of the caller's; empty: never.
using StopRequest = std::function<bool()>;

// Grows the crack tree (thesis §5.4.1 algorithm). params must pass validate().
// Deterministic: the same params give bit-identical trees on every platform with IEEE doubles.
CrackTree grow_crack_tree(const FractureParams& params, const StopRequest& stop = {});

}  // namespace brisance::fracture
