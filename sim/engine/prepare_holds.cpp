// sim/engine/prepare_holds: the prepare stage behind friction holds (thesis §3.6) — the weight
// each body presses down with, its own plus its share of the bodies resting on it.
#include <algorithm>
#include <utility>

#include "sim/engine/model.hpp"

namespace brisance::engine {

// The normal force each body presses down with at the start: its own weight plus the share of
// every body resting on it (thesis §3.6: "bricks high on the wall experience less friction ...
// lower bricks have more resistance"). A body rests on another if its bottom lies within 5 mm of
// the other's top and their footprints overlap; its load is split between its supports in
// proportion to the overlap areas. Loads are static: a body keeps its hold when the bodies above
// it are blown off.
std::vector<double> supported_weights(const std::vector<BodySource>& sources, double gravity) {
  constexpr double kContactGap_m = 5e-3;
  const std::size_t n = sources.size();
  std::vector<Box> boxes(n);
  for (std::size_t i = 0; i < n; ++i)
    boxes[i] = world_box(sources[i]);
  // Bodies by the height of their top, to find the supports of each bottom quickly.
  std::vector<std::size_t> by_top(n);
  for (std::size_t i = 0; i < n; ++i)
    by_top[i] = i;
  std::sort(by_top.begin(), by_top.end(),
            [&](std::size_t a, std::size_t b) { return boxes[a].max.y() < boxes[b].max.y(); });
  // Highest bottoms first, so a body's load is complete before it is passed down.
  std::vector<std::size_t> by_bottom = by_top;
  std::sort(by_bottom.begin(), by_bottom.end(),
            [&](std::size_t a, std::size_t b) { return boxes[a].min.y() > boxes[b].min.y(); });
  std::vector<double> weight(n);
  for (std::size_t i = 0; i < n; ++i)
    weight[i] = sources[i].mass_kg * gravity;
  std::vector<std::pair<std::size_t, double>> supports;
  for (std::size_t body : by_bottom) {
    const Box& a = boxes[body];
    auto first = std::lower_bound(by_top.begin(), by_top.end(), a.min.y() - kContactGap_m,
                                  [&](std::size_t j, double y) { return boxes[j].max.y() < y; });
    supports.clear();
    double total = 0.0;
    for (auto it = first; it != by_top.end() && boxes[*it].max.y() <= a.min.y() + kContactGap_m;
         ++it) {
      if (*it == body) continue;
      const Box& b = boxes[*it];
      const double dx = std::min(a.max.x(), b.max.x()) - std::max(a.min.x(), b.min.x());
      const double dz = std::min(a.max.z(), b.max.z()) - std::max(a.min.z(), b.min.z());
      if (dx <= 0.0 || dz <= 0.0) continue;
      supports.emplace_back(*it, dx * dz);
      total += dx * dz;
    }
    for (const auto& [support, overlap] : supports)
      weight[support] += weight[body] * overlap / total;
  }
  return weight;
}

}  // namespace brisance::engine
