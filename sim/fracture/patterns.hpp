// sim/fracture/patterns: the crack patterns of broken glass panes beyond the thesis's crack tree
// (docs/fracture.md, "Annealed glass: radial cracks and rings" and "Tempered glass: dice"), and
// the fracture-mechanics relations that size them. Standalone: no engine or scene coupling.
// Units: SI (m, Pa), pane coordinates with the origin at the lower-left corner.
#pragma once

#include <vector>

#include "sim/fracture/crack_tree.hpp"
#include "sim/fracture/fragments.hpp"

namespace brisance::fracture {

// The crack-branching (mirror) constant of soda-lime silicate glass, A_b in sigma sqrt(r_b) =
// A_b: a crack running from its origin under the stress sigma branches once it has run r_b.
// About 2 MPa m^0.5 for soda-lime glass: J. J. Mecholsky, R. W. Rice and S. W. Freiman,
// "Prediction of fracture energy and flaw size in glasses from measurements of mirror size",
// J. Am. Ceram. Soc. 57(10), 440-443 (1974) (sigma r^1/2 constant for every glass measured;
// soda-lime about 1.9-2.1 MPa m^0.5 for the mist, hackle and branching boundaries), and
// G. D. Quinn, "Fractography of ceramics and glasses", NIST SP 960-16 (2007), its table of
// mirror constants.
inline constexpr double kBranchingConstant_Pa_sqrt_m = 2.0e6;

// Poisson's ratio of soda-lime silicate glass, 0.2 (EN 572-1 §4).
inline constexpr double kGlassPoissonRatio = 0.2;

// The stress intensity of a through crack, long against the thickness, in a plate in bending
// is (1 + nu) / (3 + nu) times that of the same crack under a membrane stress equal to the
// surface bending stress (classical plate theory: M. L. Williams, J. Appl. Mech. 28, 78-82
// (1961); G. C. Sih, P. C. Paris and F. Erdogan, J. Appl. Mech. 29, 306-312 (1962)).
double bending_crack_factor(double poisson_ratio);

// The radial cracks of a pane broken in bending (docs/fracture.md): a star of n radial cracks
// of length r releases the strain energy of about the disc they span, shared by its n tips, so
// each tip's stress intensity is about sigma sqrt(pi r) sqrt(2 / n); a tip branches when that
// reaches the branching intensity of a single crack, sigma sqrt(pi r_b) = sqrt(pi) A_b. The star
// then has n(r) = 2 r sigma_e(r)^2 / A_b^2 arms at radius r, sigma_e the effective stress there
// (bending_crack_factor x the plate's surface stress). It branches while n(r) grows and keeps its
// arms beyond. The plate's surface stress field is its mode shape's: sigma(x, y) = sigma_0
// cos(pi dx / W) cos(pi dy / H) from the centre (dx, dy). Per radian around the centre the star
// has rho(theta) = max_r r sigma_e(r, theta)^2 / (pi A_b^2) arms.
struct RadialStar {
  double count = 0.0;          // n, the number of arms (before rounding or any cap)
  double branch_zone_m = 0.0;  // the largest radius (over directions) at which arms still branch
  double branching_length_m = 0.0;  // r_b = (A_b / sigma_e(centre))^2
};
RadialStar radial_star(double width_m, double height_m, double centre_stress_pa,
                       double poisson_ratio = kGlassPoissonRatio,
                       double branching_constant_pa_sqrt_m = kBranchingConstant_Pa_sqrt_m);

// The rings: once the radial cracks have cut the pane into petals, each petal is a wedge hinged
// at the frame and loaded by the pressure p. Its radial bending stress at x from the centre,
// with the part inside the last ring r_0 already gone, is (a wedge of angle dtheta: load
// p dtheta s ds at s, section dtheta x t^2 / 6 at x)
//   sigma(x) = 6 p [x (x^2 - r_0^2) / 2 - (x^3 - r_0^3) / 3] / (x t^2),
// independent of the wedge's angle; a ring cracks where it reaches the strength f (first ring
// x_1 = t sqrt(f / p)). Rings from the centre out to max_radius_m, at most kMaxRings. Static: the
// peak pressure, no dynamic amplification.
std::vector<double> ring_radii_m(double pressure_pa, double strength_pa, double thickness_m,
                                 double max_radius_m);

// Tempered glass: the residual (temper) stress, a parabola through the thickness with the
// surface in compression sigma_s and the mid-plane in tension sigma_m = sigma_s / 2, stores
// U_d = (4/5) (1 - nu) sigma_m^2 / E per unit volume (equal biaxial stress; the parabola's mean
// square is 4/5 of sigma_m^2). A cell d across is released when its stored energy pays for its
// share of the crack faces: U_d d^2 t = eta G_c 2 d t with G_c = K_c^2 / E, so
//   d = 2 eta G_c / U_d = (5/2) eta K_c^2 / ((1 - nu) sigma_m^2),
// the form of J. M. Barsom, "Fracture of tempered glass", J. Am. Ceram. Soc. 51(2), 75-78 (1968)
// (particle size proportional to (K_c / sigma_m)^2, so the count per area to sigma_m^4). eta,
// the face energy per G_c over the share of the stored energy spent on faces, is one constant
// chosen to meet one point (docs/fracture.md): the least temper of fully tempered glass, a
// surface compression of 69 MPa (ASTM C1048), gives the least count of EN 12150-1, 40 cells in
// 50 mm x 50 mm (d = 7.9 mm at K_c = 0.75 MPa m^0.5, nu = 0.2: eta = 5.35).
inline constexpr double kDiceReferenceCompression_Pa = 69e6;
inline constexpr double kDiceReferenceCount = 40.0;  // cells per 50 mm x 50 mm
// eta of the relation above, as the reference point fixes it for soda-lime glass (K_c 0.75
// MPa m^0.5, Wiederhorn 1969; nu 0.2).
double temper_energy_ratio();
// The cell size d, m, for a surface compression sigma_s > 0.
double dice_cell_m(double surface_compression_pa, double fracture_toughness_pa_sqrt_m,
                   double poisson_ratio = kGlassPoissonRatio);

// The crack segments of a radial_ring pattern (params.kind radial_ring), for extract_fragments.
// `stop` is polled before each arm and each ring (a few to some hundred microseconds of work
// apart); when it returns true the build is abandoned and the tree comes back `stopped`, with
// no segments.
CrackTree radial_ring_cracks(const FractureParams& params, const StopRequest& stop = {});

// A dice pattern (params.kind dice): quadrilateral cells on a jittered grid, made directly.
// `stop` is polled once per row of cells; when it returns true the pattern comes back
// `stopped`, with no fragments.
FracturePattern dice_pattern(const FractureParams& params, const StopRequest& stop = {});

// The most fragments in any square window of `window_m` on a side of the pane, and the fewest,
// counting a fragment in a window when its centroid lies in it (EN 12150-1 §8's count: pieces
// in a 50 mm x 50 mm square), over windows stepped by window_m / 4 and kept at least
// `margin_m` from the pane's edges (EN 12150-1 excludes a 25 mm band along the edges).
struct WindowCount {
  std::size_t fewest = 0;
  std::size_t most = 0;
  std::size_t windows = 0;
};
WindowCount fragments_per_window(const FracturePattern& pattern, double window_m, double margin_m);

}  // namespace brisance::fracture
