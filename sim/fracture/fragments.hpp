// sim/fracture/fragments: the fragments a crack tree cuts a pane into — the faces of the planar
// graph of the cracks and the pane's outline (thesis §5.4.3, DESIGN.md decision 9).
//
// Invariants (tested): every fragment is a simple counter-clockwise polygon; fragments do not
// overlap and their areas sum to the pane's; every crack edge kept in `crack_edges` borders two
// fragments, every outline edge one.
#pragma once

#include <array>
#include <cstddef>
#include <vector>

#include "sim/fracture/crack_tree.hpp"

namespace brisance::fracture {

struct Fragment {
  std::vector<Vec2> polygon_m;  // counter-clockwise, pane coordinates, m
  double area_m2 = 0.0;
  Vec2 centroid_m = Vec2::Zero();
};

struct FracturePattern {
  double width_m = 0.0;
  double height_m = 0.0;
  std::vector<Fragment> fragments;
  // The crack pieces that separate fragments, split at every junction, m.
  std::vector<std::array<Vec2, 2>> crack_edges;
  // Outline pieces, split where cracks meet the outline, m.
  std::vector<std::array<Vec2, 2>> border_edges;
  // Crack pieces that separate nothing and were dropped: dangling chains (tips ending in open
  // space) and the rare loop hanging from the rest by a single edge or vertex, whose inside then
  // stays part of the surrounding fragment.
  std::size_t dropped_edges = 0;
  std::size_t crossings = 0;  // crack crossings the growth let through, split into junctions
  bool stopped = false;       // the stop request ended the growth: no fragments
};

// The faces of the crack tree's final graph inside the pane. Builds the planar arrangement of
// the crack segments and the outline (crossings and T-junctions split within 1e-9 of the pane
// size), keeps the 2-connected part that contains the outline (which drops dangling chains), and
// walks every bounded face by next-edge-around-vertex traversal.
FracturePattern extract_fragments(const CrackTree& tree, double width_m, double height_m);

// The pattern of params.kind: grow_crack_tree or radial_ring_cracks followed by
// extract_fragments, or dice_pattern. `stop` is polled while the cracks or the dice are made and
// once more before the fragments are extracted; nothing extracted if it ended the build
// (`stopped`).
FracturePattern fracture(const FractureParams& params, const StopRequest& stop = {});

}  // namespace brisance::fracture
