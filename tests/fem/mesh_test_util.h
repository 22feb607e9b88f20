// tests/fem/mesh_test_util.h — small helpers shared by the elem_* and mesh_* tests: a
// reference rod, dof selections, dense frequencies of an assembled rod, and an error-message
// matcher for InputError. Not part of the library.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <initializer_list>
#include <string>
#include <vector>

#include "common/error.h"
#include "fem/eigensolver.h"
#include "fem/rod_mesh.h"
#include "tests/test_util.h"

namespace flexrod::fem::testing {

using flexrod::test::kPi;

/// The rig's rod (RIG.md Table 1): steel, 280 mm long, 3.175 × 19.05 mm, weak axis in plane.
inline RodSpec RigRod(int num_elements, BeamTheory theory = BeamTheory::kEulerBernoulli,
                      MeshDim dim = MeshDim::kPlanar, MassKind kind = MassKind::kConsistent) {
  RodSpec rod;
  rod.material = MaterialByName("steel");
  rod.section = RectSection{.thickness = 3.175e-3, .height = 19.05e-3};
  rod.length = 0.280;
  rod.num_elements = num_elements;
  rod.theory = theory;
  rod.mass_kind = kind;
  rod.dim = dim;
  return rod;
}

/// Every dof whose local index (within its node) is in `local`.
inline std::vector<int> DofsOfKind(const RodSpec& rod, std::initializer_list<int> local) {
  std::vector<int> out;
  for (int node = 0; node < rod.num_nodes(); ++node)
    for (int k : local) out.push_back(node * rod.dofs_per_node() + k);
  std::sort(out.begin(), out.end());
  return out;
}

inline std::vector<int> Union(std::vector<int> a, const std::vector<int>& b) {
  a.insert(a.end(), b.begin(), b.end());
  std::sort(a.begin(), a.end());
  a.erase(std::unique(a.begin(), a.end()), a.end());
  return a;
}

/// All eigenvalues λ = ω² [rad²/s²] of the assembled rod with `fixed` dofs removed.
inline Vec DenseEigenvalues(const RodSpec& rod, const std::vector<int>& fixed) {
  const AssembledRod a = AssembleRod(rod);
  const std::vector<int> free = FreeDofs(rod.num_dofs(), fixed);
  return SolveEigenDense(Mat(Restrict(a.K, free)), Mat(Restrict(a.M, free))).eigenvalues;
}

/// Natural frequencies [Hz] of the assembled rod with `fixed` dofs removed, ascending.
inline Vec DenseFrequenciesHz(const RodSpec& rod, const std::vector<int>& fixed) {
  EigenResult r;
  r.eigenvalues = DenseEigenvalues(rod, fixed);
  return r.frequencies_hz();
}

/// Runs `f`, expects an InputError whose key is `key` and whose message contains `value`.
inline void ExpectInputError(const std::function<void()>& f, const std::string& key,
                             const std::string& value) {
  try {
    f();
    ADD_FAILURE() << "expected InputError for " << key;
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), key) << e.what();
    EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find(value), std::string::npos) << e.what();
  }
}

}  // namespace flexrod::fem::testing
