// tests/fem/mesh_frequency_reftest.cc — natural frequencies of meshed rods against analytic
// solutions: Euler–Bernoulli beams for five boundary conditions (planar, and both bending
// planes of the spatial mesh) with the h⁴ convergence rate, the exact pinned–pinned Timoshenko
// spectrum of a thick beam, axial and torsional bars, and a cantilever with a tip mass.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <string>
#include <vector>

#include "mesh_test_util.h"

namespace flexrod::fem {
namespace {

using testing::DenseEigenvalues;
using testing::DenseFrequenciesHz;
using testing::DofsOfKind;
using testing::kPi;
using testing::RigRod;
using testing::Union;

// βL roots of the Euler–Bernoulli beam, first five elastic modes: Blevins, Formulas for
// Natural Frequency and Mode Shape (1979), Table 8-1 (re-solved here to 10 digits; the test
// below checks each against its characteristic equation). Pinned–pinned: βL = nπ.
// Free–free shares the clamped–clamped roots.
constexpr std::array<double, 5> kClampedFree{1.8751040687, 4.6940911330, 7.8547574382,
                                             10.9955407349, 14.1371683910};
constexpr std::array<double, 5> kClampedClamped{4.7300407449, 7.8532046241, 10.9956078380,
                                                14.1371654913, 17.2787596574};
constexpr std::array<double, 5> kClampedPinned{3.9266023120, 7.0685827456, 10.2101761228,
                                               13.3517687778, 16.4933614313};

std::array<double, 5> BetaL(const std::string& bc) {
  if (bc == "clamped-free") return kClampedFree;
  if (bc == "clamped-clamped" || bc == "free-free") return kClampedClamped;
  if (bc == "clamped-pinned") return kClampedPinned;
  return {kPi, 2 * kPi, 3 * kPi, 4 * kPi, 5 * kPi};  // pinned-pinned
}

int NumRigidBendingModes(const std::string& bc) { return bc == "free-free" ? 2 : 0; }

const std::vector<std::string> kBoundaryConditions{"clamped-clamped", "clamped-free", "free-free",
                                                   "pinned-pinned", "clamped-pinned"};

/// f_n = (βL)² / (2π L²) √(EI/(ρA)) [Hz].
double BeamFrequencyHz(const RodSpec& rod, double I, double beta_l) {
  const Material& m = rod.material;
  return beta_l * beta_l / (2.0 * kPi * rod.length * rod.length) *
         std::sqrt(m.youngs_modulus * I / (m.density * rod.section.area()));
}

/// In-plane bending frequencies of a planar mesh: axial dofs are fixed, which removes the
/// (uncoupled) axial modes without touching bending.
Vec PlanarBendingHz(const RodSpec& rod, const std::string& bc) {
  return DenseFrequenciesHz(rod, Union(BoundaryDofs(rod, bc), DofsOfKind(rod, {0})));
}

TEST(BeamRoots, TabulatedRootsSatisfyTheirCharacteristicEquations) {
  // Guards the constants above against typos (Blevins Table 8-1 frequency equations).
  for (int i = 0; i < 5; ++i) {
    const double cf = kClampedFree[i], cc = kClampedClamped[i], cp = kClampedPinned[i];
    EXPECT_NEAR(std::cos(cf) + 1.0 / std::cosh(cf), 0.0, 1e-9);  // cos cosh = −1
    EXPECT_NEAR(std::cos(cc) - 1.0 / std::cosh(cc), 0.0, 1e-9);  // cos cosh = 1
    EXPECT_NEAR(std::tan(cp) - std::tanh(cp), 0.0, 1e-8);        // tan = tanh
  }
}

TEST(EulerBernoulliFrequencies, MatchBetaLRootsForFiveBoundaryConditions) {
  // Tolerance 1e-4 relative with 40 Hermite elements (error ≈ (βh)⁴/1440 ≤ 3e-5 for mode 5).
  for (MassKind kind : {MassKind::kConsistent}) {
    const RodSpec rod = RigRod(40, BeamTheory::kEulerBernoulli, MeshDim::kPlanar, kind);
    const double I = rod.section.inertia_in_plane();
    for (const std::string& bc : kBoundaryConditions) {
      const Vec f = PlanarBendingHz(rod, bc);
      const int rigid = NumRigidBendingModes(bc);
      const std::array<double, 5> beta = BetaL(bc);
      // Rigid modes come out at round-off level, ε λ_max ≈ (2π · 0.003 Hz)².
      for (int i = 0; i < rigid; ++i)
        EXPECT_LT(f[i], 1e-4 * BeamFrequencyHz(rod, I, beta[0])) << bc << " rigid mode " << i;
      for (int n = 0; n < 5; ++n) {
        const double exact = BeamFrequencyHz(rod, I, beta[n]);
        EXPECT_NEAR(f[rigid + n] / exact, 1.0, 1e-4) << bc << " mode " << n + 1;
      }
    }
  }
}

TEST(EulerBernoulliFrequencies, SpatialMeshBendsInPlaneWithIinAndOutOfPlaneWithIout) {
  // Spatial mesh, one bending plane at a time: keep (v, φz) → in-plane with I_in; keep
  // (w, φy) → out-of-plane with I_out. Both against the same βL roots.
  const RodSpec rod = RigRod(40, BeamTheory::kEulerBernoulli, MeshDim::kSpatial);
  struct Plane {
    std::vector<int> fixed_kinds;
    double I;
    const char* name;
  };
  const Plane planes[] = {{{0, 2, 3, 4}, rod.section.inertia_in_plane(), "in-plane"},
                          {{0, 1, 3, 5}, rod.section.inertia_out_of_plane(), "out-of-plane"}};
  for (const Plane& p : planes) {
    std::vector<int> kinds_fixed;
    for (int node = 0; node < rod.num_nodes(); ++node)
      for (int k : p.fixed_kinds) kinds_fixed.push_back(node * 6 + k);
    for (const std::string& bc :
         {std::string("clamped-free"), std::string("free-free"), std::string("pinned-pinned")}) {
      const Vec f = DenseFrequenciesHz(rod, Union(BoundaryDofs(rod, bc), kinds_fixed));
      const int rigid = NumRigidBendingModes(bc);
      for (int n = 0; n < 5; ++n) {
        const double exact = BeamFrequencyHz(rod, p.I, BetaL(bc)[n]);
        EXPECT_NEAR(f[rigid + n] / exact, 1.0, 1e-4) << p.name << " " << bc << " " << n + 1;
      }
    }
  }
}

TEST(EulerBernoulliFrequencies, FreeSpatialRodHasSixZeroFrequencies) {
  const RodSpec rod = RigRod(20, BeamTheory::kEulerBernoulli, MeshDim::kSpatial);
  const Vec f = DenseFrequenciesHz(rod, {});
  const double first_elastic =
      BeamFrequencyHz(rod, rod.section.inertia_in_plane(), kClampedClamped[0]);
  for (int i = 0; i < 6; ++i) EXPECT_LT(f[i], 1e-4 * first_elastic) << i;
  EXPECT_NEAR(f[6] / first_elastic, 1.0, 1e-4);  // weak-axis in-plane bending comes first
}

/// Least-squares slope of log(error) against log(h).
double ObservedOrder(const std::vector<double>& h, const std::vector<double>& err) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0;
  const double n = static_cast<double>(h.size());
  for (size_t i = 0; i < h.size(); ++i) {
    const double x = std::log(h[i]), y = std::log(err[i]);
    sx += x, sy += y, sxx += x * x, sxy += x * y;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

TEST(EulerBernoulliFrequencies, ConsistentMassHermiteErrorDecreasesAsHToTheFourth) {
  // Eigenvalue error of a conforming element of degree p for a 2m-order operator is
  // O(h^{2(p+1−m)}) = h⁴ for cubics (m = 2) (Strang & Fix, An Analysis of the Finite Element
  // Method, ch. 6); the frequency error has the same order. Meshes 6, 12, 24: the smallest error
  // (clamped–free mode 1, ≈ 3e-8) stays far above the round-off floor ε λ_max/λ₁ (≈ 1e-10 at 24
  // elements, growing as n⁴; it reaches 4e-9 at 64 elements).
  const std::vector<int> meshes{6, 12, 24};
  for (const std::string& bc : {std::string("clamped-clamped"), std::string("pinned-pinned"),
                                std::string("clamped-free")}) {
    for (int mode = 0; mode < 2; ++mode) {
      std::vector<double> h, err;
      for (int ne : meshes) {
        const RodSpec rod = RigRod(ne);
        const double exact = BeamFrequencyHz(rod, rod.section.inertia_in_plane(), BetaL(bc)[mode]);
        const Vec f = PlanarBendingHz(rod, bc);
        h.push_back(rod.element_length());
        err.push_back(std::abs(f[mode] / exact - 1.0));
      }
      const double order = ObservedOrder(h, err);
      EXPECT_GE(order, 3.5) << bc << " mode " << mode + 1;
      EXPECT_LE(order, 4.5) << bc << " mode " << mode + 1;
    }
  }
}

TEST(EulerBernoulliFrequencies, LumpedMassConvergesFromBelowAsHSquared) {
  // Lumped (HRZ) mass: the Ritz upper bound is lost, frequencies come out low and converge as
  // h² (observed 2.00 on all three conditions); 40 elements are within 2e-3 on modes 1–2.
  for (const std::string& bc : {std::string("clamped-clamped"), std::string("pinned-pinned"),
                                std::string("clamped-free")}) {
    for (int mode = 0; mode < 2; ++mode) {
      std::vector<double> h, err;
      for (int ne : {10, 20, 40}) {
        const RodSpec rod =
            RigRod(ne, BeamTheory::kEulerBernoulli, MeshDim::kPlanar, MassKind::kLumped);
        const double exact = BeamFrequencyHz(rod, rod.section.inertia_in_plane(), BetaL(bc)[mode]);
        const double rel = PlanarBendingHz(rod, bc)[mode] / exact - 1.0;
        EXPECT_LT(rel, 0.0) << bc << " mode " << mode + 1 << " with " << ne << " elements";
        h.push_back(rod.element_length());
        err.push_back(std::abs(rel));
      }
      EXPECT_LT(err.back(), 2e-3) << bc << " mode " << mode + 1;
      const double order = ObservedOrder(h, err);
      EXPECT_GE(order, 1.8) << bc << " mode " << mode + 1;
      EXPECT_LE(order, 2.2) << bc << " mode " << mode + 1;
    }
  }
}

// Exact pinned–pinned Timoshenko beam with rotary inertia (Han, Benaroya & Wei, "Dynamics of
// transversely vibrating beams using four engineering theories", J. Sound Vib. 225 (1999)
// 935–988, hinged–hinged case): with v = V sin(kx), ψ = Ψ cos(kx), k = nπ/L,
//   ρA ρI ω⁴ − [ρA (EI k² + κGA) + ρI κGA k²] ω² + κGA EI k⁴ = 0,
// two branches per n; n = 0 adds the pure-shear mode ω² = κGA/(ρI) (v ≡ 0, ψ constant).
std::vector<double> TimoshenkoPinnedPinnedHz(const RodSpec& rod, int max_n) {
  const Material& m = rod.material;
  const double A = rod.section.area(), I = rod.section.inertia_in_plane();
  const double rhoA = m.density * A, rhoI = m.density * I, EI = m.youngs_modulus * I;
  const double kGA = RectSection::CowperShearFactor(m.poisson_ratio) * m.shear_modulus() * A;
  std::vector<double> hz{std::sqrt(kGA / rhoI) / (2.0 * kPi)};
  for (int n = 1; n <= max_n; ++n) {
    const double k = n * kPi / rod.length;
    const double a = rhoA * rhoI;
    const double b = rhoA * (EI * k * k + kGA) + rhoI * kGA * k * k;
    const double c = kGA * EI * k * k * k * k;
    const double disc = std::sqrt(b * b - 4.0 * a * c);
    const double low = 2.0 * c / (b + disc);  // stable form of (b − disc)/(2a)
    const double high = (b + disc) / (2.0 * a);
    hz.push_back(std::sqrt(low) / (2.0 * kPi));
    hz.push_back(std::sqrt(high) / (2.0 * kPi));
  }
  std::sort(hz.begin(), hz.end());
  return hz;
}

/// Thick pinned–pinned beam: L/h = 5 on the strong axis (h = 19.05 mm), in-plane bending only.
RodSpec ThickTimoshenkoBeam(int num_elements) {
  RodSpec rod = RigRod(num_elements, BeamTheory::kTimoshenko);
  rod.section.in_plane = BendingAxis::kStrong;
  rod.length = 5.0 * rod.section.height;
  return rod;
}

TEST(TimoshenkoFrequencies, ThickPinnedPinnedBeamMatchesExactSpectrum) {
  // Shear and rotary inertia lower mode 1 by ≈ 6 % at L/h = 5. The two-node element has a
  // constant shear strain per element, so its frequencies converge as h² (next test): 40
  // elements give ≤ 1e-3 on modes 1–3 (observed 2e-5, 3e-4, 9e-4), 160 elements on modes 1–5.
  const RodSpec rod = ThickTimoshenkoBeam(40);
  const std::vector<double> exact = TimoshenkoPinnedPinnedHz(rod, 20);
  const Vec f = PlanarBendingHz(rod, "pinned-pinned");
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(f[i] / exact[i], 1.0, 1e-3) << "mode " << i + 1;
  const Vec fine = PlanarBendingHz(ThickTimoshenkoBeam(160), "pinned-pinned");
  for (int i = 0; i < 5; ++i) EXPECT_NEAR(fine[i] / exact[i], 1.0, 1e-3) << "mode " << i + 1;
  // The same mesh with Euler–Bernoulli elements misses mode 1 by more than 3 %: the test
  // discriminates between the theories.
  RodSpec eb = rod;
  eb.theory = BeamTheory::kEulerBernoulli;
  EXPECT_GT(PlanarBendingHz(eb, "pinned-pinned")[0] / exact[0] - 1.0, 0.03);
}

TEST(TimoshenkoFrequencies, ShearDominatedElementConvergesAsHSquared) {
  // With element length below the depth (Φ = 12EI/(κGAL²) ≫ 1) the interdependent element
  // tends to linear v and ψ with constant shear strain: energy error O(h), eigenvalue error
  // O(h²) (Strang & Fix, ch. 6). The rate is a property of the element; pin it so that a
  // change in the mass or stiffness terms that spoils it is caught.
  const std::vector<int> meshes{40, 80, 160};
  std::vector<Vec> f;
  for (int ne : meshes) f.push_back(PlanarBendingHz(ThickTimoshenkoBeam(ne), "pinned-pinned"));
  const std::vector<double> exact = TimoshenkoPinnedPinnedHz(ThickTimoshenkoBeam(40), 20);
  for (int mode = 0; mode < 5; ++mode) {
    std::vector<double> h, err;
    for (size_t i = 0; i < meshes.size(); ++i) {
      h.push_back(1.0 / meshes[i]);
      err.push_back(std::abs(f[i][mode] / exact[mode] - 1.0));
    }
    const double order = ObservedOrder(h, err);
    EXPECT_GE(order, 1.8) << "mode " << mode + 1;
    EXPECT_LE(order, 2.2) << "mode " << mode + 1;
  }
}

/// Exact discrete spectrum of a clamped–free chain of linear 2-node bar elements with
/// consistent mass: the modes sample sin(kx) exactly, k = (2n−1)π/(2L), and
/// ω² = (6c²/h²)(1 − cos kh)/(2 + cos kh) (the chain is the symmetric half of a
/// clamped–clamped chain of length 2L, whose modes are sin(mπx/2L) with the standard
// consistent-mass dispersion relation).
double BarChainHz(double wave_speed, double L, int ne, int n) {
  const double h = L / ne, k = (2 * n - 1) * kPi / (2.0 * L);
  const double ck = std::cos(k * h);
  return std::sqrt(6.0 * wave_speed * wave_speed / (h * h) * (1.0 - ck) / (2.0 + ck)) / (2.0 * kPi);
}

TEST(BarFrequencies, ClampedFreeAxialBarMatchesContinuumAndDiscreteDispersion) {
  // Continuum: f_n = (2n−1)/(4L) √(E/ρ) (wave equation; Blevins 1979, ch. 8). Linear elements
  // over-estimate by ≈ (kh)²/24 (≤ 1.6e-3 for n = 3, 40 elements); the discrete formula is exact.
  const RodSpec rod = RigRod(40);
  const double c = std::sqrt(rod.material.youngs_modulus / rod.material.density);
  const Vec f = DenseFrequenciesHz(rod, Union({0}, DofsOfKind(rod, {1, 2})));
  for (int n = 1; n <= 5; ++n) {
    EXPECT_NEAR(f[n - 1] / BarChainHz(c, rod.length, 40, n), 1.0, 1e-10) << n;
    if (n <= 3) {
      EXPECT_NEAR(f[n - 1] / ((2 * n - 1) * c / (4.0 * rod.length)), 1.0, 2e-3) << n;
    }
  }
}

TEST(BarFrequencies, ClampedFreeTorsionalBarUsesGJAndPolarInertia) {
  // Torsion: f_n = (2n−1)/(4L) √(GJ/(ρ I_p)), I_p = I_y + I_z (wave equation; Blevins 1979, ch. 8).
  const RodSpec rod = RigRod(40, BeamTheory::kEulerBernoulli, MeshDim::kSpatial);
  const RectSection& s = rod.section;
  const double c =
      std::sqrt(rod.material.shear_modulus() * s.torsion_constant() /
                (rod.material.density * (s.inertia_in_plane() + s.inertia_out_of_plane())));
  const Vec f = DenseFrequenciesHz(
      rod, Union(BoundaryDofs(rod, "clamped-free"), DofsOfKind(rod, {0, 1, 2, 4, 5})));
  for (int n = 1; n <= 5; ++n) {
    EXPECT_NEAR(f[n - 1] / BarChainHz(c, rod.length, 40, n), 1.0, 1e-10) << n;
    if (n <= 3) {
      EXPECT_NEAR(f[n - 1] / ((2 * n - 1) * c / (4.0 * rod.length)), 1.0, 2e-3) << n;
    }
  }
}

TEST(BarFrequencies, LinearBarErrorDecreasesAsHSquared) {
  std::vector<double> h, err;
  for (int ne : {10, 20, 40}) {
    const RodSpec rod = RigRod(ne);
    const double c = std::sqrt(rod.material.youngs_modulus / rod.material.density);
    const Vec f = DenseFrequenciesHz(rod, Union({0}, DofsOfKind(rod, {1, 2})));
    h.push_back(rod.element_length());
    err.push_back(f[0] / (c / (4.0 * rod.length)) - 1.0);
  }
  const double order = ObservedOrder(h, err);
  EXPECT_GE(order, 1.8);
  EXPECT_LE(order, 2.2);
}

// Cantilever with a tip point mass M (no rotary inertia): frequency equation
//   1 + cos λ cosh λ + (M/m) λ (cos λ sinh λ − sin λ cosh λ) = 0,  ω = λ² √(EI/(m L³)),
// m = ρAL (Laura, Pombo & Susemihl, "A note on the vibrations of a clamped-free beam with a
// mass at the free end", J. Sound Vib. 37 (1974) 161–168).
double TipMassLambda(double mass_ratio) {
  auto g = [&](double x) {
    return 1.0 + std::cos(x) * std::cosh(x) +
           mass_ratio * x * (std::cos(x) * std::sinh(x) - std::sin(x) * std::cosh(x));
  };
  double lo = 1e-6, hi = kClampedFree[0];  // g(lo) ≈ 2 > 0, g(hi) < 0
  for (int it = 0; it < 200; ++it) {
    const double mid = 0.5 * (lo + hi);
    (g(mid) > 0.0 ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

TEST(Attachments, HeavyTipMassOnCantileverGivesSpringMassFrequency) {
  RodSpec rod = RigRod(40);
  const double rod_mass = rod.material.density * rod.section.area() * rod.length;
  const double ratio = 100.0;
  rod.attachments.push_back(
      {.name = "tip", .node = rod.num_elements, .mass = ratio * rod_mass, .inertia = 0.0});
  const double EI = rod.material.youngs_modulus * rod.section.inertia_in_plane();
  const double L = rod.length;
  // Full planar model (axial modes included: the lowest mode is still the bending one).
  const Vec f = DenseFrequenciesHz(rod, BoundaryDofs(rod, "clamped-free"));
  const double lambda = TipMassLambda(ratio);
  const double exact = lambda * lambda * std::sqrt(EI / (rod_mass * L * L * L)) / (2.0 * kPi);
  EXPECT_NEAR(f[0] / exact, 1.0, 1e-4);
  // Massless spring k = 3EI/L³ carrying M: within 1 % (the rod adds ≈ 0.24 of its mass).
  const double spring_mass = std::sqrt(3.0 * EI / (L * L * L) / (ratio * rod_mass)) / (2.0 * kPi);
  EXPECT_NEAR(f[0] / spring_mass, 1.0, 0.01);
  EXPECT_LT(f[0], spring_mass);  // the rod's own mass only lowers it
}

}  // namespace
}  // namespace flexrod::fem
