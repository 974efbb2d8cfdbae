// Composite Simpson quadrature: an independent check of the closed-form integrals in tests.
#pragma once

namespace brisance::testing {

template <typename F>
double simpson(F&& f, double a, double b, int intervals = 20000) {
  const double h = (b - a) / intervals;
  double sum = f(a) + f(b);
  for (int i = 1; i < intervals; ++i)
    sum += f(a + i * h) * (i % 2 ? 4.0 : 2.0);
  return sum * h / 3.0;
}

}  // namespace brisance::testing
