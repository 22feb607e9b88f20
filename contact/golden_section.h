// contact/golden_section.h — Internal to contact/: golden-section search for the minimum of a
// unimodal function on [a, b], used by the standard linear solid's calibration and by the
// single-impact simulator's peak force.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cmath>

namespace flexrod::contact {

/// The last bracket [a, b] of a golden-section search and its two interior points x1 < x2
/// with their values f1 = f(x1), f2 = f(x2).
struct GoldenBracket {
  double a, b, x1, x2, f1, f2;
};

/// Golden-section search for the minimum of f on [a, b]: at most `max_iterations` reductions,
/// stopping once b − a ≤ rel_tol · b (rel_tol = 0: all of them).
template <typename F>
GoldenBracket GoldenSectionMinimum(F&& f, double a, double b, int max_iterations, double rel_tol) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - g * (b - a), x2 = a + g * (b - a);
  double f1 = f(x1), f2 = f(x2);
  for (int i = 0; i < max_iterations && b - a > rel_tol * b; ++i) {
    if (f1 < f2) {
      b = x2;
      x2 = x1;
      f2 = f1;
      x1 = b - g * (b - a);
      f1 = f(x1);
    } else {
      a = x1;
      x1 = x2;
      f1 = f2;
      x2 = a + g * (b - a);
      f2 = f(x2);
    }
  }
  return {a, b, x1, x2, f1, f2};
}

}  // namespace flexrod::contact
