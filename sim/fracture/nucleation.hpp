// sim/fracture/nucleation: where a pane's cracks start under a load that is not uniform — the
// point of the largest bending stress of a simply supported rectangular plate, from Navier's
// double sine series (Timoshenko & Woinowsky-Krieger, *Theory of Plates and Shells*, 2nd ed.,
// §28–§30). A uniform load puts it at the centre; a close charge off to one side pulls it toward
// the charge's foot. Linear elastic and static: the stress's shape, not its history (the plate
// SDOF of sim/fracture/pane gives when it breaks). Units: metres, newtons, pascals; pane
// coordinates with the origin at the lower-left corner (as crack_tree.hpp).
#pragma once

#include <vector>

#include <Eigen/Core>

namespace brisance::fracture {

// A part of the load: a force normal to the pane (N; pressure times the area it acts on) at a
// point of the pane. Only the sign convention matters within one load: all push the same way.
struct PointForce {
  Eigen::Vector2d point_m = Eigen::Vector2d::Zero();
  double force_n = 0.0;
};

struct StressPeak {
  Eigen::Vector2d point_m = Eigen::Vector2d::Zero();  // where the largest principal stress is
  double stress_pa = 0.0;                             // its magnitude (a face's, |sigma_1|)
  double centre_stress_pa = 0.0;                      // the same at the pane's centre
};

// The largest principal bending stress over the pane (searched on an evaluation grid of
// `evaluation_cells` + 1 points a side, the centre among them, then refined around the best) of a
// plate of `width_m` x `height_m` x `thickness_m` with Poisson's ratio `poisson`, simply
// supported on all four edges, under the point forces, summed to `terms` x `terms` sine terms.
// The forces act as point loads in the series: sample a pressure at cell centres of a grid at
// least as fine as `terms` per side (a coarser sampling aliases). Throws std::invalid_argument
// for a size, thickness or term count that is not positive.
StressPeak largest_bending_stress(double width_m, double height_m, double thickness_m,
                                  double poisson, const std::vector<PointForce>& forces,
                                  int terms = 31, int evaluation_cells = 40);

}  // namespace brisance::fracture
