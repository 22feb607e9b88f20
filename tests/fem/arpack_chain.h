// tests/fem/arpack_chain.h — spring–mass chains for the eigensolver tests: stiffness and mass
// matrices (full symmetric storage) of fixed–fixed and free–free chains. Test helper only.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cmath>
#include <vector>

#include "common/eigen.h"

namespace flexrod::fem::testing {

struct Chain {
  SpMat K;  ///< [N/m]
  SpMat M;  ///< [kg]
};

/// n masses between two walls, n + 1 springs of stiffness k [N/m]. `coupling` ≥ 0 adds a
/// consistent-mass-like off-diagonal term coupling·(m_i + m_{i+1})/2 between neighbours; M stays
/// strictly diagonally dominant (hence positive definite) while
/// coupling < m_min / (m_min + m_max).
inline Chain FixedFixedChain(const std::vector<double>& masses, double k, double coupling = 0.0) {
  const int n = static_cast<int>(masses.size());
  std::vector<Triplet> tk, tm;
  for (int i = 0; i < n; ++i) {
    tk.emplace_back(i, i, 2.0 * k);
    tm.emplace_back(i, i, masses[i]);
    if (i + 1 < n) {
      tk.emplace_back(i, i + 1, -k);
      tk.emplace_back(i + 1, i, -k);
      if (coupling > 0.0) {
        const double c = coupling * 0.5 * (masses[i] + masses[i + 1]);
        tm.emplace_back(i, i + 1, c);
        tm.emplace_back(i + 1, i, c);
      }
    }
  }
  Chain chain{SpMat(n, n), SpMat(n, n)};
  chain.K.setFromTriplets(tk.begin(), tk.end());
  chain.M.setFromTriplets(tm.begin(), tm.end());
  return chain;
}

/// n equal masses m [kg] joined by n − 1 springs k [N/m], no walls: one zero eigenvalue.
inline Chain FreeFreeChain(int n, double m, double k) {
  std::vector<Triplet> tk, tm;
  for (int i = 0; i < n; ++i) {
    tm.emplace_back(i, i, m);
    if (i + 1 < n) {
      tk.emplace_back(i, i, k);
      tk.emplace_back(i + 1, i + 1, k);
      tk.emplace_back(i, i + 1, -k);
      tk.emplace_back(i + 1, i, -k);
    }
  }
  Chain chain{SpMat(n, n), SpMat(n, n)};
  chain.K.setFromTriplets(tk.begin(), tk.end());
  chain.M.setFromTriplets(tm.begin(), tm.end());
  return chain;
}

/// Non-uniform masses in [0.5, 1.5] kg, deterministic.
inline std::vector<double> NonUniformMasses(int n) {
  std::vector<double> m(n);
  for (int i = 0; i < n; ++i) m[i] = 1.0 + 0.5 * std::sin(0.7 * i + 0.3 * i * i / n);
  return m;
}

}  // namespace flexrod::fem::testing
