// sim/geometry/disjoint_sets: union-find over 0..n-1 whose representative is always the smallest
// member (union by smaller root, path halving), so groupings come out deterministic.
#pragma once

#include <algorithm>
#include <cstddef>
#include <numeric>
#include <vector>

namespace brisance::geometry {

class DisjointSets {
 public:
  explicit DisjointSets(std::size_t count) : parent_(count) {
    std::iota(parent_.begin(), parent_.end(), std::size_t{0});
  }
  std::size_t find(std::size_t x) {
    while (parent_[x] != x) {
      parent_[x] = parent_[parent_[x]];
      x = parent_[x];
    }
    return x;
  }
  void unite(std::size_t x, std::size_t y) {
    x = find(x);
    y = find(y);
    if (x != y) parent_[std::max(x, y)] = std::min(x, y);
  }

 private:
  std::vector<std::size_t> parent_;
};

}  // namespace brisance::geometry
