// sim/engine/prepare_holds: the prepare stage behind friction holds (thesis §3.6) — the weight
// each body presses down with, its own plus its share of the bodies resting on it.
#include <algorithm>
#include <numeric>
#include <utility>

#include "sim/engine/model.hpp"

namespace brisance::engine {

// The normal force each body presses down with at the start: its own weight plus the share of
// every body resting on it (thesis §3.6: "bricks high on the wall experience less friction ...
// lower bricks have more resistance"). A body rests on another if its bottom lies within 5 mm of
// the other's top and their footprints overlap; its load is split between its supports in
// proportion to the overlap areas. Loads are static: a body keeps its hold when the bodies above
// it are blown off.
namespace {

constexpr double kContactGap_m = 5e-3;

// The world boxes of the sources and their indices by the height of their top, to find the
// supports of each bottom quickly.
struct Stack {
  std::vector<Box> boxes;
  std::vector<std::size_t> by_top;
};

Stack stack_of(const std::vector<BodySource>& sources) {
  Stack stack;
  const std::size_t n = sources.size();
  stack.boxes.resize(n);
  for (std::size_t i = 0; i < n; ++i)
    stack.boxes[i] = world_box(sources[i]);
  stack.by_top.resize(n);
  std::iota(stack.by_top.begin(), stack.by_top.end(), std::size_t{0});
  std::sort(stack.by_top.begin(), stack.by_top.end(), [&](std::size_t a, std::size_t b) {
    return stack.boxes[a].max.y() < stack.boxes[b].max.y();
  });
  return stack;
}

// The bodies `body` rests on (its bottom within 5 mm of their top, footprints overlapping),
// with the overlap areas, m^2.
void supports_of(const Stack& stack, std::size_t body,
                 std::vector<std::pair<std::size_t, double>>& supports) {
  const std::vector<Box>& boxes = stack.boxes;
  const Box& a = boxes[body];
  auto first = std::lower_bound(stack.by_top.begin(), stack.by_top.end(), a.min.y() - kContactGap_m,
                                [&](std::size_t j, double y) { return boxes[j].max.y() < y; });
  supports.clear();
  for (auto it = first; it != stack.by_top.end() && boxes[*it].max.y() <= a.min.y() + kContactGap_m;
       ++it) {
    if (*it == body) continue;
    const Box& b = boxes[*it];
    const double dx = std::min(a.max.x(), b.max.x()) - std::max(a.min.x(), b.min.x());
    const double dz = std::min(a.max.z(), b.max.z()) - std::max(a.min.z(), b.min.z());
    if (dx <= 0.0 || dz <= 0.0) continue;
    supports.emplace_back(*it, dx * dz);
  }
}

}  // namespace

std::vector<double> supported_weights(const std::vector<BodySource>& sources, double gravity) {
  const std::size_t n = sources.size();
  const Stack stack = stack_of(sources);
  // Highest bottoms first, so a body's load is complete before it is passed down.
  std::vector<std::size_t> by_bottom = stack.by_top;
  std::sort(by_bottom.begin(), by_bottom.end(), [&](std::size_t a, std::size_t b) {
    return stack.boxes[a].min.y() > stack.boxes[b].min.y();
  });
  std::vector<double> weight(n);
  for (std::size_t i = 0; i < n; ++i)
    weight[i] = sources[i].mass_kg * gravity;
  std::vector<std::pair<std::size_t, double>> supports;
  for (std::size_t body : by_bottom) {
    supports_of(stack, body, supports);
    double total = 0.0;
    for (const auto& [support, overlap] : supports)
      total += overlap;
    for (const auto& [support, overlap] : supports)
      weight[support] += weight[body] * overlap / total;
  }
  return weight;
}

Footing footing(const std::vector<BodySource>& sources, std::optional<double> ground_height_m) {
  const std::size_t n = sources.size();
  const Stack stack = stack_of(sources);
  // Lowest bottoms first: a body's supports (whose tops meet its bottom) are decided before it.
  std::vector<std::size_t> by_bottom = stack.by_top;
  std::sort(by_bottom.begin(), by_bottom.end(), [&](std::size_t a, std::size_t b) {
    return stack.boxes[a].min.y() < stack.boxes[b].min.y();
  });
  Footing result;
  result.standing.assign(n, 0);
  result.supports.assign(n, {});
  std::vector<std::pair<std::size_t, double>> supports;
  for (std::size_t body : by_bottom) {
    const BodySource& source = sources[body];
    const bool on_ground =
        ground_height_m && stack.boxes[body].min.y() <= *ground_height_m + kContactGap_m;
    bool standing = on_ground || source.anchored || source.breakaway_hold_n;
    supports_of(stack, body, supports);
    for (const auto& [support, overlap] : supports) {
      if (!result.standing[support]) continue;
      result.supports[body].push_back(static_cast<std::uint32_t>(support));
      standing = true;
    }
    result.standing[body] = standing ? 1 : 0;
  }
  return result;
}

std::vector<EmbeddedAnchor> embedded_anchors(const std::vector<BodySource>& sources,
                                             std::optional<double> ground_height_m,
                                             Checkpoint& checkpoint) {
  std::vector<EmbeddedAnchor> anchors;
  std::vector<std::size_t> anchored;
  for (std::size_t b = 0; b < sources.size(); ++b)
    if (sources[b].anchored) anchored.push_back(b);
  if (anchored.empty()) return anchors;
  std::vector<Box> boxes(sources.size());
  for (std::size_t b = 0; b < sources.size(); ++b)
    boxes[b] = world_box(sources[b]);
  for (std::size_t a : anchored) {
    checkpoint.tick(16);  // each anchor looks at every body
    const Box& box = boxes[a];
    // Standing on the ground, it holds on to the ground whatever happens around it.
    if (ground_height_m && box.min.y() <= *ground_height_m + kContactGap_m) continue;
    EmbeddedAnchor anchor{static_cast<std::uint32_t>(a), {}};
    for (std::size_t b = 0; b < sources.size(); ++b) {
      if (sources[b].anchored || sources[b].fragment) continue;
      const Box& other = boxes[b];
      // Touching: the boxes, each grown by the 5 mm gap, overlap on every axis.
      if (((box.min.array() - kContactGap_m) < other.max.array()).all() &&
          ((other.min.array() - kContactGap_m) < box.max.array()).all())
        anchor.neighbours.push_back(static_cast<std::uint32_t>(b));
    }
    if (!anchor.neighbours.empty()) anchors.push_back(std::move(anchor));
  }
  return anchors;
}

}  // namespace brisance::engine
