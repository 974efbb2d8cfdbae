// sim/fracture/crack_tree: growing the crack tree on the bit bucket (thesis §§5.4.1–5.4.3).
#include "sim/fracture/crack_tree.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <deque>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>

#include "sim/geometry/polygon.hpp"
#include "sim/geometry/queries.hpp"

namespace brisance::fracture {

namespace {

constexpr std::uint32_t kEmpty = std::numeric_limits<std::uint32_t>::max();
constexpr double kDegToRad = std::numbers::pi / 180.0;

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

Vec2 unit(double angle_rad) {
  return {std::cos(angle_rad), std::sin(angle_rad)};
}

// Uniform doubles in [0, 1) from the top 53 bits of a 64-bit Mersenne Twister, whose output
// sequence the standard fixes. std::uniform_real_distribution is implementation-defined and
// would make patterns differ between standard libraries.
class Random {
 public:
  explicit Random(std::uint64_t seed) : engine_(seed) {}
  double uniform() { return static_cast<double>(engine_() >> 11) * 0x1.0p-53; }
  bool coin() { return (engine_() >> 63) != 0; }

 private:
  std::mt19937_64 engine_;
};

// The growth state. Hot per-step data lives in flat arrays indexed by segment or tip.
class Grower {
 public:
  Grower(const FractureParams& params, const StopRequest& stop)
      : p_(params),
        stop_(stop),
        random_(params.seed),
        nx_(params.grid_x),
        ny_(params.grid_y),
        scale_x_(params.grid_x / params.width_m),
        scale_y_(params.grid_y / params.height_m),
        // One step never crosses more than one column and one row of the bit bucket, so every
        // touched cell is checked (thesis §5.4.2 and fig. 5.6).
        step_m_(std::min(params.width_m / params.grid_x, params.height_m / params.grid_y)),
        wiggle_length_m_(params.wiggle_length_m > 0.0 ? params.wiggle_length_m
                                                      : params.growth_length_m),
        wiggles_(params.wiggle_probability > 0.0 && params.wiggle_variance_deg > 0.0),
        cells_(static_cast<std::size_t>(nx_) * static_cast<std::size_t>(ny_), kEmpty) {}

  CrackTree grow();

 private:
  struct TipState {
    std::uint32_t segment = 0;  // current segment
    double angle_rad = 0.0;
    double length_m = 0.0;  // path length grown so far
    double to_wiggle_m = 0.0;
    double grace_m = 0.0;  // see ignorable()
    std::uint32_t tree = 0;
    bool alive = true;
  };
  struct NodeState {
    int depth = 0;
    std::uint32_t tree = 0;
  };

  std::size_t cell_index(const Vec2& p) const {
    const int cx = std::clamp(static_cast<int>(std::floor(p.x() * scale_x_)), 0, nx_ - 1);
    const int cy = std::clamp(static_cast<int>(std::floor(p.y() * scale_y_)), 0, ny_ - 1);
    return static_cast<std::size_t>(cy) * static_cast<std::size_t>(nx_) +
           static_cast<std::size_t>(cx);
  }

  std::uint32_t add_node(const Vec2& position, std::int32_t parent_tip, std::uint32_t tree);
  std::uint32_t add_tip(std::uint32_t node, double angle_rad, double grace_m);
  std::uint32_t add_segment(std::uint32_t tip, const Vec2& start, double angle_rad);
  void advance(std::uint32_t tip);
  // Checks one cell the tip's step enters; returns false (and ends the tip) on a hit.
  bool enter_cell(std::uint32_t tip, std::size_t cell, const Vec2& from);
  bool ignorable(std::uint32_t tip, std::uint32_t owner, const Vec2& at) const;
  void hit(std::uint32_t tip, std::uint32_t owner, const Vec2& from);
  void fork(std::uint32_t tip);
  void kill_inside_cycle(std::uint32_t halt_tip, std::uint32_t hit_tip, std::uint32_t hit_segment,
                         const Vec2& hit_point);
  bool descends_from(std::uint32_t node, std::uint32_t ancestor) const;

  const FractureParams& p_;
  const StopRequest& stop_;
  Random random_;
  const int nx_;
  const int ny_;
  const double scale_x_;  // cells per metre
  const double scale_y_;
  const double step_m_;
  const double wiggle_length_m_;
  const bool wiggles_;
  std::vector<std::uint32_t> cells_;  // the bit bucket: segment id per cell, kEmpty if none

  // Per segment (hot): start, unit direction, length, owner tip, path offset of its start.
  std::vector<Vec2> seg_start_;
  std::vector<Vec2> seg_end_;
  std::vector<Vec2> seg_dir_;
  std::vector<double> seg_length_;
  std::vector<double> seg_offset_;
  std::vector<std::uint32_t> seg_tip_;

  std::vector<TipState> tip_state_;
  std::vector<NodeState> node_state_;
  CrackTree tree_;
  std::vector<std::uint32_t> live_;
  std::deque<std::uint32_t> queue_;  // the FIFO bifurcation queue (thesis §5.4.1)
};

std::uint32_t Grower::add_node(const Vec2& position, std::int32_t parent_tip, std::uint32_t tree) {
  CrackNode node;
  node.position = position;
  node.parent_tip = parent_tip;
  NodeState state;
  state.tree = tree;
  if (parent_tip >= 0) {
    const auto parent = static_cast<std::size_t>(parent_tip);
    state.depth = node_state_[tree_.tips[parent].start_node].depth + 1;
  }
  tree_.nodes.push_back(node);
  node_state_.push_back(state);
  return static_cast<std::uint32_t>(tree_.nodes.size() - 1);
}

std::uint32_t Grower::add_segment(std::uint32_t tip, const Vec2& start, double angle_rad) {
  const auto id = static_cast<std::uint32_t>(seg_start_.size());
  seg_start_.push_back(start);
  seg_end_.push_back(start);
  seg_dir_.push_back(unit(angle_rad));
  seg_length_.push_back(0.0);
  seg_offset_.push_back(tip_state_[tip].length_m);
  seg_tip_.push_back(tip);
  tree_.tips[tip].segments.push_back(id);
  tip_state_[tip].segment = id;
  tip_state_[tip].angle_rad = angle_rad;
  return id;
}

std::uint32_t Grower::add_tip(std::uint32_t node, double angle_rad, double grace_m) {
  const auto id = static_cast<std::uint32_t>(tree_.tips.size());
  CrackTip tip;
  tip.start_node = node;
  tree_.tips.push_back(tip);
  TipState state;
  state.to_wiggle_m = wiggle_length_m_;
  state.grace_m = grace_m;
  state.tree = node_state_[node].tree;
  tip_state_.push_back(state);
  tree_.nodes[node].child_tips.push_back(id);
  add_segment(id, tree_.nodes[node].position, angle_rad);
  live_.push_back(id);
  return id;
}

// Cells that a tip's own recent path or its fork's other branches share with it are no hits:
// near a fork the branches and the parent overlap on the grid for a while (two lines at angle β
// are a cell apart only after about 1/sin(β/2) cells). Rejected: a plain "same parent" rule,
// which misses the aunt and cousin branches that start within those cells when a_c is short.
bool Grower::ignorable(std::uint32_t tip, std::uint32_t owner, const Vec2& at) const {
  const TipState& state = tip_state_[tip];
  if (seg_tip_[owner] == tip) {
    if (owner == state.segment) return true;
    // An earlier segment of the same tip: ignored just behind the tip (a wiggle's corner);
    // farther back the tip has curled into itself (thesis §5.4.3), which is a hit.
    const double behind_m = state.length_m - (seg_offset_[owner] + seg_length_[owner]);
    return behind_m < 3.0 * step_m_;
  }
  const Vec2& fork = tree_.nodes[tree_.tips[tip].start_node].position;
  return (at - fork).norm() < state.grace_m &&
         geometry::distance_to_segment(fork, seg_start_[owner], seg_end_[owner]) < state.grace_m;
}

bool Grower::enter_cell(std::uint32_t tip, std::size_t cell, const Vec2& from) {
  const std::uint32_t owner = cells_[cell];
  if (owner == kEmpty) {
    cells_[cell] = tip_state_[tip].segment;
    return true;
  }
  if (ignorable(tip, owner, from)) return true;
  hit(tip, owner, from);
  return false;
}

// The halting tip ends exactly on the crack it hit, so the fragments close without gaps: at the
// crossing of the two lines if that lies within this step, else at the nearest point of the hit
// segment (reached by a last short segment).
void Grower::hit(std::uint32_t tip, std::uint32_t owner, const Vec2& from) {
  TipState& state = tip_state_[tip];
  const std::uint32_t seg = state.segment;
  const Vec2& dir = seg_dir_[seg];
  const Vec2& e_start = seg_start_[owner];
  const Vec2& e_dir = seg_dir_[owner];
  const double e_length = seg_length_[owner];
  const double denom = cross(dir, e_dir);
  double along_hit = -1.0;
  if (std::abs(denom) > 1e-9) {
    const double s = cross(e_start - from, e_dir) / denom;
    const double u = cross(e_start - from, dir) / denom;
    if (s >= 0.0 && s <= 2.0 * step_m_ && u >= 0.0 && u <= e_length) along_hit = u;
  }
  if (along_hit >= 0.0) {
    const Vec2 point = e_start + along_hit * e_dir;
    seg_end_[seg] = point;
    seg_length_[seg] = (point - seg_start_[seg]).norm();
  } else {
    const Vec2 ahead = from + step_m_ * dir;
    along_hit = std::clamp((ahead - e_start).dot(e_dir), 0.0, e_length);
    const Vec2 point = e_start + along_hit * e_dir;
    if (point != from) {
      const Vec2 last = point - from;
      const std::uint32_t extra = add_segment(tip, from, std::atan2(last.y(), last.x()));
      seg_end_[extra] = point;
      seg_length_[extra] = last.norm();
    }
  }
  state.alive = false;
  CrackTip& record = tree_.tips[tip];
  record.end = TipEnd::hit_edge;
  record.hit_segment = static_cast<std::int32_t>(owner);
  ++tree_.hits;
  const std::uint32_t hit_tip = seg_tip_[owner];
  if (hit_tip != tip && tip_state_[hit_tip].tree == state.tree)
    kill_inside_cycle(tip, hit_tip, owner, seg_end_[tree_.tips[tip].segments.back()]);
}

void Grower::advance(std::uint32_t tip) {
  TipState& state = tip_state_[tip];
  // Line wiggling (thesis fig. 5.13): at each new straight piece, maybe turn.
  if (wiggles_) {
    state.to_wiggle_m -= step_m_;
    if (state.to_wiggle_m <= 0.0) {
      state.to_wiggle_m += wiggle_length_m_;
      if (random_.uniform() < p_.wiggle_probability) {
        const double turn = (random_.uniform() - 0.5) * p_.wiggle_variance_deg * kDegToRad;
        add_segment(tip, seg_end_[state.segment], state.angle_rad + turn);
      }
    }
  }
  const std::uint32_t seg = state.segment;
  const Vec2 from = seg_end_[seg];
  Vec2 to = from + step_m_ * seg_dir_[seg];

  // Clip the step at the pane's outline; the end lands exactly on it.
  bool at_border = false;
  {
    const Vec2 delta = to - from;
    double t_exit = 1.0;
    int axis = -1;
    double limit = 0.0;
    const double bounds[2] = {p_.width_m, p_.height_m};
    for (int k = 0; k < 2; ++k) {
      if (to[k] < 0.0 || to[k] > bounds[k]) {
        const double edge = to[k] < 0.0 ? 0.0 : bounds[k];
        const double t = (edge - from[k]) / delta[k];
        if (t < t_exit) {
          t_exit = t;
          axis = k;
          limit = edge;
        }
      }
    }
    if (axis >= 0) {
      to = from + std::max(t_exit, 0.0) * delta;
      to[axis] = limit;
      to[1 - axis] = std::clamp(to[1 - axis], 0.0, bounds[1 - axis]);
      at_border = true;
    }
  }

  // The cells the step enters, in order: at most one column and one row are crossed
  // (thesis §5.4.2: one horizontally or vertically adjacent and one diagonal bucket).
  const std::size_t from_cell = cell_index(from);
  const std::size_t to_cell = cell_index(to);
  if (to_cell != from_cell) {
    const auto fx = static_cast<std::ptrdiff_t>(from_cell % static_cast<std::size_t>(nx_));
    const auto fy = static_cast<std::ptrdiff_t>(from_cell / static_cast<std::size_t>(nx_));
    const auto tx = static_cast<std::ptrdiff_t>(to_cell % static_cast<std::size_t>(nx_));
    const auto ty = static_cast<std::ptrdiff_t>(to_cell / static_cast<std::size_t>(nx_));
    if (fx != tx && fy != ty) {
      // Which grid line the step crosses first decides the diagonal's middle cell; on a tie
      // (through the corner) both neighbours are entered, as a supercover requires.
      const double gx0 = from.x() * scale_x_;
      const double gy0 = from.y() * scale_y_;
      const double gx1 = to.x() * scale_x_;
      const double gy1 = to.y() * scale_y_;
      const double line_x = static_cast<double>(std::max(fx, tx));
      const double line_y = static_cast<double>(std::max(fy, ty));
      const double cross_x = (line_x - gx0) / (gx1 - gx0);
      const double cross_y = (line_y - gy0) / (gy1 - gy0);
      const auto index = [&](std::ptrdiff_t cx, std::ptrdiff_t cy) {
        return static_cast<std::size_t>(cy * nx_ + cx);
      };
      const bool x_first = cross_x <= cross_y + 1e-9;
      const bool y_first = cross_y <= cross_x + 1e-9;
      if (x_first && !enter_cell(tip, index(tx, fy), from)) return;
      if (y_first && !enter_cell(tip, index(fx, ty), from)) return;
    }
    if (!enter_cell(tip, to_cell, from)) return;
  }
  seg_end_[seg] = to;
  const double grown = (to - from).norm();
  seg_length_[seg] += grown;
  state.length_m += grown;
  if (at_border) {
    state.alive = false;
    tree_.tips[tip].end = TipEnd::border;
  }
}

void Grower::fork(std::uint32_t tip) {
  TipState& state = tip_state_[tip];
  state.alive = false;
  const double parent_angle = state.angle_rad;
  const std::uint32_t node =
      add_node(seg_end_[state.segment], static_cast<std::int32_t>(tip), state.tree);
  tree_.tips[tip].end = TipEnd::forked;
  tree_.tips[tip].end_node = static_cast<std::int32_t>(node);
  // Branch angle with its variance (thesis fig. 5.12), never closing below the minimum.
  const double branch_deg =
      std::max(FractureParams::kMinBranchAngleDeg,
               p_.branch_angle_deg + (random_.uniform() - 0.5) * p_.angle_variance_deg);
  const double half_rad = 0.5 * branch_deg * kDegToRad;
  const double grace_m = std::clamp(1.5 / std::sin(half_rad), 2.0, 40.0) * step_m_;
  const std::uint32_t left = add_tip(node, parent_angle + half_rad, grace_m);
  const std::uint32_t right = add_tip(node, parent_angle - half_rad, grace_m);
  // Both children join the bifurcation queue in random order (thesis §5.4.1).
  if (random_.coin()) {
    queue_.push_back(left);
    queue_.push_back(right);
  } else {
    queue_.push_back(right);
    queue_.push_back(left);
  }
  ++tree_.forks;
}

bool Grower::descends_from(std::uint32_t node, std::uint32_t ancestor) const {
  while (true) {
    if (node == ancestor) return true;
    const std::int32_t parent = tree_.nodes[node].parent_tip;
    if (parent < 0) return false;
    node = tree_.tips[static_cast<std::size_t>(parent)].start_node;
  }
}

// Thesis §5.4.3: a hit within one tree closes the cycle "halt tip → hit point → hit tip's
// ancestors → common ancestor → halt tip's ancestors". A live tip inside it (of any tree) can only
// spiral inwards, so it is killed. Rejected: tracing the whole face through earlier hits; the tree
// cycle is what the thesis traces and it is O(depth) to find.
void Grower::kill_inside_cycle(std::uint32_t halt_tip, std::uint32_t hit_tip,
                               std::uint32_t hit_segment, const Vec2& hit_point) {
  std::vector<Vec2> points;  // the cycle, in walking order
  const auto& tips = tree_.tips;
  const auto& nodes = tree_.nodes;
  // Appends a tip's polyline walked from `from_node` side (forward) or backward.
  const auto walk_tip = [&](std::uint32_t t, bool forward) {
    const auto& segs = tips[t].segments;
    if (forward) {
      for (std::uint32_t s : segs)
        points.push_back(seg_end_[s]);
    } else {
      for (std::size_t k = segs.size(); k-- > 0;)
        points.push_back(seg_start_[segs[k]]);
    }
  };

  const CrackTip& hit = tips[hit_tip];
  const std::uint32_t halt_start = tips[halt_tip].start_node;
  points.push_back(hit_point);
  const auto hit_pos = static_cast<std::size_t>(
      std::find(hit.segments.begin(), hit.segments.end(), hit_segment) - hit.segments.begin());

  std::uint32_t node = 0;
  if (hit.end_node >= 0 && descends_from(halt_start, static_cast<std::uint32_t>(hit.end_node))) {
    // The hit tip is an ancestor: walk it forward to its fork, then down to the halting tip.
    for (std::size_t k = hit_pos; k < hit.segments.size(); ++k)
      points.push_back(seg_end_[hit.segments[k]]);
    node = static_cast<std::uint32_t>(hit.end_node);
  } else {
    // Walk the hit tip back to its start, then up to the common ancestor.
    for (std::size_t k = hit_pos + 1; k-- > 0;)
      points.push_back(seg_start_[hit.segments[k]]);
    node = hit.start_node;
    while (!descends_from(halt_start, node)) {
      const auto up = static_cast<std::uint32_t>(nodes[node].parent_tip);
      walk_tip(up, false);
      node = tips[up].start_node;
    }
  }
  // From `node` (the common ancestor, or the hit tip's fork) down to the halting tip's start.
  std::vector<std::uint32_t> down;  // tips from the halting tip's start up to `node`, reversed
  for (std::uint32_t n = halt_start; n != node;) {
    const auto up = static_cast<std::uint32_t>(nodes[n].parent_tip);
    down.push_back(up);
    n = tips[up].start_node;
  }
  std::reverse(down.begin(), down.end());
  for (std::uint32_t t : down)
    walk_tip(t, true);
  walk_tip(halt_tip, true);  // ends at the hit point

  // Every live tip inside the closed curve is enclosed by cracks and could only spiral inwards.
  // Decided by the curve itself (even-odd rule). Rejected: the curve's turn at each of its nodes
  // (which side of the walk a branch leaves on). Branches may cross near their fork, where they
  // ignore each other's cells, and the curve then crosses itself: the local turn called the whole
  // rest of the tree "inside" and killed every tip at once (a 1.2 x 0.8 m pane at a growth length
  // of two cells: 1 fragment for seeds 1, 6 and 7, and 1 fragment at other lengths and seeds).
  Vec2 low = points.front();
  Vec2 high = points.front();
  for (const Vec2& q : points) {
    low = low.cwiseMin(q);
    high = high.cwiseMax(q);
  }
  for (std::uint32_t t : live_) {
    TipState& state = tip_state_[t];
    if (!state.alive || t == halt_tip) continue;
    // Half a step ahead of the tip: a branch just born on the curve is judged by where it heads.
    const Vec2 probe = seg_end_[state.segment] + 0.5 * step_m_ * seg_dir_[state.segment];
    if ((probe.array() < low.array()).any() || (probe.array() > high.array()).any()) continue;
    if (!geometry::contains(points, probe)) continue;
    state.alive = false;
    tree_.tips[t].end = TipEnd::killed;
    ++tree_.killed;
  }
}

CrackTree Grower::grow() {
  const double half_length_m = 0.5 * p_.initial.length_m;
  std::vector<Vec2> centres = p_.initial.centres_m;
  if (centres.empty()) centres.emplace_back(0.5 * p_.width_m, 0.5 * p_.height_m);
  std::vector<std::uint32_t> initial_tips;
  for (std::size_t i = 0; i < centres.size(); ++i) {
    const double angle_rad =
        i == 0 ? p_.initial.angle_deg * kDegToRad : random_.uniform() * 2.0 * std::numbers::pi;
    const std::uint32_t root = add_node(centres[i], -1, static_cast<std::uint32_t>(i));
    const int arms = p_.initial.shape == InitialCrack::Shape::cross ? 4 : 2;
    for (int arm = 0; arm < arms; ++arm) {
      const double arm_angle = angle_rad + 2.0 * std::numbers::pi * arm / arms;
      initial_tips.push_back(add_tip(root, arm_angle, 3.0 * step_m_));
    }
  }
  // The initial tips join the bifurcation queue in random order (Fisher–Yates).
  for (std::size_t i = initial_tips.size(); i > 1; --i) {
    const auto j = static_cast<std::size_t>(random_.uniform() * static_cast<double>(i));
    std::swap(initial_tips[i - 1], initial_tips[std::min(j, i - 1)]);
  }
  queue_.assign(initial_tips.begin(), initial_tips.end());

  // The micro-crack grows to its length L first; then one tip forks every a_c of growth.
  double grown_m = 0.0;
  double next_fork_m = half_length_m + p_.growth_length_m;
  const std::size_t max_steps =
      8 * static_cast<std::size_t>(nx_ + ny_) + static_cast<std::size_t>(half_length_m / step_m_);
  const double stop_m = p_.growth_limit_m > 0.0 ? half_length_m + p_.growth_limit_m
                                                : std::numeric_limits<double>::infinity();
  while (!live_.empty() && tree_.steps < max_steps && grown_m < stop_m) {
    if (stop_ && tree_.steps % 64 == 0 && stop_()) {
      tree_.stopped = true;
      return std::move(tree_);
    }
    ++tree_.steps;
    grown_m += step_m_;
    for (std::size_t i = 0; i < live_.size(); ++i) {  // children added this step wait
      const std::uint32_t tip = live_[i];
      if (tip_state_[tip].alive) advance(tip);
    }
    while (grown_m >= next_fork_m) {
      next_fork_m += p_.growth_length_m;
      while (!queue_.empty() && !tip_state_[queue_.front()].alive)
        queue_.pop_front();
      if (queue_.empty()) break;
      const std::uint32_t candidate = queue_.front();
      queue_.pop_front();
      fork(candidate);
    }
    std::erase_if(live_, [&](std::uint32_t t) { return !tip_state_[t].alive; });
  }
  for (std::uint32_t t : live_) {
    tip_state_[t].alive = false;
    tree_.tips[t].end = TipEnd::step_limit;
  }

  tree_.segments.reserve(seg_start_.size());
  for (std::size_t s = 0; s < seg_start_.size(); ++s)
    tree_.segments.push_back({seg_start_[s], seg_end_[s], seg_tip_[s]});
  return std::move(tree_);
}

}  // namespace

std::optional<std::string> validate(const FractureParams& params) {
  std::ostringstream message;
  const auto positive = [](double v) { return std::isfinite(v) && v > 0.0; };
  if (!positive(params.width_m) || !positive(params.height_m)) {
    message << "width and height must be positive finite lengths in metres, got " << params.width_m
            << " x " << params.height_m;
    return message.str();
  }
  if (params.kind == FractureParams::Kind::radial_ring) {
    if (params.radial.count < 2 || params.radial.count > FractureParams::kMaxRadialCracks) {
      message << "a radial pattern needs 2 to " << FractureParams::kMaxRadialCracks
              << " radial cracks, got " << params.radial.count;
      return message.str();
    }
    if (params.radial.ring_radii_m.size() > static_cast<std::size_t>(FractureParams::kMaxRings)) {
      message << "a radial pattern has at most " << FractureParams::kMaxRings << " rings, got "
              << params.radial.ring_radii_m.size();
      return message.str();
    }
    double last = 0.0;
    for (const double r : params.radial.ring_radii_m) {
      if (!(std::isfinite(r) && r > last)) {
        message << "ring radii must be positive, finite and increasing, got " << r << " m";
        return message.str();
      }
      last = r;
    }
  } else if (params.kind == FractureParams::Kind::dice) {
    const double cells = std::ceil(params.width_m / params.dice_cell_m) *
                         std::ceil(params.height_m / params.dice_cell_m);
    if (!positive(params.dice_cell_m) ||
        !(cells <= static_cast<double>(FractureParams::kMaxDice))) {
      message << "dice cells must be a positive size giving at most " << FractureParams::kMaxDice
              << " cells on the pane, got " << params.dice_cell_m << " m";
      return message.str();
    }
  }
  if (params.grid_x < 4 || params.grid_y < 4 || params.grid_x > FractureParams::kMaxGridCells ||
      params.grid_y > FractureParams::kMaxGridCells) {
    message << "grid must have 4 to " << FractureParams::kMaxGridCells << " cells per side, got "
            << params.grid_x << " x " << params.grid_y;
    return message.str();
  }
  const double cell_m = std::max(params.width_m / params.grid_x, params.height_m / params.grid_y);
  if (!positive(params.growth_length_m) || params.growth_length_m < 0.5 * cell_m) {
    message << "growth length a_c must be at least half a grid cell (" << 0.5 * cell_m
            << " m), got " << params.growth_length_m << " m; raise it or refine the grid";
    return message.str();
  }
  // An arm of the initial crack stops at the border, so no arm needs to be longer than the
  // diagonal; a longer one would only overflow the step budget (found by tests/fuzz).
  const double diagonal_m = std::hypot(params.width_m, params.height_m);
  if (!std::isfinite(params.initial.length_m) || params.initial.length_m < 0.0 ||
      params.initial.length_m > 2.0 * diagonal_m) {
    message << "initial crack length must be from 0 to twice the pane's diagonal ("
            << 2.0 * diagonal_m << " m), got " << params.initial.length_m;
    return message.str();
  }
  if (!std::isfinite(params.initial.angle_deg)) return "initial crack angle must be finite";
  for (const Vec2& c : params.initial.centres_m) {
    if (!(c.x() > 0.0 && c.x() < params.width_m && c.y() > 0.0 && c.y() < params.height_m)) {
      message << "nucleation point (" << c.x() << ", " << c.y()
              << ") m must lie strictly inside the pane";
      return message.str();
    }
  }
  if (!(params.branch_angle_deg >= FractureParams::kMinBranchAngleDeg &&
        params.branch_angle_deg <= 170.0)) {
    message << "branch angle must be between " << FractureParams::kMinBranchAngleDeg
            << " and 170 degrees, got " << params.branch_angle_deg;
    return message.str();
  }
  if (!(params.angle_variance_deg >= 0.0 && params.angle_variance_deg <= 180.0)) {
    message << "angle variance must be between 0 and 180 degrees, got "
            << params.angle_variance_deg;
    return message.str();
  }
  if (!(params.wiggle_probability >= 0.0 && params.wiggle_probability <= 1.0)) {
    message << "wiggle probability must be between 0 and 1, got " << params.wiggle_probability;
    return message.str();
  }
  if (!(params.wiggle_variance_deg >= 0.0 && params.wiggle_variance_deg <= 90.0)) {
    message << "wiggle variance must be between 0 and 90 degrees (a turn of at most 45), got "
            << params.wiggle_variance_deg;
    return message.str();
  }
  if (!(params.wiggle_length_m >= 0.0) || !std::isfinite(params.wiggle_length_m) ||
      (params.wiggle_length_m > 0.0 && params.wiggle_length_m < 0.5 * cell_m)) {
    message << "wiggle length must be 0 (use a_c) or at least half a grid cell, got "
            << params.wiggle_length_m;
    return message.str();
  }
  if (!(params.growth_limit_m >= 0.0) || !std::isfinite(params.growth_limit_m)) {
    message << "growth limit must be 0 (none) or a positive length in m, got "
            << params.growth_limit_m;
    return message.str();
  }
  return std::nullopt;
}

FractureParams base_preset(double branch_angle_deg) {
  FractureParams params;
  params.branch_angle_deg = branch_angle_deg;
  params.growth_length_m = 0.02;
  return params;
}

FractureParams angle_variance_preset() {
  FractureParams params = base_preset(25.0);
  params.angle_variance_deg = 34.5;  // thesis fig. 5.12
  return params;
}

FractureParams wiggle_preset() {
  FractureParams params = base_preset(25.0);
  params.wiggle_probability = 0.3;
  params.wiggle_variance_deg = 30.0;
  params.wiggle_length_m = 0.01;
  return params;
}

FractureParams combined_preset() {
  FractureParams params = wiggle_preset();
  params.angle_variance_deg = 34.5;
  return params;
}

FractureParams creep_preset() {
  // Thesis fig. 5.16: a much longer initial crack, 15° forks and both stochastic variations.
  FractureParams params = combined_preset();
  params.branch_angle_deg = 15.0;
  params.angle_variance_deg = 15.0;
  params.initial.length_m = 0.4;
  params.growth_length_m = 0.05;
  params.growth_limit_m = 0.3;
  return params;
}

double critical_crack_length_m(double k_c_pa_sqrt_m, double stress_pa) {
  assert(k_c_pa_sqrt_m > 0.0 && stress_pa > 0.0);
  const double ratio = k_c_pa_sqrt_m / stress_pa;
  return ratio * ratio / std::numbers::pi;  // thesis eq. 5.5 solved for a
}

CrackTree grow_crack_tree(const FractureParams& params, const StopRequest& stop) {
  assert(!validate(params));
  Grower grower(params, stop);
  return grower.grow();
}

}  // namespace brisance::fracture
