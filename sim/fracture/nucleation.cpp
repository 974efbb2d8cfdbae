// sim/fracture/nucleation: the largest bending stress of a simply supported plate under point
// forces, by Navier's double sine series (Timoshenko & Woinowsky-Krieger §28–§30).
//
// With alpha_m = m pi / a and beta_n = n pi / b, a force F at (x0, y0) loads the sine term (m, n)
// with q_mn = 4 F sin(alpha_m x0) sin(beta_n y0) / (a b), and the deflection's term is
// w_mn = q_mn / (D (alpha_m^2 + beta_n^2)^2). The moments per unit length follow by
// differentiating the series term by term:
//   M_x  =  D sum w_mn (alpha_m^2 + nu beta_n^2) sin(alpha_m x) sin(beta_n y)
//   M_y  =  D sum w_mn (nu alpha_m^2 + beta_n^2) sin(alpha_m x) sin(beta_n y)
//   M_xy = -D (1 - nu) sum w_mn alpha_m beta_n cos(alpha_m x) cos(beta_n y)
// and a face's stresses are 6 M / t^2. D cancels: the stress does not depend on the modulus.
#include "sim/fracture/nucleation.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

namespace brisance::fracture {

namespace {

using Vec2 = Eigen::Vector2d;

// The series' moment coefficients, D w_mn, term (m, n) at [(m - 1) * terms + (n - 1)].
class PlateSeries {
 public:
  PlateSeries(double a, double b, double nu, int terms, const std::vector<PointForce>& forces)
      : a_(a), b_(b), nu_(nu), terms_(terms), dw_(static_cast<std::size_t>(terms) * terms, 0.0) {
    std::vector<double> sx(terms_);
    std::vector<double> sy(terms_);
    const double scale = 4.0 / (a_ * b_);
    for (const PointForce& f : forces) {
      for (int m = 0; m < terms_; ++m) {
        sx[m] = std::sin(alpha(m) * f.point_m.x());
        sy[m] = std::sin(beta(m) * f.point_m.y());
      }
      for (int m = 0; m < terms_; ++m)
        for (int n = 0; n < terms_; ++n)
          dw_[index(m, n)] += scale * f.force_n * sx[m] * sy[n];
    }
    for (int m = 0; m < terms_; ++m) {
      for (int n = 0; n < terms_; ++n) {
        const double k2 = alpha(m) * alpha(m) + beta(n) * beta(n);
        dw_[index(m, n)] /= k2 * k2;
      }
    }
  }

  // The larger principal stress magnitude of a face at (x, y) of a plate t thick.
  double principal_stress(double x, double y, double t) const {
    thread_local std::vector<double> sin_y;
    thread_local std::vector<double> cos_y;
    sin_y.resize(terms_);
    cos_y.resize(terms_);
    for (int n = 0; n < terms_; ++n) {
      sin_y[n] = std::sin(beta(n) * y);
      cos_y[n] = std::cos(beta(n) * y);
    }
    double mx = 0.0;
    double my = 0.0;
    double mxy = 0.0;
    for (int m = 0; m < terms_; ++m) {
      const double am = alpha(m);
      const double s_m = std::sin(am * x);
      const double c_m = std::cos(am * x);
      for (int n = 0; n < terms_; ++n) {
        const double bn = beta(n);
        const double w = dw_[index(m, n)];
        const double ss = w * s_m * sin_y[n];
        mx += ss * (am * am + nu_ * bn * bn);
        my += ss * (nu_ * am * am + bn * bn);
        mxy -= (1.0 - nu_) * w * am * bn * c_m * cos_y[n];
      }
    }
    const double k = 6.0 / (t * t);
    const double mean = 0.5 * k * (mx + my);
    const double radius = std::hypot(0.5 * k * (mx - my), k * mxy);
    return std::max(std::abs(mean + radius), std::abs(mean - radius));
  }

 private:
  double alpha(int m) const { return (m + 1) * std::numbers::pi / a_; }
  double beta(int n) const { return (n + 1) * std::numbers::pi / b_; }
  std::size_t index(int m, int n) const { return static_cast<std::size_t>(m) * terms_ + n; }

  double a_, b_, nu_;
  int terms_;
  std::vector<double> dw_;
};

}  // namespace

StressPeak largest_bending_stress(double width_m, double height_m, double thickness_m,
                                  double poisson, const std::vector<PointForce>& forces, int terms,
                                  int evaluation_cells) {
  if (!(width_m > 0.0) || !(height_m > 0.0) || !(thickness_m > 0.0))
    throw std::invalid_argument(
        "largest_bending_stress: the pane's size and thickness must be > 0");
  if (terms < 1 || evaluation_cells < 2)
    throw std::invalid_argument("largest_bending_stress: terms must be >= 1 and cells >= 2, got " +
                                std::to_string(terms) + " and " + std::to_string(evaluation_cells));
  const PlateSeries series(width_m, height_m, poisson, terms, forces);
  const auto stress = [&](const Vec2& p) {
    return series.principal_stress(p.x(), p.y(), thickness_m);
  };
  StressPeak peak;
  peak.centre_stress_pa = stress(Vec2(0.5 * width_m, 0.5 * height_m));
  // An even cell count puts the centre on the grid: a symmetric load finds it exactly.
  const int cells = evaluation_cells + evaluation_cells % 2;
  Vec2 step(width_m / cells, height_m / cells);
  Vec2 best(0.5 * width_m, 0.5 * height_m);
  double best_stress = peak.centre_stress_pa;
  const auto search = [&](const Vec2 from, int steps) {  // by value: `best` moves
    for (int i = -steps; i <= steps; ++i) {
      for (int j = -steps; j <= steps; ++j) {
        const Vec2 p = from + Vec2(i * step.x(), j * step.y());
        if (p.x() < 0.0 || p.x() > width_m || p.y() < 0.0 || p.y() > height_m) continue;
        const double s = stress(p);
        // Strictly larger: on a tie (a symmetric load) the point nearest the centre stays.
        if (s > best_stress * (1.0 + 1e-12)) {
          best_stress = s;
          best = p;
        }
      }
    }
  };
  search(Vec2(0.5 * width_m, 0.5 * height_m), cells / 2);
  // Two refinements, each a tenth of the grid before it, around the best point.
  for (int level = 0; level < 2; ++level) {
    step /= 10.0;
    search(best, 10);
  }
  peak.point_m = best;
  peak.stress_pa = best_stress;
  return peak;
}

}  // namespace brisance::fracture
