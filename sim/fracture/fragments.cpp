// sim/fracture/fragments: the planar arrangement of the cracks and the outline, and its faces.
#include "sim/fracture/fragments.hpp"

#include <algorithm>
#include <cassert>
#include <cmath>
#include <cstdint>
#include <numeric>

#include "sim/fracture/patterns.hpp"
#include "sim/geometry/disjoint_sets.hpp"
#include "sim/geometry/polygon.hpp"
#include "sim/geometry/queries.hpp"

namespace brisance::fracture {

namespace {

double cross(const Vec2& a, const Vec2& b) {
  return a.x() * b.y() - a.y() * b.x();
}

struct Segment {
  Vec2 a;
  Vec2 b;
  bool border = false;
};

struct Split {
  std::uint32_t segment = 0;
  double t = 0.0;  // position along the segment, 0 at a, 1 at b
  Vec2 point;
};

// All crossings and T-junctions between segments, found through a uniform grid of buckets.
// A pair is tested in the first bucket (lowest row, then column) that both bounding boxes share.
class Arrangement {
 public:
  Arrangement(std::vector<Segment> segments, double width_m, double height_m, double eps_m)
      : segments_(std::move(segments)), eps_(eps_m) {
    const auto n = static_cast<double>(segments_.size());
    buckets_ = std::clamp(static_cast<int>(std::sqrt(n)), 1, 1024);
    bucket_w_ = width_m / buckets_;
    bucket_h_ = height_m / buckets_;
  }

  std::vector<Split> find_splits(std::size_t& crossings) {
    // Bucket ranges per segment (bounding box grown by eps), then a CSR bucket → segments table.
    const std::size_t n = segments_.size();
    std::vector<std::array<int, 4>> range(n);
    const std::size_t bucket_count =
        static_cast<std::size_t>(buckets_) * static_cast<std::size_t>(buckets_);
    std::vector<std::uint32_t> start(bucket_count + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
      const Segment& s = segments_[i];
      range[i] = {
          bucket_x(std::min(s.a.x(), s.b.x()) - eps_), bucket_y(std::min(s.a.y(), s.b.y()) - eps_),
          bucket_x(std::max(s.a.x(), s.b.x()) + eps_), bucket_y(std::max(s.a.y(), s.b.y()) + eps_)};
      for_each_bucket(range[i], [&](std::size_t b) { ++start[b + 1]; });
    }
    std::partial_sum(start.begin(), start.end(), start.begin());
    std::vector<std::uint32_t> members(start.back());
    std::vector<std::uint32_t> fill(start.begin(), start.end() - 1);
    for (std::size_t i = 0; i < n; ++i)
      for_each_bucket(range[i],
                      [&](std::size_t b) { members[fill[b]++] = static_cast<std::uint32_t>(i); });

    std::vector<Split> splits;
    for (std::size_t b = 0; b < bucket_count; ++b) {
      const int bx = static_cast<int>(b % static_cast<std::size_t>(buckets_));
      const int by = static_cast<int>(b / static_cast<std::size_t>(buckets_));
      for (std::uint32_t p = start[b]; p < start[b + 1]; ++p) {
        for (std::uint32_t q = p + 1; q < start[b + 1]; ++q) {
          const std::uint32_t i = members[p];
          const std::uint32_t j = members[q];
          const int first_x = std::max(range[i][0], range[j][0]);
          const int first_y = std::max(range[i][1], range[j][1]);
          if (first_x != bx || first_y != by) continue;  // tested in an earlier bucket
          if (range[i][2] < range[j][0] || range[j][2] < range[i][0] || range[i][3] < range[j][1] ||
              range[j][3] < range[i][1])
            continue;
          test_pair(i, j, splits, crossings);
        }
      }
    }
    return splits;
  }

  const std::vector<Segment>& segments() const { return segments_; }

 private:
  int bucket_x(double x) const {
    return std::clamp(static_cast<int>(std::floor(x / bucket_w_)), 0, buckets_ - 1);
  }
  int bucket_y(double y) const {
    return std::clamp(static_cast<int>(std::floor(y / bucket_h_)), 0, buckets_ - 1);
  }
  template <class F>
  void for_each_bucket(const std::array<int, 4>& r, F&& f) const {
    for (int y = r[1]; y <= r[3]; ++y)
      for (int x = r[0]; x <= r[2]; ++x)
        f(static_cast<std::size_t>(y) * static_cast<std::size_t>(buckets_) +
          static_cast<std::size_t>(x));
  }

  // An endpoint of one segment within eps of the other's interior splits the other there (the
  // T-junctions where a tip stopped on a crack or the outline); a proper crossing splits both.
  void test_pair(std::uint32_t i, std::uint32_t j, std::vector<Split>& splits,
                 std::size_t& crossings) const {
    const Segment& si = segments_[i];
    const Segment& sj = segments_[j];
    const auto touch = [&](std::uint32_t onto, const Segment& target, const Vec2& q) {
      if ((q - target.a).norm() <= eps_ || (q - target.b).norm() <= eps_) return;
      const geometry::SegmentNearest nearest = geometry::nearest_on_segment(q, target.a, target.b);
      if (nearest.distance_m <= eps_) splits.push_back({onto, nearest.t, q});
    };
    touch(i, si, sj.a);
    touch(i, si, sj.b);
    touch(j, sj, si.a);
    touch(j, sj, si.b);
    const Vec2 di = si.b - si.a;
    const Vec2 dj = sj.b - sj.a;
    const double li = di.norm();
    const double lj = dj.norm();
    if (li <= eps_ || lj <= eps_) return;
    // Signed distances of each segment's ends from the other's line.
    const double o1 = cross(di, sj.a - si.a) / li;
    const double o2 = cross(di, sj.b - si.a) / li;
    const double o3 = cross(dj, si.a - sj.a) / lj;
    const double o4 = cross(dj, si.b - sj.a) / lj;
    const auto opposite = [&](double u, double v) {
      return (u > eps_ && v < -eps_) || (u < -eps_ && v > eps_);
    };
    if (opposite(o1, o2) && opposite(o3, o4)) {
      const double tj = o1 / (o1 - o2);
      const Vec2 point = sj.a + tj * dj;
      const double ti = std::clamp((point - si.a).dot(di) / (li * li), 0.0, 1.0);
      splits.push_back({i, ti, point});
      splits.push_back({j, tj, point});
      if (!si.border && !sj.border) ++crossings;
    }
  }

  std::vector<Segment> segments_;
  double eps_;
  int buckets_ = 1;
  double bucket_w_ = 1.0;
  double bucket_h_ = 1.0;
};

struct Edge {
  std::uint32_t u = 0;
  std::uint32_t v = 0;
  bool border = false;
};

// Marks the edges of the biconnected block (Hopcroft–Tarjan, iterative) that contains a border
// edge. In a 2-connected plane graph every face is bounded by a simple cycle, which is what
// makes every fragment a simple polygon; bridges, dangling chains and loops hanging from a single
// vertex all lie outside that block.
std::vector<bool> outline_block(const std::vector<Edge>& edges, std::size_t vertex_count) {
  std::vector<bool> keep(edges.size(), false);
  std::vector<std::uint32_t> adj_start(vertex_count + 1, 0);
  for (const Edge& e : edges) {
    ++adj_start[e.u + 1];
    ++adj_start[e.v + 1];
  }
  std::partial_sum(adj_start.begin(), adj_start.end(), adj_start.begin());
  std::vector<std::pair<std::uint32_t, std::uint32_t>> adj(adj_start.back());  // (vertex, edge)
  {
    std::vector<std::uint32_t> fill(adj_start.begin(), adj_start.end() - 1);
    for (std::uint32_t k = 0; k < edges.size(); ++k) {
      adj[fill[edges[k].u]++] = {edges[k].v, k};
      adj[fill[edges[k].v]++] = {edges[k].u, k};
    }
  }
  const auto border_edge =
      std::find_if(edges.begin(), edges.end(), [](const Edge& e) { return e.border; });
  if (border_edge == edges.end()) return keep;

  constexpr std::int64_t kUnseen = -1;
  std::vector<std::int64_t> disc(vertex_count, kUnseen);
  std::vector<std::int64_t> low(vertex_count, 0);
  struct Frame {
    std::uint32_t v;
    std::int64_t parent_edge;
    std::uint32_t next;
  };
  std::vector<Frame> frames;
  std::vector<std::uint32_t> edge_stack;
  std::int64_t time = 0;
  const std::uint32_t root = border_edge->u;
  disc[root] = low[root] = time++;
  frames.push_back({root, -1, adj_start[root]});
  while (!frames.empty()) {
    Frame& f = frames.back();
    if (f.next < adj_start[f.v + 1]) {
      const auto [w, e] = adj[f.next++];
      if (static_cast<std::int64_t>(e) == f.parent_edge) continue;
      if (disc[w] == kUnseen) {
        edge_stack.push_back(e);
        disc[w] = low[w] = time++;
        frames.push_back({w, static_cast<std::int64_t>(e), adj_start[w]});
      } else if (disc[w] < disc[f.v]) {
        edge_stack.push_back(e);
        low[f.v] = std::min(low[f.v], disc[w]);
      }
      continue;
    }
    const Frame done = f;
    frames.pop_back();
    if (frames.empty()) break;
    Frame& parent = frames.back();
    low[parent.v] = std::min(low[parent.v], low[done.v]);
    if (low[done.v] >= disc[parent.v]) {
      // The edges above and including (parent, done) form one block.
      std::vector<std::uint32_t> block;
      while (true) {
        const std::uint32_t e = edge_stack.back();
        edge_stack.pop_back();
        block.push_back(e);
        if (static_cast<std::int64_t>(e) == done.parent_edge) break;
      }
      const bool has_border =
          std::any_of(block.begin(), block.end(), [&](std::uint32_t e) { return edges[e].border; });
      if (has_border)
        for (std::uint32_t e : block)
          keep[e] = true;
    }
  }
  return keep;
}

// Counter-clockwise order of directions, starting at +x.
bool ccw_before(const Vec2& a, const Vec2& b) {
  const auto half = [](const Vec2& d) { return d.y() < 0.0 || (d.y() == 0.0 && d.x() < 0.0); };
  if (half(a) != half(b)) return !half(a);
  return cross(a, b) > 0.0;
}

}  // namespace

FracturePattern extract_fragments(const CrackTree& tree, double width_m, double height_m) {
  FracturePattern pattern;
  pattern.width_m = width_m;
  pattern.height_m = height_m;
  const double eps_m = 1e-9 * std::max(width_m, height_m);

  std::vector<Segment> segments;
  segments.reserve(tree.segments.size() + 4);
  for (const CrackSegment& s : tree.segments)
    if (s.start != s.end) segments.push_back({s.start, s.end, false});
  const Vec2 corners[4] = {{0.0, 0.0}, {width_m, 0.0}, {width_m, height_m}, {0.0, height_m}};
  for (int k = 0; k < 4; ++k)
    segments.push_back({corners[k], corners[(k + 1) % 4], true});

  // 1. Split every segment at its junctions and crossings.
  Arrangement arrangement(std::move(segments), width_m, height_m, eps_m);
  std::vector<Split> splits = arrangement.find_splits(pattern.crossings);
  const std::vector<Segment>& segs = arrangement.segments();
  for (std::uint32_t i = 0; i < segs.size(); ++i) {
    splits.push_back({i, 0.0, segs[i].a});
    splits.push_back({i, 1.0, segs[i].b});
  }
  std::sort(splits.begin(), splits.end(), [](const Split& x, const Split& y) {
    return x.segment != y.segment ? x.segment < y.segment : x.t < y.t;
  });

  // 2. Merge points closer than eps into vertices (sweep in x; representative: lowest index).
  std::vector<std::uint32_t> by_x(splits.size());
  std::iota(by_x.begin(), by_x.end(), 0U);
  std::sort(by_x.begin(), by_x.end(), [&](std::uint32_t a, std::uint32_t b) {
    const Vec2& p = splits[a].point;
    const Vec2& q = splits[b].point;
    return p.x() != q.x() ? p.x() < q.x() : (p.y() != q.y() ? p.y() < q.y() : a < b);
  });
  geometry::DisjointSets sets(splits.size());
  for (std::size_t k = 0; k < by_x.size(); ++k) {
    const Vec2& p = splits[by_x[k]].point;
    for (std::size_t m = k; m-- > 0;) {
      const Vec2& q = splits[by_x[m]].point;
      if (p.x() - q.x() > eps_m) break;
      if (std::abs(p.y() - q.y()) <= eps_m) sets.unite(by_x[k], by_x[m]);
    }
  }
  constexpr std::uint32_t kNone = 0xffffffffU;
  std::vector<std::uint32_t> vertex_of(splits.size(), kNone);
  std::vector<Vec2> vertices;
  std::vector<std::uint32_t> split_vertex(splits.size());
  for (std::size_t k = 0; k < splits.size(); ++k) {
    const std::size_t root = sets.find(k);
    if (vertex_of[root] == kNone) {
      vertex_of[root] = static_cast<std::uint32_t>(vertices.size());
      vertices.push_back(splits[root].point);
    }
    split_vertex[k] = vertex_of[root];
  }

  // 3. Edges between consecutive vertices along each segment, without repeats.
  std::vector<Edge> edges;
  for (std::size_t k = 0; k + 1 < splits.size(); ++k) {
    if (splits[k].segment != splits[k + 1].segment) continue;
    const std::uint32_t u = split_vertex[k];
    const std::uint32_t v = split_vertex[k + 1];
    if (u == v) continue;
    edges.push_back({std::min(u, v), std::max(u, v), segs[splits[k].segment].border});
  }
  std::sort(edges.begin(), edges.end(), [](const Edge& x, const Edge& y) {
    return x.u != y.u ? x.u < y.u : (x.v != y.v ? x.v < y.v : x.border > y.border);
  });
  edges.erase(std::unique(edges.begin(), edges.end(),
                          [](const Edge& x, const Edge& y) { return x.u == y.u && x.v == y.v; }),
              edges.end());

  // 4. Keep the 2-connected block of the outline: dangling cracks separate no material.
  const std::vector<bool> keep = outline_block(edges, vertices.size());
  std::vector<Edge> kept;
  for (std::size_t k = 0; k < edges.size(); ++k) {
    if (keep[k]) {
      kept.push_back(edges[k]);
      (edges[k].border ? pattern.border_edges : pattern.crack_edges)
          .push_back({vertices[edges[k].u], vertices[edges[k].v]});
    } else if (!edges[k].border) {
      ++pattern.dropped_edges;
    }
  }

  // 5. Faces: half-edge 2k runs u → v, 2k+1 runs v → u. Around each vertex the outgoing
  // half-edges are sorted counter-clockwise; the face left of u → v continues with the outgoing
  // half-edge of v just clockwise of v → u.
  const std::size_t half_count = 2 * kept.size();
  const auto from = [&](std::size_t h) { return (h & 1) ? kept[h / 2].v : kept[h / 2].u; };
  const auto to = [&](std::size_t h) { return (h & 1) ? kept[h / 2].u : kept[h / 2].v; };
  std::vector<std::uint32_t> out_start(vertices.size() + 1, 0);
  for (std::size_t h = 0; h < half_count; ++h)
    ++out_start[from(h) + 1];
  std::partial_sum(out_start.begin(), out_start.end(), out_start.begin());
  std::vector<std::uint32_t> outgoing(half_count);
  {
    std::vector<std::uint32_t> fill(out_start.begin(), out_start.end() - 1);
    for (std::size_t h = 0; h < half_count; ++h)
      outgoing[fill[from(h)]++] = static_cast<std::uint32_t>(h);
  }
  std::vector<std::uint32_t> position(half_count);
  for (std::size_t v = 0; v < vertices.size(); ++v) {
    const auto first = outgoing.begin() + out_start[v];
    const auto last = outgoing.begin() + out_start[v + 1];
    std::sort(first, last, [&](std::uint32_t a, std::uint32_t b) {
      return ccw_before(vertices[to(a)] - vertices[v], vertices[to(b)] - vertices[v]);
    });
    for (auto it = first; it != last; ++it)
      position[*it] = static_cast<std::uint32_t>(it - first);
  }
  std::vector<bool> visited(half_count, false);
  for (std::size_t h0 = 0; h0 < half_count; ++h0) {
    if (visited[h0]) continue;
    Fragment fragment;
    for (std::size_t h = h0; !visited[h];) {
      visited[h] = true;
      fragment.polygon_m.push_back(vertices[from(h)]);
      const std::uint32_t v = to(h);
      const std::size_t twin = h ^ 1;
      const std::uint32_t degree = out_start[v + 1] - out_start[v];
      const std::uint32_t index = (position[twin] + degree - 1) % degree;
      h = outgoing[out_start[v] + index];
    }
    const double area = geometry::signed_area(fragment.polygon_m);
    if (area <= 0.0) continue;  // the outer face
    fragment.area_m2 = area;
    fragment.centroid_m = geometry::centroid(fragment.polygon_m);
    pattern.fragments.push_back(std::move(fragment));
  }
  return pattern;
}

FracturePattern fracture(const FractureParams& params, const StopRequest& stop) {
  if (params.kind == FractureParams::Kind::dice) return dice_pattern(params, stop);
  const CrackTree tree = params.kind == FractureParams::Kind::radial_ring
                             ? radial_ring_cracks(params, stop)
                             : grow_crack_tree(params, stop);
  if (tree.stopped || (stop && stop())) {
    FracturePattern pattern;
    pattern.width_m = params.width_m;
    pattern.height_m = params.height_m;
    pattern.stopped = true;
    return pattern;
  }
  return extract_fragments(tree, params.width_m, params.height_m);
}

}  // namespace brisance::fracture
