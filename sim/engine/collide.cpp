// sim/engine/collide: the step's phase of contacts between bodies (issue 13), after
// integrate_awake — place the shapes, sweep and prune, narrowphase, one sequential-impulse solve
// of the body contacts and the ground contacts of the bodies in them, then holds and sleeping:
//   place          world boxes (static bodies only when they have moved); a body's convex pieces
//                  are placed in the world frame only when one of its pairs needs them
//   broadphase     sort and sweep, along the axis of widest spread, on world boxes grown by each
//                  body's motion in the step; the order is kept from step to step, so the
//                  insertion sort is near linear
//   narrowphase    separating axes between convex pieces (dynamics/convex.hpp), kept from step
//                  to step while a pair's relative pose barely changes (PairCache)
//   solve          dynamics/body_contact.hpp, with static partners (ground, anchored, held,
//                  asleep) of zero inverse mass
//   holds          a held body pushed harder than its hold, or whose supports have all gone,
//                  is released
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <numeric>
#include <span>

#include "sim/engine/run.hpp"
#include "sim/engine/sleeping.hpp"

namespace brisance::engine {

namespace {

using dynamics::Mat3;

constexpr double kContactMargin_m = 2e-3;  // speculative distance added to each body's motion
// Boxes the sweep passes over are apart by more than this, m: far more than the rounding of
// coordinates up to 10^6 m, far less than any margin.
constexpr double kSweptSlack_m = 1e-6;
constexpr std::uint64_t kGroundId = 0xFFFFFF;
// A pair's narrowphase is found with this multiple of its margin and kept while the pair's
// relative motion stays within the difference and within kCacheMove_m (PairCache). Chosen on
// the Stability and Contacts tests: 1.5 and 1 mm, or 2 and 2 mm, let the ten-brick towers
// drift (their kept points are the corners of a face overlap, which do not move with either
// brick); 1.25 and 0.1 mm pass all, and skip the narrowphase of 56 % of the pairs on the
// brick wall (65 % on the 16 walls).
constexpr double kCacheMargin = 1.25;
constexpr double kCacheMove_m = 1e-4;
// A joined pair's shapes are tested for overlap again once it has moved this far relative to
// where they last overlapped (part_joined_pairs): a tenth of a 6 mm pane's thickness.
constexpr double kJoinedRetest_m = 6e-4;
// Two fragments part once their shapes are kJoinedGap_m apart (the contact margin: as soon as
// they part, the neighbours they were are not within it; with no gap, 579 fragments of a pane
// broken by the static model made twice the contact points); a fragment and its frame, which
// start touching but not overlapping, once they overlap by no more than kJoinedOverlap_m.
constexpr double kJoinedGap_m = 2e-3;
constexpr double kJoinedOverlap_m = 1e-4;

// A finite double's bits, reordered so that unsigned comparison orders as the doubles do (-0
// and +0 alike), for sorting on integers.
std::uint64_t ordered_bits(double x) {
  const auto bits = std::bit_cast<std::uint64_t>(x + 0.0);  // (+ 0.0: -0 becomes +0)
  return (bits >> 63) != 0 ? ~bits : bits | (std::uint64_t{1} << 63);
}

std::uint64_t contact_key(std::uint64_t a, std::uint64_t b, std::uint32_t feature) {
  return (a << 40) | (b << 16) | (feature & 0xFFFFu);
}

// At most four contacts per pair of bodies (pieces of fragments give many, mostly in one
// plane): the extremes along two directions across the deepest contact's normal (skewed from
// its plane's axes, so a rectangle's four corners are four distinct extremes).
void reduce_pair_contacts(std::vector<dynamics::PairContact>& contacts,
                          std::vector<std::uint32_t>& held, std::size_t first) {
  const std::size_t count = contacts.size() - first;
  if (count <= 4) return;
  std::size_t deepest = first;
  for (std::size_t i = first; i < contacts.size(); ++i)
    if (contacts[i].depth_m > contacts[deepest].depth_m) deepest = i;
  const Vec3 normal = contacts[deepest].normal;
  const Vec3 x = std::abs(normal.x()) < 0.57 ? Vec3(Vec3::UnitX().cross(normal).normalized())
                                             : Vec3(Vec3::UnitY().cross(normal).normalized());
  const Vec3 y = normal.cross(x);
  const Vec3 u = x + 0.37 * y, v = y - 0.37 * x;
  std::array<std::size_t, 4> keep = {first, first, first, first};
  for (std::size_t i = first; i < contacts.size(); ++i) {
    const Vec3& p = contacts[i].point;
    if (p.dot(u) < contacts[keep[0]].point.dot(u)) keep[0] = i;
    if (p.dot(u) > contacts[keep[1]].point.dot(u)) keep[1] = i;
    if (p.dot(v) < contacts[keep[2]].point.dot(v)) keep[2] = i;
    if (p.dot(v) > contacts[keep[3]].point.dot(v)) keep[3] = i;
  }
  std::sort(keep.begin(), keep.end());
  std::size_t out = first;
  for (std::size_t k = 0; k < 4; ++k) {
    if (k > 0 && keep[k] == keep[k - 1]) continue;
    contacts[out] = contacts[keep[k]];
    held[out] = held[keep[k]];
    ++out;
  }
  contacts.resize(out);
  held.resize(out);
}

}  // namespace

void Run::init_collisions() {
  if (model_.collisions == Collisions::off) return;
  const std::size_t n = model_.bodies.size();
  state_.shapes.reserve(n);
  for (std::size_t b = 0; b < n; ++b)
    state_.shapes.push_back(
        dynamics::collision_shape(result_.bodies[b].mesh, model_.centre_of_mass[b]));
  state_.placed.resize(n);
  state_.placed_state.resize(n);
  state_.placed_valid.assign(n, 0);
  state_.box_state.resize(n);
  state_.box_valid.assign(n, 0);
  state_.shape_box_centre.assign(n, Vec3::Zero());
  state_.shape_box_half.assign(n, Vec3::Zero());
  for (std::size_t b = 0; b < n; ++b) {
    if (state_.shapes[b].pieces.empty()) continue;
    Vec3 low = Vec3::Constant(INFINITY), high = Vec3::Constant(-INFINITY);
    for (const dynamics::ConvexPiece& piece : state_.shapes[b].pieces)
      dynamics::grow_box(piece, Vec3::Zero(), Mat3::Identity(), low, high);
    state_.shape_box_centre[b] = 0.5 * (low + high);
    state_.shape_box_half[b] = 0.5 * (high - low);
  }
  state_.box_min.assign(n, Vec3::Zero());
  state_.box_max.assign(n, Vec3::Zero());
  state_.sweep_order.resize(n);
  std::iota(state_.sweep_order.begin(), state_.sweep_order.end(), 0u);
  state_.touching_body.assign(n, 0);
  state_.touching_ground.assign(n, 0);
  state_.ground_with_bodies.assign(n, 0);
  // A pane's pieces start in touch: each fragment with its neighbours along the cracks (the
  // hulls of concave outlines even overlap there) and the fragments at its edge with the frame.
  // Every pair of a fragment and another fragment (`on`; `auto` never pairs two fragments) or
  // an anchored body whose boxes meet at the start (joined_pairs) is left out until the two
  // have once been apart; their contacts would otherwise push the pieces out of each other
  // with the hulls' overlap (docs/simulator.md: with `on`, window.json's 1 880 fragments did
  // not finish 0.3 s in ten minutes).
  std::vector<Vec3> low(n), high(n);
  for (std::size_t b = 0; b < n; ++b) {
    const Mat3 r = state_.bodies[b].orientation.toRotationMatrix();
    low[b] = high[b] = state_.bodies[b].position;
    for (const Vec3& p : model_.bodies[b].hull_points) {
      const Vec3 w = state_.bodies[b].position + r * p;
      low[b] = low[b].cwiseMin(w);
      high[b] = high[b].cwiseMax(w);
    }
  }
  std::vector<std::uint32_t> order(n);
  std::iota(order.begin(), order.end(), 0u);
  std::sort(order.begin(), order.end(), [&](std::uint32_t a, std::uint32_t b) {
    return low[a].x() != low[b].x() ? low[a].x() < low[b].x() : a < b;
  });
  for (std::size_t i = 0; i < n; ++i) {
    const std::uint32_t a = order[i];
    for (std::size_t k = i + 1; k < n && low[order[k]].x() <= high[a].x() + kContactMargin_m; ++k) {
      const std::uint32_t b = order[k];
      const bool pane_pair =
          (model_.fragment[a] && state_.motion[b] == Motion::anchored) ||
          (model_.fragment[b] && state_.motion[a] == Motion::anchored) ||
          (model_.fragment[a] && model_.fragment[b] && model_.collisions == Collisions::on);
      if (!pane_pair) continue;
      if ((low[a].array() > high[b].array() + kContactMargin_m).any() ||
          (low[b].array() > high[a].array() + kContactMargin_m).any())
        continue;
      const std::uint32_t first = std::min(a, b), second = std::max(a, b);
      const dynamics::BodyState& sa = state_.bodies[first];
      const dynamics::BodyState& sb = state_.bodies[second];
      state_.joined_pairs.push_back(JoinedPair{
          contact_key(first, second, 0), sa.orientation.conjugate() * (sb.position - sa.position),
          sa.orientation.conjugate() * sb.orientation});
    }
  }
  std::sort(state_.joined_pairs.begin(), state_.joined_pairs.end(),
            [](const JoinedPair& x, const JoinedPair& y) { return x.key < y.key; });
}

// Places body b's convex pieces in the world where it is now, unless they already are.
void Run::place_body(std::uint32_t b) {
  const dynamics::BodyState& s = state_.bodies[b];
  if (state_.placed_valid[b] && s.position == state_.placed_state[b].position &&
      s.orientation.coeffs() == state_.placed_state[b].orientation.coeffs())
    return;
  const Mat3 r = s.orientation.toRotationMatrix();
  const auto& pieces = state_.shapes[b].pieces;
  auto& placed = state_.placed[b];
  placed.resize(pieces.size());
  for (std::size_t p = 0; p < pieces.size(); ++p)
    dynamics::place(pieces[p], s.position, r, placed[p]);
  state_.placed_state[b] = s;
  state_.placed_valid[b] = 1;
}

// A joined pair (init_collisions) is parted once the two are apart: their boxes, grown
// by both bodies' margins, no longer meet (the broadphase would not form the pair), or their
// collision shapes no longer overlap (separating axes). From then on they
// collide like any other pair: fragments that meet again, piled on the ground. (Two fragments'
// shapes must be kJoinedGap_m apart; a fragment's and its frame's may still touch.) Until then
// their shapes overlap where the pane broke (the hulls of concave outlines), and contacts
// would push them out of each other. The shapes are tested again only once the pair has moved
// by kJoinedRetest_m relative to where they last overlapped (pieces flying side by side are
// not tested every step). Held pieces do not move: a pair with neither body awake stays as it
// is.
void Run::part_joined_pairs() {
  auto& joined = state_.joined_pairs;
  const auto& margin = state_.margin;
  std::size_t out = 0;
  for (JoinedPair& pair : joined) {
    const auto a = static_cast<std::uint32_t>(pair.key >> 40);
    const auto b = static_cast<std::uint32_t>((pair.key >> 16) & 0xFFFFFFu);
    if (state_.motion[a] != Motion::awake && state_.motion[b] != Motion::awake) {
      joined[out++] = pair;
      continue;
    }
    if (boxes_apart(a, b, margin[a] + margin[b])) continue;
    const dynamics::BodyState& sa = state_.bodies[a];
    const dynamics::BodyState& sb = state_.bodies[b];
    const Vec3 relative_position = sa.orientation.conjugate() * (sb.position - sa.position);
    const dynamics::Quat relative_turn = sa.orientation.conjugate() * sb.orientation;
    const double half_turn = (pair.relative_turn.conjugate() * relative_turn).vec().norm();
    const double moved =
        (relative_position - pair.relative_position).norm() +
        2.0 * std::asin(std::min(half_turn, 1.0)) * model_.bodies[b].bounding_radius_m;
    // (Not while either is still being launched: the launch, the pane's velocity shape, is the
    // pane's own; the frame and the neighbours act on it only once its blast load has ended.)
    auto launching = [&](std::uint32_t x) {
      return state_.release_time_s[x] >= 0.0 && state_.launch_speed_m_s[x] < 0.0;
    };
    if (moved > kJoinedRetest_m && !launching(a) && !launching(b)) {
      place_body(a);
      place_body(b);
      const double gap =
          model_.fragment[a] && model_.fragment[b] ? kJoinedGap_m : -kJoinedOverlap_m;
      bool apart = true;
      for (const auto& pa : state_.placed[a])
        for (const auto& pb : state_.placed[b])
          apart = apart && dynamics::separated(pa, pb, gap);
      if (apart) continue;
      pair.relative_position = relative_position;
      pair.relative_turn = relative_turn;
    }
    joined[out++] = pair;
  }
  joined.resize(out);
}

bool Run::in_flight(std::uint32_t b) const {
  return state_.motion[b] == Motion::awake && !state_.touching_ground[b];
}

bool Run::boxes_apart(std::uint32_t a, std::uint32_t b, double gap) const {
  return (state_.box_min[a].array() > state_.box_max[b].array() + gap).any() ||
         (state_.box_min[b].array() > state_.box_max[a].array() + gap).any();
}

void Run::form_pair(std::uint32_t a, std::uint32_t b, bool a_flies, double dt,
                    std::uint64_t& culled) {
  if (boxes_apart(a, b, state_.margin[a] + state_.margin[b])) return;
  if (a_flies && (model_.fragment[a] || model_.fragment[b]) && in_flight(b) &&
      boxes_apart(a, b, relative_margin(a, b, dt))) {
    ++culled;
    return;
  }
  state_.pairs.emplace_back(std::min(a, b), std::max(a, b));
}

double Run::relative_margin(std::uint32_t a, std::uint32_t b, double dt) const {
  const Vec3 relative = (state_.bodies[b].velocity - state_.bodies[a].velocity) * dt;
  return kContactMargin_m + relative.norm() + state_.spin_margin[a] + state_.spin_margin[b];
}

// `on`: the fragments in flight (state_.sweep_fragments) against each other. A pane's pieces fly
// as a flock, thousands side by side, each box grown by its own speed (8 cm at 8 m/s) meeting
// dozens of neighbours' that the sweep in collide then culled by their relative motion: 37 000
// pairs a step on window.json, 94 % of them culled, and the sweep a quarter of the run. Here
// each box is grown instead by its motion relative to the flock's mean velocity: two bodies'
// relative motion is at most the sum of theirs to the mean, so the sweep meets every pair the
// relative margin keeps, and form_pair's tests then keep the same pairs.
void Run::sweep_flying_fragments(double dt, std::uint64_t& culled) {
  const auto& flying = state_.sweep_fragments;
  Vec3 mean = Vec3::Zero();
  for (const std::uint32_t b : flying)
    mean += state_.bodies[b].velocity;
  mean /= static_cast<double>(flying.size());
  const int axis = state_.sweep_axis;
  auto& flock_margin = state_.flying_margin;
  flock_margin.resize(state_.bodies.size());
  auto& order = state_.sweep_flying;
  order.clear();
  for (const std::uint32_t b : flying) {
    // Half the fixed margin each, and a nanometre against rounding in the sum.
    flock_margin[b] = 0.5 * kContactMargin_m + 1e-9 +
                      (state_.bodies[b].velocity - mean).norm() * dt + state_.spin_margin[b];
    order.emplace_back(state_.box_min[b][axis] - flock_margin[b], b);
  }
  std::sort(order.begin(), order.end());
  for (std::size_t i = 0; i < order.size(); ++i) {
    const std::uint32_t a = order[i].second;
    const double high = state_.box_max[a][axis] + flock_margin[a];
    for (std::size_t k = i + 1; k < order.size() && order[k].first <= high; ++k)
      form_pair(a, order[k].second, true, dt, culled);
  }
}

void Run::collide(double dt) {
  if (model_.collisions == Collisions::off) return;
  const std::size_t n = model_.bodies.size();
  if (n < 2) return;
  std::fill(state_.touching_body.begin(), state_.touching_body.end(), 0);
  state_.next_touching_pairs.clear();

  // Boxes: for awake bodies every step, for the others when they have moved since. The pieces
  // themselves are placed only for the pairs that reach the narrowphase (place_body): most
  // bodies in flight meet nothing, and placing every fragment's hull each step was an eighth
  // of window.json's run with `auto`.
  std::vector<double>& margin = state_.margin;
  margin.assign(n, kContactMargin_m);
  std::vector<double>& spin_margin = state_.spin_margin;
  spin_margin.assign(n, 0.0);
  bool any_awake = false;
  for (std::uint32_t b = 0; b < n; ++b) {
    const dynamics::BodyState& s = state_.bodies[b];
    const bool awake = state_.motion[b] == Motion::awake;
    any_awake = any_awake || awake;
    if (awake) {
      const double spin = dynamics::angular_velocity(model_.bodies[b], s).norm() *
                          model_.bodies[b].bounding_radius_m;
      margin[b] += (s.velocity.norm() + spin) * dt;
      spin_margin[b] = spin * dt;
    }
    if (!awake && state_.box_valid[b] && s.position == state_.box_state[b].position &&
        s.orientation.coeffs() == state_.box_state[b].orientation.coeffs())
      continue;
    const Mat3 r = s.orientation.toRotationMatrix();
    if (model_.fragment[b]) {
      // A fragment's box is its own frame's box turned into the world (an oriented box's
      // world box): it holds the hull's box and costs nine products, not a turn of each of its
      // hull's up to 64 vertices (a tenth of window.json's run with `auto`).
      const Vec3 centre = s.position + r * state_.shape_box_centre[b];
      const Vec3 half = r.cwiseAbs() * state_.shape_box_half[b];
      state_.box_min[b] = centre - half;
      state_.box_max[b] = centre + half;
    } else {
      Vec3 low = Vec3::Constant(INFINITY), high = Vec3::Constant(-INFINITY);
      for (const dynamics::ConvexPiece& piece : state_.shapes[b].pieces)
        dynamics::grow_box(piece, s.position, r, low, high);
      state_.box_min[b] = low;
      state_.box_max[b] = high;
    }
    state_.box_state[b] = s;
    state_.box_valid[b] = 1;
  }
  if (!any_awake) return;
  if (!state_.joined_pairs.empty()) part_joined_pairs();

  // Broadphase: sort and sweep along the axis over which the boxes' centres spread most (a
  // pane's fragments start side by side across it, a wall's bricks along it). The order is
  // last step's, mended by insertion sort, unless the axis changed.
  {
    Vec3 sum = Vec3::Zero(), sum_squares = Vec3::Zero();
    double count = 0.0;
    for (std::uint32_t b = 0; b < n; ++b) {
      if (state_.shapes[b].pieces.empty()) continue;
      const Vec3 centre = 0.5 * (state_.box_min[b] + state_.box_max[b]);
      sum += centre;
      sum_squares += centre.cwiseProduct(centre);
      count += 1.0;
    }
    const Vec3 spread = sum_squares - sum.cwiseProduct(sum) / std::max(count, 1.0);
    int widest = 0;
    spread.maxCoeff(&widest);
    // Switch only to an axis clearly wider (twice the spread), not back and forth.
    if (widest != state_.sweep_axis && spread[widest] > 2.0 * spread[state_.sweep_axis]) {
      state_.sweep_axis = widest;
      const int axis = widest;
      std::sort(state_.sweep_order.begin(), state_.sweep_order.end(),
                [&](std::uint32_t a, std::uint32_t b) {
                  const double la = state_.box_min[a][axis] - margin[a];
                  const double lb = state_.box_min[b][axis] - margin[b];
                  return la != lb ? la < lb : a < b;
                });
    }
  }
  const int axis = state_.sweep_axis;
  auto& order = state_.sweep_order;
  auto low_of = [&](std::uint32_t b) { return state_.box_min[b][axis] - margin[b]; };
  for (std::size_t i = 1; i < order.size(); ++i) {
    const std::uint32_t body = order[i];
    const double key = low_of(body);
    std::size_t j = i;
    while (j > 0 &&
           (low_of(order[j - 1]) > key || (low_of(order[j - 1]) == key && order[j - 1] > body))) {
      order[j] = order[j - 1];
      --j;
    }
    order[j] = body;
  }
  // A fragment and a body both in flight: their margin is their motion relative to each other
  // in the step (plus kContactMargin_m), not each one's own, and the pair is left out here if
  // their boxes are farther apart than that: however fast both fly, they cannot meet in the
  // step (fragments of one pane flying side by side, whose own margins, grown by their speeds,
  // overlap: 535 contact points on window.json against 19, and with 579 fragments a
  // speculative contact between most neighbours in every step). Not on the ground, whose
  // contacts change the velocities within the solve. Also for a body that touched another in
  // the last step: leaving those out (the rule's first form) made each fragment that touched
  // another take in every neighbour within its own margin, 8 cm at 11 m/s, and on the
  // 1 880-fragment window.json with `on` 1.2 M contact points (4.26 s) instead of 241 k
  // (1.72 s). Only with a fragment: for all pairs, leaving out the inert speculative contacts
  // of bricks falling side by side changed the islands' solve enough that 5 of the 30 towers
  // of Stability.BrickTowerStandsWhateverTheDrop fell and BoxPyramidSettles failed.
  // Pairs: each body against those after it in the order whose boxes (grown by both margins)
  // meet its own. With `auto`, fragments are swept against the other bodies only, never
  // against each other: their contacts, measured on window.json (docs/simulator.md), cost ten
  // times the run without them (1 880 fragments, `on`); and a pane's thousands of pieces
  // flying side by side, each box grown by its speed, overlapped 36 000 times a step, to be
  // found and skipped one by one (2.06 s against 0.166 s without contacts).
  auto& pairs = state_.pairs;
  pairs.clear();
  auto& others = state_.sweep_others;
  auto& fragments = state_.sweep_fragments;
  others.clear();
  fragments.clear();
  // With `on`, the fragments in flight are a list of their own too, swept against each other
  // below by their motion relative to the flock.
  const bool fragments_apart = model_.collisions == Collisions::automatic;
  for (const std::uint32_t b : order) {
    if (state_.shapes[b].pieces.empty()) continue;
    const bool apart = model_.fragment[b] && (fragments_apart || in_flight(b));
    (apart ? fragments : others).push_back(b);
  }
  // Their boxes grown by their margins, alongside. The sweep passes over many bodies for each
  // pair it forms (17 on the 16 walls, where four walls share each stretch of the axis):
  // those whose grown boxes are apart across the axis, surely (by kSweptSlack_m, more than
  // the rounding of either test), are passed over here, with no call of form_pair, whose first
  // test would have left them out.
  auto swept = [&](const std::vector<std::uint32_t>& list, std::vector<SweptBox>& boxes) {
    boxes.resize(list.size());
    for (std::size_t k = 0; k < list.size(); ++k) {
      const std::uint32_t b = list[k];
      // (low[axis] is low_of(b), the sweep's own key: the same subtraction.)
      boxes[k] = SweptBox{state_.box_min[b] - Vec3::Constant(margin[b]),
                          state_.box_max[b] + Vec3::Constant(margin[b]), b,
                          state_.motion[b] == Motion::awake};
    }
  };
  swept(others, state_.swept_others);
  swept(fragments, state_.swept_fragments);
  std::uint64_t culled = 0;
  // a against the bodies of `list` from `first` on, while their boxes start within a's.
  auto sweep = [&](std::uint32_t a, const std::vector<SweptBox>& list, std::size_t first) {
    const double high = state_.box_max[a][axis] + margin[a];
    const Vec3 a_low = state_.box_min[a] - Vec3::Constant(margin[a] + kSweptSlack_m);
    const Vec3 a_high = state_.box_max[a] + Vec3::Constant(margin[a] + kSweptSlack_m);
    const bool a_awake = state_.motion[a] == Motion::awake;
    const bool a_flies = in_flight(a);
    for (std::size_t k = first; k < list.size() && list[k].low[axis] <= high; ++k) {
      const SweptBox& b = list[k];
      if (!a_awake && !b.awake) continue;
      if ((b.low.array() > a_high.array()).any() || (a_low.array() > b.high.array()).any())
        continue;
      form_pair(a, b.body, a_flies, dt, culled);
    }
  };
  // Both lists keep the order's; walking it, next_other and next_fragment are where each list
  // goes on after the body at hand.
  std::size_t next_other = 0, next_fragment = 0;
  for (const std::uint32_t a : order) {
    if (state_.shapes[a].pieces.empty()) continue;
    if (next_fragment < fragments.size() && fragments[next_fragment] == a) {
      ++next_fragment;
      sweep(a, state_.swept_others, next_other);
    } else {
      ++next_other;
      sweep(a, state_.swept_others, next_other);
      sweep(a, state_.swept_fragments, next_fragment);
    }
  }
  if (!fragments_apart && fragments.size() > 1) sweep_flying_fragments(dt, culled);
  std::sort(pairs.begin(), pairs.end());
  result_.stats.collision_pairs += pairs.size() + culled;
  result_.stats.collision_pairs_skipped += culled;

  // Narrowphase. An asleep body met by a moving one wakes up.
  // (The step's buffers live in the state, to spare their allocations; solver_index is left
  // all -1 at the end of the step.)
  std::vector<std::int32_t>& solver_index = state_.solver_index;
  solver_index.resize(n, -1);
  std::vector<dynamics::SolverBody>& solver = state_.solver;
  solver.assign(1, dynamics::SolverBody{});  // 0: every static partner
  std::vector<std::uint32_t>& solver_body = state_.solver_body;
  solver_body.assign(1, 0);
  auto dynamic_index = [&](std::uint32_t b) -> std::uint32_t {
    if (state_.motion[b] != Motion::awake) return 0;
    if (solver_index[b] < 0) {
      const dynamics::BodyModel& body = model_.bodies[b];
      const dynamics::BodyState& s = state_.bodies[b];
      solver_index[b] = static_cast<std::int32_t>(solver.size());
      // Filled in place: a local copy trips GCC 12's -Wmaybe-uninitialized at -O1 (the
      // sanitizer build) inside Eigen's assignment.
      dynamics::SolverBody& sb = solver.emplace_back();
      sb.velocity = s.velocity;
      sb.inverse_mass = body.inverse_mass;
      if (body.rotates) {
        const Mat3 r = s.orientation.toRotationMatrix();
        sb.inverse_inertia = r * body.inverse_inertia_body * r.transpose();
        sb.omega = sb.inverse_inertia * s.angular_momentum;
      }
      solver_body.push_back(b);
    }
    return static_cast<std::uint32_t>(solver_index[b]);
  };
  auto moving = [&](std::uint32_t b) {
    return state_.motion[b] == Motion::awake && state_.rest_time_s[b] == 0.0;
  };
  const double restitution = model_.ground ? model_.ground->restitution : 0.2;
  const Vec3 gravity_step = model_.world.gravity_m_s2 * dt;
  auto& contacts = state_.pair_contacts;
  auto& contact_held = state_.contact_held;  // per contact: the held partner, or n
  contacts.clear();
  contact_held.clear();
  dynamics::Manifold manifold;
  state_.next_pair_cache.clear();
  state_.next_cached_points.clear();
  std::size_t cache_cursor = 0;
  for (const auto& [a, b] : pairs) {
    for (std::uint32_t x : {a, b}) {
      const std::uint32_t other = x == a ? b : a;
      if (state_.motion[x] == Motion::asleep && moving(other)) {
        state_.motion[x] = Motion::awake;
        state_.rest_time_s[x] = 0.0;
      }
    }
    if (!state_.joined_pairs.empty() &&
        std::binary_search(
            state_.joined_pairs.begin(), state_.joined_pairs.end(),
            JoinedPair{contact_key(a, b, 0), Vec3::Zero(), dynamics::Quat()},
            [](const JoinedPair& x, const JoinedPair& y) { return x.key < y.key; })) {
      // Pieces of one pane not yet apart (part_joined_pairs).
      ++result_.stats.collision_pairs_skipped;
      continue;
    }
    if (model_.collisions == Collisions::automatic && state_.motion[a] == Motion::awake &&
        state_.motion[b] == Motion::awake) {
      // Moving apart faster than 1 cm/s and not pressed together last step: they cannot meet
      // in this step (fragments of a pane leaving along their cracks, debris flying apart).
      const Vec3 apart = state_.bodies[b].position - state_.bodies[a].position;
      const Vec3 closing = state_.bodies[b].velocity - state_.bodies[a].velocity;
      if (closing.dot(apart) > 0.01 * apart.norm() &&
          !std::binary_search(state_.touching_pairs.begin(), state_.touching_pairs.end(),
                              contact_key(a, b, 0))) {
        ++result_.stats.collision_pairs_skipped;
        continue;
      }
    }
    double pair_margin = margin[a] + margin[b];
    if ((model_.fragment[a] || model_.fragment[b]) && in_flight(a) && in_flight(b))
      pair_margin = std::min(pair_margin, relative_margin(a, b, dt));  // (culled in the sweep)
    const dynamics::BodyState& sa = state_.bodies[a];
    const dynamics::BodyState& sb = state_.bodies[b];
    const Mat3 ra = sa.orientation.toRotationMatrix();
    const Mat3 rb = sb.orientation.toRotationMatrix();
    const Vec3 relative_position = ra.transpose() * (sb.position - sa.position);
    const dynamics::Quat relative_turn = sa.orientation.conjugate() * sb.orientation;
    // The narrowphase found last step is kept while b has moved in a's frame by less than the
    // margin it was found with beyond this step's (kCacheMargin): every point now within this
    // step's margin was within that one. Its points move with the bodies (each is kept on both
    // surfaces), so their depths follow the bodies' motion; the narrowphase runs again
    // once they have moved farther, or turned.
    const std::uint64_t pair_key = contact_key(a, b, 0);
    const auto& cache = state_.pair_cache;
    while (cache_cursor < cache.size() && cache[cache_cursor].key < pair_key)
      ++cache_cursor;
    bool reuse = false;
    if (cache_cursor < cache.size() && cache[cache_cursor].key == pair_key) {
      const PairCache& kept = cache[cache_cursor];
      const double half_turn = (kept.relative_turn.conjugate() * relative_turn).vec().norm();
      const double moved =
          (relative_position - kept.relative_position).norm() +
          2.0 * std::asin(std::min(half_turn, 1.0)) * model_.bodies[b].bounding_radius_m;
      reuse = moved + pair_margin <= kept.margin_m && moved <= kCacheMove_m;
    }
    auto& points = state_.next_cached_points;
    const std::uint32_t points_first = static_cast<std::uint32_t>(points.size());
    if (reuse) {
      const PairCache& kept = cache[cache_cursor];
      points.insert(points.end(), state_.cached_points.begin() + kept.first,
                    state_.cached_points.begin() + kept.first + kept.count);
      state_.next_pair_cache.push_back(kept);
      state_.next_pair_cache.back().first = points_first;
    } else {
      const double found_margin = kCacheMargin * pair_margin;
      const dynamics::StepMotion step{(sb.velocity - sa.velocity) * dt,
                                      spin_margin[a] + spin_margin[b]};
      place_body(a);
      place_body(b);
      const auto& pa = state_.placed[a];
      const auto& pb = state_.placed[b];
      for (std::size_t i = 0; i < pa.size(); ++i)
        for (std::size_t j = 0; j < pb.size(); ++j) {
          const std::uint32_t base = static_cast<std::uint32_t>((i * pb.size() + j) << 8);
          if (!dynamics::collide(pa[i], pb[j], found_margin, base, manifold, true, pair_margin,
                                 step))
            continue;
          const Vec3 normal_a = ra.transpose() * manifold.normal;
          for (const dynamics::ContactPoint& p : manifold.points) {
            const Vec3 half = (0.5 * p.depth_m) * manifold.normal;
            points.push_back(CachedPoint{ra.transpose() * (p.point + half - sa.position),
                                         rb.transpose() * (p.point - half - sb.position), normal_a,
                                         p.feature});
          }
        }
      state_.next_pair_cache.push_back(
          PairCache{pair_key, relative_position, relative_turn, found_margin, points_first,
                    static_cast<std::uint32_t>(points.size()) - points_first});
    }
    // The contacts: the kept points where the bodies are now, those within the margin.
    const std::size_t first = contacts.size();
    bool pressed = false;
    for (std::size_t k = points_first; k < points.size(); ++k) {
      const CachedPoint& kept = points[k];
      const Vec3 on_a = sa.position + ra * kept.on_a;
      const Vec3 on_b = sb.position + rb * kept.on_b;
      const Vec3 normal = ra * kept.normal_a;
      const double depth = (on_a - on_b).dot(normal);
      if (depth < -pair_margin) continue;
      const Vec3 point = 0.5 * (on_a + on_b);
      const std::uint32_t ia = dynamic_index(a), ib = dynamic_index(b);
      dynamics::PairContact c;
      c.a = ia;
      c.b = ib;
      c.point = point;
      c.normal = normal;
      c.depth_m = depth;
      c.friction = std::sqrt(model_.friction[a] * model_.friction[b]);
      c.restitution = restitution;
      c.gravity_speed_m_s =
          gravity_step.dot(normal) * ((ib != 0 ? 1.0 : 0.0) - (ia != 0 ? 1.0 : 0.0));
      c.key = contact_key(a, b, kept.feature);
      c.arm_a = ia != 0 ? Vec3(point - sa.position) : Vec3::Zero();
      c.arm_b = ib != 0 ? Vec3(point - sb.position) : Vec3::Zero();
      contacts.push_back(c);
      const bool a_held = state_.motion[a] == Motion::held;
      const bool b_held = state_.motion[b] == Motion::held;
      contact_held.push_back(a_held ? a : b_held ? b : static_cast<std::uint32_t>(n));
      if (depth > -1e-3) state_.touching_body[a] = state_.touching_body[b] = 1;
      if (depth > 1e-4) pressed = true;
    }
    reduce_pair_contacts(contacts, contact_held, first);
    // (Pairs come in sorted order: the list stays sorted.)
    if (pressed) state_.next_touching_pairs.push_back(contact_key(a, b, 0));
  }
  std::swap(state_.pair_cache, state_.next_pair_cache);
  std::swap(state_.cached_points, state_.next_cached_points);
  // Bodies whose ground contact was left to this solve join it even if they met no body.
  for (std::uint32_t b = 0; b < n; ++b)
    if (state_.ground_with_bodies[b] && state_.motion[b] == Motion::awake) dynamic_index(b);
  if (solver.size() == 1) {
    state_.contact_impulses.clear();
  } else {
    // The ground under the bodies in contact joins the same solve (a box under another is
    // pressed into the ground by it within the step).
    if (model_.ground) {
      // Points within the body's margin of the ground take part as speculative contacts, so
      // that a body rocking on three corners is held by the fourth when it is struck.
      for (std::size_t s = 1; s < solver.size(); ++s) {
        const std::uint32_t b = solver_body[s];
        const double top = model_.ground->height_m + margin[b];
        const dynamics::BodyState& st = state_.bodies[b];
        const Mat3 r = st.orientation.toRotationMatrix();
        const auto& hull = model_.bodies[b].hull_points;
        for (std::size_t k = 0; k < hull.size(); ++k) {
          const Vec3 arm = r * hull[k];
          const double y = st.position.y() + arm.y();
          if (y > top) continue;
          dynamics::PairContact c;
          c.a = 0;
          c.b = static_cast<std::uint32_t>(s);
          c.point = st.position + arm;
          c.normal = Vec3::UnitY();
          c.depth_m = model_.ground->height_m - y;
          if (c.depth_m > -1e-4) state_.touching_ground[b] = 1;
          c.friction = model_.ground->friction;
          c.restitution = model_.ground->restitution;
          c.gravity_speed_m_s = gravity_step.y();
          c.key = contact_key(kGroundId, b, static_cast<std::uint32_t>(k));
          c.arm_a = Vec3::Zero();
          c.arm_b = arm;
          contacts.push_back(c);
          contact_held.push_back(static_cast<std::uint32_t>(n));
        }
      }
    }
    // Islands: the moving bodies joined by their contacts (static partners join nothing),
    // each solved on its own, so that one settles in the sweeps it needs rather than in those
    // of the slowest. Union-find over solver bodies, the smaller index the root.
    auto& parent = state_.island_parent;
    parent.resize(solver.size());
    std::iota(parent.begin(), parent.end(), 0u);
    auto root = [&](std::uint32_t x) {
      while (parent[x] != x)
        x = parent[x] = parent[parent[x]];
      return x;
    };
    for (const dynamics::PairContact& c : contacts) {
      if (c.a == 0 || c.b == 0) continue;
      const std::uint32_t ra = root(c.a), rb = root(c.b);
      if (ra != rb) parent[std::max(ra, rb)] = std::min(ra, rb);
    }
    // By island, then bottom up within it, so a stack's weight is passed down within a sweep:
    // counted into islands (their roots are solve bodies), then each island sorted on packed
    // keys, whose comparisons read no contact. (One sort of all the contacts was 7 % of the
    // 16 walls' run, its comparisons mostly of islands.)
    std::vector<std::uint32_t>& island = state_.contact_island;
    island.resize(contacts.size());
    auto& start = state_.island_start;
    start.assign(solver.size() + 1, 0);
    for (std::size_t i = 0; i < contacts.size(); ++i) {
      island[i] = root(contacts[i].a != 0 ? contacts[i].a : contacts[i].b);
      ++start[island[i] + 1];
    }
    std::partial_sum(start.begin(), start.end(), start.begin());
    auto& order_keys = state_.contact_order;
    order_keys.resize(contacts.size());
    for (std::size_t i = 0; i < contacts.size(); ++i)
      order_keys[start[island[i]]++] =
          ContactOrder{ordered_bits(contacts[i].point.y()), contacts[i].key,
                       static_cast<std::uint32_t>(i), island[i]};
    // (Filling moved each island's start on to its end, where the next island begins.)
    for (std::size_t s = 0, first = 0; s < solver.size(); first = start[s++])
      if (start[s] - first > 1)
        std::sort(order_keys.begin() + static_cast<std::ptrdiff_t>(first),
                  order_keys.begin() + start[s], [](const ContactOrder& x, const ContactOrder& y) {
                    return x.height != y.height ? x.height < y.height : x.key < y.key;
                  });
    auto& sorted = state_.sorted_contacts;
    auto& sorted_held = state_.sorted_held;
    sorted.clear();
    sorted_held.clear();
    for (const ContactOrder& o : order_keys) {
      sorted.push_back(contacts[o.index]);
      sorted_held.push_back(contact_held[o.index]);
    }
    result_.stats.contact_points += sorted.size();
    dynamics::PairSolveSettings settings;
    settings.dt_s = dt;
    settings.gravity_m_s2 = model_.world.gravity_m_s2.norm();
    const std::uint64_t limited_before = state_.solve_buffers.energy_limited;
    const std::uint64_t spun_before = state_.solve_buffers.spin_limited;
    const std::uint64_t sped_before = state_.solve_buffers.speed_limited;
    const std::uint64_t runaways_before = state_.solve_buffers.runaways;
    // Warm start as forces: last step's impulses in proportion to the step's length, at most
    // doubled (an impact's impulse in a tiny step is no force to scale up).
    if (state_.contact_impulses_dt_s > 0.0)
      settings.warm_start_scale = std::min(dt / state_.contact_impulses_dt_s, 2.0);
    state_.contact_impulses_dt_s = dt;
    std::vector<dynamics::SolverBody>& before = state_.solver_before;
    before = solver;
    state_.next_contact_impulses.clear();
    for (std::size_t first = 0; first < sorted.size();) {
      std::size_t last = first + 1;
      while (last < sorted.size() && order_keys[last].island == order_keys[first].island)
        ++last;
      dynamics::solve_pair_contacts(
          solver, std::span<dynamics::PairContact>(sorted.data() + first, last - first),
          state_.contact_impulses, state_.next_contact_impulses, settings, state_.solve_buffers);
      first = last;
    }
    state_.next_contact_impulses.seal();
    const dynamics::PairSolveBuffers& solved = state_.solve_buffers;
    const struct {
      std::uint64_t count;
      const char* code;
      const char* message;
    } limits[] = {
        {solved.energy_limited - limited_before, "contact_energy_limited",
         "a contact solve would have given bodies kinetic energy (a fast spinner meeting another "
         "body: its contacts are linear in the step) and was scaled back; shorten the step "
         "(lower 'tolerance') if these bodies matter"},
        {solved.spin_limited - spun_before, "contact_spin_limited",
         "contacts would have spun a body by more than a quarter turn in one step (a thin piece "
         "struck on an edge) and its spin was limited to that, as the contacts found once a step "
         "cannot follow it; shorten the step (lower 'tolerance') if these bodies matter"},
        {solved.runaways - runaways_before, "contact_solve_runaway",
         "a contact solve of pieces jammed together ran away (friction kept raising the impulses "
         "that bound it) and was done again with each contact's friction capped at what its "
         "push alone can bear; the motion of pieces in such piles is approximate"},
        {solved.speed_limited - sped_before, "contact_speed_limited",
         "contacts would have sent a body off faster than twice the fastest body they touched (a "
         "light piece squeezed in a pile) and its speed was limited to that"},
    };
    for (const auto& limit : limits)
      if (limit.count > 0) warnings_.add(limit.code, limit.message, limit.count);
    std::swap(state_.contact_impulses, state_.next_contact_impulses);
    // The step's motion redone with the solved velocities (body_contact.hpp): each body moves
    // and turns by its change of velocity over the step, then out of what penetration is left.
    for (std::size_t s = 1; s < solver.size(); ++s) {
      const std::uint32_t b = solver_body[s];
      dynamics::BodyState& st = state_.bodies[b];
      const dynamics::BodyModel& body = model_.bodies[b];
      st.velocity = solver[s].velocity;
      st.position += (solver[s].velocity - before[s].velocity) * dt + solver[s].position_shift;
      if (body.rotates) {
        // The solved spin is the body's at the end of the step, and it turns with the body:
        // kept in the body's frame through the redone turn, so the body keeps the energy the
        // solve left it. (Kept as angular momentum in the world instead, a sliver turned by a
        // fraction of a radian took that momentum about an axis of a thousandth of the inertia:
        // thousands of rad/s, and energy from nowhere.)
        const Vec3 spin_body = st.orientation.conjugate() * solver[s].omega;
        const Vec3 turn = (solver[s].omega - before[s].omega) * dt;
        const double angle = turn.norm();
        if (angle > 0.0)
          st.orientation = (dynamics::Quat(Eigen::AngleAxisd(angle, turn / angle)) * st.orientation)
                               .normalized();
        st.angular_momentum = st.orientation * (body.inertia_body * spin_body);
      }
    }
    // A held body pushed harder than its hold breaks free.
    std::vector<double>& pushed = state_.pushed;
    pushed.clear();
    for (std::size_t i = 0; i < sorted.size(); ++i) {
      const std::uint32_t held = sorted_held[i];
      if (held == n) continue;
      if (pushed.empty()) pushed.assign(n, 0.0);
      pushed[held] += sorted[i].normal_impulse;
    }
    for (std::size_t b = 0; b < pushed.size(); ++b)
      if (pushed[b] > model_.hold_force_n[b] * dt && state_.motion[b] == Motion::held)
        state_.motion[b] = Motion::awake;
  }
  for (std::size_t s = 1; s < solver_body.size(); ++s)
    solver_index[solver_body[s]] = -1;

  std::swap(state_.touching_pairs, state_.next_touching_pairs);

  // A held body whose supports have all left falls.
  for (std::uint32_t b = 0; b < n; ++b) {
    // (Fragments are held by their frame grip, whatever lies under them.)
    if (state_.motion[b] != Motion::held || model_.supports[b].empty() || model_.fragment[b])
      continue;
    const bool supported =
        std::any_of(model_.supports[b].begin(), model_.supports[b].end(), [&](std::uint32_t s) {
          return state_.motion[s] == Motion::held || state_.motion[s] == Motion::anchored;
        });
    if (!supported) state_.motion[b] = Motion::awake;
  }
}

// With contacts between bodies, whether a body falls asleep is judged after them: before, a
// body resting on another still carries the step's gravity (g dt, 0.09 m/s at the 9.5 ms
// step, above the resting speed), so it never slept and never settled.
void Run::sleep_after_contacts(double dt) {
  const bool may_sleep = model_.timing.sleep && model_.ground.has_value();
  for (std::uint32_t b : state_.stepped) {
    if (state_.motion[b] != Motion::awake) continue;
    dynamics::BodyState& state = state_.bodies[b];
    const bool touching = state_.touching_ground[b] || state_.touching_body[b];
    const double spin = dynamics::angular_velocity(model_.bodies[b], state).squaredNorm();
    if (falls_asleep(may_sleep && touching, state.velocity.norm(), spin, dt,
                     state_.rest_time_s[b])) {
      state_.motion[b] = Motion::asleep;
      state.velocity.setZero();
      state.angular_momentum.setZero();
      ++result_.stats.bodies_slept;
    }
  }
  state_.stepped.clear();
}

}  // namespace brisance::engine
