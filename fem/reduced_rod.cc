// SPDX-License-Identifier: GPL-3.0-or-later
// Craig–Bampton reduction: Craig & Bampton, AIAA J. 6 (1968) 1313–1319. Basis
//   Φ = [ I 0 ; Ψ Φ_k ] on (interface, interior) dofs, Ψ = −K_II⁻¹ K_IB (static constraint
//   modes), Φ_k the k lowest fixed-interface modes of (K_II, M_II).
#include "fem/reduced_rod.h"

#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <optional>
#include <set>

#include "common/error.h"
#include "common/hdf5.h"
#include "fem/eigensolver.h"
#include "fem/sparse_solver.h"

namespace flexrod::fem {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
/// Eigenvalues below this fraction of the largest kept one count as rigid-body modes.
constexpr double kRigidModeRelTol = 1e-8;
/// Above this many interior dofs ARPACK is used for the fixed-interface modes.
constexpr int kDenseEigenLimit = 600;

/// Gauss–Legendre 4-point rule on [0, 1]: exact for polynomials of degree 7, i.e. for the
/// products of two cubic Hermite interpolants (ffrf-planar.md).
constexpr double kGaussX[4] = {0.5 - 0.5 * 0.8611363115940526, 0.5 - 0.5 * 0.3399810435848563,
                               0.5 + 0.5 * 0.3399810435848563, 0.5 + 0.5 * 0.8611363115940526};
constexpr double kGaussW[4] = {0.5 * 0.3478548451374538, 0.5 * 0.6521451548625461,
                               0.5 * 0.6521451548625461, 0.5 * 0.3478548451374538};

Mat2 Jrot() {
  Mat2 J;
  J << 0.0, -1.0, 1.0, 0.0;
  return J;
}

EigenResult LowestModes(const SpMat& K, const SpMat& M, int count, double cutoff_hz) {
  const int n = static_cast<int>(K.rows());
  if (cutoff_hz > 0.0) {
    EigenRequest req;
    req.min_hz = 0.0;
    req.max_hz = cutoff_hz;
    if (n <= kDenseEigenLimit) {
      EigenResult all = SolveEigenDense(Mat(K), Mat(M));
      const Vec f = all.frequencies_hz();
      int k = 0;
      while (k < f.size() && f[k] <= cutoff_hz) ++k;
      EigenResult r;
      r.eigenvalues = all.eigenvalues.head(k);
      r.eigenvectors = all.eigenvectors.leftCols(k);
      r.num_converged = k;
      return r;
    }
    return SolveEigenArpack(K, M, req);
  }
  if (count == 0) {
    EigenResult r;
    r.eigenvalues.resize(0);
    r.eigenvectors.resize(n, 0);
    return r;
  }
  if (n <= kDenseEigenLimit) return SolveEigenDense(Mat(K), Mat(M), count);
  EigenRequest req;
  req.num_modes = count;
  return SolveEigenArpack(K, M, req);
}

/// Selection matrix columns: dense sub-block extraction of a sparse matrix.
/// X = A⁻¹ B for a symmetric positive definite banded A, by a band Cholesky factorisation in
/// long double (x87 extended precision, ε ≈ 1.1e-19). Returns false if A's half-bandwidth
/// exceeds `max_band` (the caller then uses the sparse solver). A beam's interior stiffness has
/// cond ~ (number of elements)⁴ (≈1e16 at 10 000 elements): the constraint modes Ψ solved in
/// double lost enough digits to put the reduced fundamental frequency 3e-3 off (1.6e-5 at
/// 1 000 elements, where the modal truncation dominates).
constexpr int kExtendedBandLimit = 64;  // node-wise dof numbering: 2 × 6 dofs per node at most

bool SolveBandedExtended(const SpMat& A, const Mat& B, Mat* X, int max_band) {
  const int n = static_cast<int>(A.rows());
  int band = 0;
  for (int c = 0; c < A.outerSize(); ++c) {
    for (SpMat::InnerIterator it(A, c); it; ++it)
      band = std::max(band, static_cast<int>(std::abs(it.row() - c)));
  }
  if (band > max_band) return false;
  const int w = band + 1;  // L(i, j), j in [i − band, i], stored at i·w + (j − i + band)
  std::vector<long double> L(static_cast<size_t>(n) * w, 0.0L);
  auto at = [&](int i, int j) -> long double& {
    return L[static_cast<size_t>(i) * w + (j - i + band)];
  };
  for (int c = 0; c < A.outerSize(); ++c) {
    for (SpMat::InnerIterator it(A, c); it; ++it) {
      if (it.row() >= c) at(static_cast<int>(it.row()), c) = it.value();
    }
  }
  for (int j = 0; j < n; ++j) {
    long double d = at(j, j);
    for (int k = std::max(0, j - band); k < j; ++k) d -= at(j, k) * at(j, k);
    if (!(d > 0.0L))
      throw NumericalError("constraint modes: the interior stiffness is not positive definite");
    const long double ljj = std::sqrt(d);
    at(j, j) = ljj;
    for (int i = j + 1; i <= std::min(n - 1, j + band); ++i) {
      long double v = at(i, j);
      for (int k = std::max(0, i - band); k < j; ++k) v -= at(i, k) * at(j, k);
      at(i, j) = v / ljj;
    }
  }
  X->resize(n, B.cols());
  std::vector<long double> y(n);
  for (int c = 0; c < B.cols(); ++c) {
    for (int i = 0; i < n; ++i) {  // L y = b
      long double v = B(i, c);
      for (int k = std::max(0, i - band); k < i; ++k) v -= at(i, k) * y[k];
      y[i] = v / at(i, i);
    }
    for (int i = n - 1; i >= 0; --i) {  // Lᵀ x = y
      long double v = y[i];
      for (int k = i + 1; k <= std::min(n - 1, i + band); ++k) v -= at(k, i) * y[k];
      y[i] = v / at(i, i);
    }
    for (int i = 0; i < n; ++i) (*X)(i, c) = static_cast<double>(y[i]);
  }
  return true;
}

SpMat SubMatrix(const SpMat& A, const std::vector<int>& rows, const std::vector<int>& cols) {
  std::vector<int> rmap(A.rows(), -1), cmap(A.cols(), -1);
  for (size_t i = 0; i < rows.size(); ++i) rmap[rows[i]] = static_cast<int>(i);
  for (size_t j = 0; j < cols.size(); ++j) cmap[cols[j]] = static_cast<int>(j);
  std::vector<Triplet> t;
  for (int c = 0; c < A.outerSize(); ++c) {
    if (cmap[c] < 0) continue;
    for (SpMat::InnerIterator it(A, c); it; ++it) {
      if (rmap[it.row()] >= 0) t.emplace_back(rmap[it.row()], cmap[c], it.value());
    }
  }
  SpMat S(rows.size(), cols.size());
  S.setFromTriplets(t.begin(), t.end());
  return S;
}

/// Dense generalised eigen-decomposition of a small reduced pair, ascending.
EigenResult SmallEigen(const Mat& K, const Mat& M) { return SolveEigenDense(K, M); }

Vec ToHz(const Vec& eigenvalues) {
  Vec f(eigenvalues.size());
  for (int i = 0; i < f.size(); ++i) f[i] = std::sqrt(std::max(eigenvalues[i], 0.0)) / kTwoPi;
  return f;
}

/// Indices of rigid-body (near-zero) eigenvalues.
int CountRigid(const Vec& eigenvalues) {
  if (eigenvalues.size() == 0) return 0;
  const double scale = eigenvalues.cwiseAbs().maxCoeff();
  int r = 0;
  for (int i = 0; i < eigenvalues.size(); ++i) {
    if (std::abs(eigenvalues[i]) <= kRigidModeRelTol * scale) ++r;
  }
  return r;
}

/// Element dof indices of a planar element.
std::array<int, 6> PlanarElementDofs(int e) {
  return {3 * e, 3 * e + 1, 3 * e + 2, 3 * e + 3, 3 * e + 4, 3 * e + 5};
}

/// The fixed-interface static responses of a planar rod to the axial inertia loads of a
/// rigid motion: f₁ = M r_u (uniform axial acceleration) and f₂ = M (x r_u) (the centripetal
/// load θ̇² x), with the frame's and the interface's dofs held, so that together with the
/// interface's axial constraint mode the basis carries an axial force linear, then quadratic
/// in x. Each is made M-orthogonal to `basis` (Gram–Schmidt, twice) and M-normalised; one
/// that the basis already spans (to 1e-8 of its norm) is dropped.
Mat AxialLoadModes(const RodSpec& rod, const AssembledRod& A, const std::vector<int>& interior,
                   const std::vector<int>& boundary, const Mat& basis) {
  (void)boundary;
  const int ndof = rod.num_dofs();
  const int ni = static_cast<int>(interior.size());
  Mat loads = Mat::Zero(ndof, 2);
  for (int i = 0; i < rod.num_nodes(); ++i) {
    loads(3 * i, 0) = 1.0;
    loads(3 * i, 1) = rod.node_x(i);
  }
  const Mat f = A.M * loads;
  Mat rhs(ni, 2);
  for (int i = 0; i < ni; ++i) rhs.row(i) = f.row(interior[i]);
  Mat x(ni, 2);
  auto chol = MakeSparseSolver(SparseSolverKind::kCholmod);
  chol->Factorize(SubMatrix(A.K, interior, interior));
  chol->Solve(rhs, &x);
  Mat out = Mat::Zero(ndof, 2);
  int kept = 0;
  Mat accepted = basis;
  for (int c = 0; c < 2; ++c) {
    Vec psi = Vec::Zero(ndof);
    for (int i = 0; i < ni; ++i) psi(interior[i]) = x(i, c);
    const double norm0 = std::sqrt(psi.dot(A.M * psi));
    for (int pass = 0; pass < 2; ++pass) {
      const Mat MB = A.M * accepted;
      const Mat G = accepted.transpose() * MB;
      const Vec coeff = G.ldlt().solve(MB.transpose() * psi);
      psi -= accepted * coeff;
    }
    const double norm = std::sqrt(psi.dot(A.M * psi));
    if (!(norm > 1e-8 * norm0)) continue;
    psi /= norm;
    out.col(kept++) = psi;
    accepted.conservativeResize(Eigen::NoChange, accepted.cols() + 1);
    accepted.rightCols(1) = psi;
  }
  return out.leftCols(kept);
}

/// Node shape rows of a planar rod: rows (u, v) and φ of the basis at every node.
std::vector<MarkerShape> PlanarNodeShapes(const RodSpec& rod, const Mat& basis) {
  std::vector<MarkerShape> nodes(rod.num_nodes());
  for (int i = 0; i < rod.num_nodes(); ++i) {
    MarkerShape& m = nodes[i];
    m.position = Vec2(rod.node_x(i), 0.0);
    m.S_u = basis.middleRows(3 * i, 2);
    m.S_phi = basis.row(3 * i + 2);
  }
  return nodes;
}

PlanarInertia ComputePlanarInertia(const RodSpec& rod, const Mat& basis,
                                   const std::vector<MarkerShape>& nodes) {
  const int n = static_cast<int>(basis.cols());
  const double rhoA = rod.material.density * rod.section.area();
  // Rotary inertia (fibres at y move axially by −yψ) is kept for Timoshenko, whose consistent
  // mass contains it; Euler–Bernoulli uses the thin-beam approximation, matching its mass.
  const double rhoI = rod.theory == BeamTheory::kTimoshenko
                          ? rod.material.density * rod.section.inertia_in_plane()
                          : 0.0;
  const double le = rod.element_length();
  PlanarInertia in;
  in.S = Mat2X::Zero(2, n);
  in.I1 = Vec::Zero(n);
  in.Ibar = Vec::Zero(n);
  in.Mff = Mat::Zero(n, n);
  in.Stilde = Mat::Zero(n, n);
  Eigen::Matrix<double, 6, Eigen::Dynamic> phi_e(6, n);
  RowVec Nu(n), Nv(n), Npsi(n);
  const Mat2 J = Jrot();
  // A node point mass m with rotational inertia j (lumped mass, attachments).
  auto add_node_mass = [&](const MarkerShape& k, const Vec2& offset, double m, double j) {
    const Vec2 u0 = k.position + offset;
    const Mat2X Sa = k.S_u + J * offset * k.S_phi;
    in.mass += m;
    in.S0 += m * u0;
    in.S += m * Sa;
    in.J0 += m * u0.squaredNorm() + j;
    in.I1 += m * Sa.transpose() * u0;
    in.Ibar += m * Sa.transpose() * (J * u0) + j * k.S_phi.transpose();
    in.Mff += m * Sa.transpose() * Sa + j * k.S_phi.transpose() * k.S_phi;
    in.Stilde += m * Sa.transpose() * J * Sa;
  };
  if (rod.mass_kind == MassKind::kLumped) {
    // The lumped (HRZ) element mass as node point masses ρA l/2 with rotational inertia
    // ρA l³/78 + ρI l/2 (fem/beam_element.cc), so that the body's inertia is the lumped mass's.
    const double rhoI_lumped = rod.material.density * rod.section.inertia_in_plane();
    const double j = rhoA * le * le * le / 78.0 +
                     (rod.theory == BeamTheory::kTimoshenko ? 0.5 * rhoI_lumped * le : 0.0);
    for (int e = 0; e < rod.num_elements; ++e) {
      for (int k : {e, e + 1}) add_node_mass(nodes[k], Vec2::Zero(), 0.5 * rhoA * le, j);
    }
  }
  for (int e = 0; e < rod.num_elements && rod.mass_kind == MassKind::kConsistent; ++e) {
    const auto dofs = PlanarElementDofs(e);
    for (int i = 0; i < 6; ++i) phi_e.row(i) = basis.row(dofs[i]);
    const double x0 = rod.node_x(e);
    for (int g = 0; g < 4; ++g) {
      const PlanarShape sh =
          PlanarFrameShape(rod.section, rod.material, le, rod.theory, kGaussX[g]);
      const double w = kGaussW[g] * le;
      const double x = x0 + kGaussX[g] * le;
      Nu.noalias() = sh.N.row(0) * phi_e;
      Nv.noalias() = sh.N.row(1) * phi_e;
      Npsi.noalias() = sh.N.row(2) * phi_e;
      in.mass += rhoA * w;
      in.S0.x() += rhoA * x * w;
      in.S.row(0) += rhoA * w * Nu;
      in.S.row(1) += rhoA * w * Nv;
      in.J0 += (rhoA * x * x + rhoI) * w;
      in.I1 += (rhoA * x * w) * Nu.transpose();
      in.Ibar += w * (rhoI * Npsi.transpose() + rhoA * x * Nv.transpose());
      in.Mff.noalias() +=
          w * (rhoA * (Nu.transpose() * Nu + Nv.transpose() * Nv) + rhoI * Npsi.transpose() * Npsi);
      in.Stilde.noalias() += (rhoA * w) * (Nv.transpose() * Nu - Nu.transpose() * Nv);
    }
  }
  // Rigid attachments as point masses plus their own rotational inertia (ffrf-planar.md).
  for (const RigidAttachment& a : rod.attachments)
    add_node_mass(nodes[a.node], a.com_offset, a.mass, a.inertia);
  in.Mff = 0.5 * (in.Mff + in.Mff.transpose());
  in.Stilde = 0.5 * (in.Stilde - in.Stilde.transpose());
  return in;
}

}  // namespace

ReductionMethod ReductionMethodFromString(const std::string& key, const std::string& value) {
  if (value == "craig-bampton") return ReductionMethod::kCraigBampton;
  if (value == "orthonormal-cb") return ReductionMethod::kOrthonormalCraigBampton;
  if (value == "free-free") return ReductionMethod::kFreeFree;
  if (value == "full") return ReductionMethod::kFull;
  throw InputError(key, value, "must be one of craig-bampton, orthonormal-cb, free-free, full");
}

const char* ToString(ReductionMethod m) {
  switch (m) {
    case ReductionMethod::kCraigBampton:
      return "craig-bampton";
    case ReductionMethod::kOrthonormalCraigBampton:
      return "orthonormal-cb";
    case ReductionMethod::kFreeFree:
      return "free-free";
    case ReductionMethod::kFull:
      return "full";
  }
  return "?";
}

void ReductionSpec::Validate(const RodSpec& rod) const {
  Require(num_modes >= 0, "reduction.modes", num_modes, "must be >= 0");
  RequireNonNegative("reduction.cutoff", cutoff_hz);
  const int ndof = rod.num_dofs();
  for (int d : fixed_dofs)
    Require(d >= 0 && d < ndof, "reduction.fixed_dofs", d, "dof out of range");
  for (int k : interface_nodes) {
    Require(k >= 0 && k < rod.num_nodes(), "reduction.interface", k,
            "node out of range 0.." + std::to_string(rod.num_nodes() - 1));
  }
  if (method == ReductionMethod::kCraigBampton ||
      method == ReductionMethod::kOrthonormalCraigBampton) {
    Require(!interface_nodes.empty(), "reduction.interface", 0.0,
            "Craig–Bampton needs interface nodes");
  }
}

ReductionSpec MechanismReduction(const RodSpec& rod, ReductionMethod m, int num_modes) {
  ReductionSpec s;
  s.method = m;
  s.num_modes = num_modes;
  const int dpn = rod.dofs_per_node();
  if (m != ReductionMethod::kFreeFree) {
    for (int d = 0; d < dpn; ++d) s.fixed_dofs.push_back(d);  // big-end node fixed in the frame
  }
  s.interface_nodes = {rod.num_nodes() - 1};
  return s;
}

MarkerShape ReducedRod::Marker(int node, const Vec2& offset) const {
  if (node < 0 || node >= static_cast<int>(nodes.size())) {
    throw InputError("marker.node", std::to_string(node), "must be an FE node of the rod");
  }
  const MarkerShape& k = nodes[node];
  MarkerShape m;
  m.position = k.position + offset;
  m.S_u = k.S_u + Jrot() * offset * k.S_phi;
  m.S_phi = k.S_phi;
  return m;
}

StrainGaugeRows ReducedRod::Gauge(const std::string& name, double x, double y) const {
  if (!(x >= 0.0 && x <= rod.length)) {
    throw InputError("gauge." + name + ".x", FormatValue(x),
                     "must lie on the rod, 0 <= x <= length");
  }
  if (rod.dim != MeshDim::kPlanar)
    throw InputError("gauge", name, "strain gauges need a planar rod");
  const double le = rod.element_length();
  const int e = std::min(static_cast<int>(x / le), rod.num_elements - 1);
  const double xi = (x - rod.node_x(e)) / le;
  const PlanarShape sh = PlanarFrameShape(rod.section, rod.material, le, rod.theory, xi);
  const int n = num_coordinates();
  Eigen::Matrix<double, 6, Eigen::Dynamic> phi_e(6, n);
  const auto dofs = PlanarElementDofs(e);
  for (int i = 0; i < 6; ++i) phi_e.row(i) = basis.row(dofs[i]);
  StrainGaugeRows g;
  g.name = name;
  g.x = x;
  g.y = y;
  g.axial = sh.B.row(0) * phi_e;
  g.bending = -y * (sh.B.row(1) * phi_e);
  // (P s)_e = ½ qᵀ (Σ_f P_ef Φ_fᵀ K_G Φ_f) q.
  const Mat V = Elongation().basis;
  const Vec Pe = V * V.row(e).transpose();
  g.membrane = Mat::Zero(n, n);
  for (int f = 0; f < rod.num_elements; ++f) {
    if (Pe(f) == 0.0) continue;
    const auto phi_f = ElementBasisRows(f);
    g.membrane.noalias() += (0.5 * Pe(f) / le) * (phi_f.transpose() * element_Kg * phi_f);
  }
  return g;
}

ElongationSpace ReducedRod::Elongation() const {
  FLEXROD_ASSERT(rod.dim == MeshDim::kPlanar);
  const int ne = rod.num_elements, n = num_coordinates();
  Mat E(ne, n);
  for (int e = 0; e < ne; ++e) {
    const auto dofs = PlanarElementDofs(e);
    E.row(e) = basis.row(dofs[3]) - basis.row(dofs[0]);
  }
  if (n == 0) return {Mat(ne, 0), Mat(0, ne)};
  const Eigen::JacobiSVD<Mat> svd(E, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Vec& sv = svd.singularValues();
  // Elongations below 1e-8 of the basis's largest displacement per unit q are round-off (a
  // free-free basis without axial modes has σ ≈ 1e-13 against 0.1 for an axial mode).
  const double floor = 1e-8 * basis.cwiseAbs().maxCoeff();
  int r = 0;
  while (r < sv.size() && sv[r] > floor && sv[r] > 1e-9 * sv[0]) ++r;
  ElongationSpace out;
  out.basis = svd.matrixU().leftCols(r);
  out.shortening_to_q =
      svd.matrixV().leftCols(r) * sv.head(r).cwiseInverse().asDiagonal() * out.basis.transpose();
  return out;
}

Eigen::Matrix<double, 6, Eigen::Dynamic> ReducedRod::ElementBasisRows(int e) const {
  FLEXROD_ASSERT(e >= 0 && e < rod.num_elements && rod.dim == MeshDim::kPlanar);
  Eigen::Matrix<double, 6, Eigen::Dynamic> rows(6, basis.cols());
  const auto dofs = PlanarElementDofs(e);
  for (int i = 0; i < 6; ++i) rows.row(i) = basis.row(dofs[i]);
  return rows;
}

ReducedRod Reduce(const RodSpec& rod, const ReductionSpec& spec) {
  rod.Validate();
  spec.Validate(rod);
  const AssembledRod A = AssembleRod(rod);
  const int ndof = rod.num_dofs();
  const int dpn = rod.dofs_per_node();

  std::set<int> fixed(spec.fixed_dofs.begin(), spec.fixed_dofs.end());
  const std::vector<int> free = FreeDofs(ndof, spec.fixed_dofs);
  const int nfree = static_cast<int>(free.size());

  ReducedRod out;
  out.rod = rod;
  out.reduction = spec;
  Mat& basis = out.basis;

  std::optional<Mat> structured_K;  // Craig–Bampton: K_r from its block structure
  switch (spec.method) {
    case ReductionMethod::kFull: {
      basis = Mat::Zero(ndof, nfree);
      for (int j = 0; j < nfree; ++j) basis(free[j], j) = 1.0;
      break;
    }
    case ReductionMethod::kFreeFree: {
      const SpMat Kf = Restrict(A.K, free), Mf = Restrict(A.M, free);
      const int rigid_expected = fixed.empty() ? (dpn == 3 ? 3 : 6) : 0;
      const int want = spec.cutoff_hz > 0.0 ? 0 : spec.num_modes + rigid_expected;
      Require(spec.cutoff_hz > 0.0 || want <= nfree, "reduction.modes", spec.num_modes,
              "more modes than the " + std::to_string(nfree - rigid_expected) +
                  " free dofs of the rod's mesh (rod.elements = " +
                  std::to_string(rod.num_elements) + ")");
      EigenResult er;
      if (spec.cutoff_hz > 0.0) {
        er = LowestModes(Kf, Mf, 0, spec.cutoff_hz);
      } else {
        EigenRequest req;
        req.num_modes = want;
        er = nfree <= kDenseEigenLimit ? SolveEigenDense(Mat(Kf), Mat(Mf), want)
                                       : SolveEigenArpack(Kf, Mf, req);
      }
      const int rigid = CountRigid(er.eigenvalues);
      const int keep = static_cast<int>(er.eigenvalues.size()) - rigid;
      basis = Mat::Zero(ndof, keep);
      for (int j = 0; j < nfree; ++j)
        basis.row(free[j]) = er.eigenvectors.row(j).segment(rigid, keep);
      break;
    }
    case ReductionMethod::kCraigBampton:
    case ReductionMethod::kOrthonormalCraigBampton: {
      std::vector<int> boundary, interior;
      std::set<int> bset;
      for (int k : spec.interface_nodes) {
        for (int d = 0; d < dpn; ++d) {
          if (!fixed.count(k * dpn + d)) bset.insert(k * dpn + d);
        }
      }
      boundary.assign(bset.begin(), bset.end());
      for (int d : free) {
        if (!bset.count(d)) interior.push_back(d);
      }
      const int nb = static_cast<int>(boundary.size());
      const int ni = static_cast<int>(interior.size());
      Require(spec.cutoff_hz > 0.0 || spec.num_modes <= ni, "reduction.modes", spec.num_modes,
              "more modes than the " + std::to_string(ni) +
                  " interior dofs of the rod's mesh (rod.elements = " +
                  std::to_string(rod.num_elements) + ")");
      const SpMat Kii = SubMatrix(A.K, interior, interior);
      const SpMat Mii = SubMatrix(A.M, interior, interior);
      const SpMat Kib = SubMatrix(A.K, interior, boundary);
      Mat Psi(ni, nb);
      if (ni > 0 && nb > 0) {
        const Mat rhs = -(Kib * Mat::Identity(nb, nb));
        if (!SolveBandedExtended(Kii, rhs, &Psi, kExtendedBandLimit)) {
          auto chol = MakeSparseSolver(SparseSolverKind::kCholmod);
          chol->Factorize(Kii);
          chol->Solve(rhs, &Psi);
        }
      }
      EigenResult fixed_interface;
      if (ni > 0) fixed_interface = LowestModes(Kii, Mii, spec.num_modes, spec.cutoff_hz);
      const int k = ni > 0 ? static_cast<int>(fixed_interface.eigenvalues.size()) : 0;
      basis = Mat::Zero(ndof, nb + k);
      for (int i = 0; i < nb; ++i) basis(boundary[i], i) = 1.0;
      for (int i = 0; i < ni; ++i) {
        basis.row(interior[i]).head(nb) = Psi.row(i);
        if (k > 0) basis.row(interior[i]).tail(k) = fixed_interface.eigenvectors.row(i);
      }
      // Reduced stiffness from the Craig–Bampton block structure (Craig & Bampton 1968):
      // K_r = diag(K_bb + K_bi Ψ, Λ); the coupling Φ_mᵀ(K_ii Ψ + K_ib) is zero and Φ_m is
      // M-orthonormal. The projection Φᵀ K Φ forms the same matrix from products of K's
      // largest entries (12EI/h³ ≈ 6e12 N/m at 10 000 elements) with smooth shapes, and its
      // cancellation alone put the reduced fundamental frequency 1e-2 below the full model's
      // there; the Schur complement cancels once, against the boundary entries only.
      Mat Kcb = Mat::Zero(nb + k, nb + k);
      if (nb > 0) {
        Kcb.topLeftCorner(nb, nb) = Mat(SubMatrix(A.K, boundary, boundary));
        if (ni > 0) Kcb.topLeftCorner(nb, nb) += Mat(SpMat(Kib.transpose())) * Psi;
      }
      for (int j = 0; j < k; ++j) Kcb(nb + j, nb + j) = fixed_interface.eigenvalues(j);
      Kcb = (0.5 * (Kcb + Kcb.transpose())).eval();
      structured_K = Kcb;
      if (spec.axial_load_modes && dpn == 3 && ni > 0) {
        // Fixed-interface static responses to the axial inertia loads of a rigid motion
        // (uniform axial acceleration, and the centripetal load growing with x): ψ = K_ii⁻¹ f_i,
        // M-orthogonalised against the basis (AxialLoadModes).
        const Mat psi = AxialLoadModes(rod, A, interior, boundary, basis);
        if (psi.cols() > 0) {
          const int na = static_cast<int>(psi.cols());
          Mat widened = Mat::Zero(ndof, nb + k + na);
          widened.leftCols(nb + k) = basis;
          widened.rightCols(na) = psi;
          basis = std::move(widened);
          structured_K.reset();  // K_r by projection: the static modes couple to the boundary
        }
      }
      if (spec.method == ReductionMethod::kOrthonormalCraigBampton) {
        // Diagonalise the reduced pair; the basis becomes M-orthonormal with K diagonal. When
        // the frame carries rigid-body motion (no dofs fixed), rigid-body modes are dropped.
        const Mat Mr = basis.transpose() * (A.M * basis);
        const Mat Kr = structured_K ? Kcb : Mat(basis.transpose() * (A.K * basis));
        const EigenResult er = SmallEigen(0.5 * (Kr + Kr.transpose()), 0.5 * (Mr + Mr.transpose()));
        const int rigid = fixed.empty() ? CountRigid(er.eigenvalues) : 0;
        const Mat E = er.eigenvectors.rightCols(er.eigenvalues.size() - rigid);
        basis = basis * E;
        structured_K = (E.transpose() * Kr * E).eval();
      }
      break;
    }
  }

  out.K = structured_K ? *structured_K : Mat(basis.transpose() * (A.K * basis));
  out.M = basis.transpose() * (A.M * basis);
  out.K = 0.5 * (out.K + out.K.transpose());
  out.M = 0.5 * (out.M + out.M.transpose());
  const int n = static_cast<int>(basis.cols());
  out.frequencies_hz = n > 0 ? ToHz(SmallEigen(out.K, out.M).eigenvalues) : Vec();

  out.element_Kg.setZero();
  if (rod.dim == MeshDim::kPlanar) {
    out.nodes = PlanarNodeShapes(rod, basis);
    out.inertia = ComputePlanarInertia(rod, basis, out.nodes);
    const double le = rod.element_length();
    out.element_axial_stiffness = rod.material.youngs_modulus * rod.section.area() / le;
    out.element_Kg = PlanarFrameGeometricStiffness(le);
  }
  return out;
}

std::string MeshPrecisionWarning(const RodSpec& rod, ReductionMethod method) {
  const int limit = method == ReductionMethod::kFull ? 30000 : 10000;
  if (rod.num_elements <= limit) return "";
  return "rod.elements = " + std::to_string(rod.num_elements) + ": beyond " +
         std::to_string(limit) + " elements the " +
         (method == ReductionMethod::kFull ? "full model's" : "reduced model's") +
         " frequencies lose accuracy to round-off (stiffness conditioning ~ elements^4; measured "
         "on "
         "the clamped-free steel rod: Craig-Bampton 2.8e-4 at 10 000 and 1.8e-2 at 30 000 "
         "elements, the full model wrong at 100 000); a few hundred elements converge the modes";
}

std::vector<ModeReportRow> CompareWithFullModel(const ReducedRod& reduced, int num_modes) {
  const RodSpec& rod = reduced.rod;
  const AssembledRod A = AssembleRod(rod);
  const std::vector<int> free = FreeDofs(rod.num_dofs(), reduced.reduction.fixed_dofs);
  const SpMat Kf = Restrict(A.K, free), Mf = Restrict(A.M, free);
  const int nfree = static_cast<int>(free.size());
  num_modes = std::min(num_modes, nfree);
  Require(num_modes >= 1, "modes", num_modes, "must be >= 1");
  EigenResult full;
  if (nfree <= kDenseEigenLimit || num_modes >= nfree - 1) {
    full = SolveEigenDense(Mat(Kf), Mat(Mf), num_modes);
  } else {
    EigenRequest req;
    req.num_modes = num_modes;
    full = SolveEigenArpack(Kf, Mf, req);
  }
  const Vec full_hz = ToHz(full.eigenvalues);
  const int n_full_rigid = CountRigid(full.eigenvalues);

  const int n = reduced.num_coordinates();
  EigenResult red;
  if (n > 0) red = SmallEigen(reduced.K, reduced.M);
  const Vec red_hz = n > 0 ? ToHz(red.eigenvalues) : Vec();
  const int n_red_rigid = n > 0 ? CountRigid(red.eigenvalues) : 0;
  // The reduced model may drop rigid-body modes the frame carries; align elastic modes.
  const int shift = n_full_rigid - n_red_rigid;

  // In-plane transverse rigid translation of every node (the v dof), for effective mass.
  const int dpn = rod.dofs_per_node();
  Vec r = Vec::Zero(nfree);
  for (int j = 0; j < nfree; ++j) r[j] = (free[j] % dpn == 1) ? 1.0 : 0.0;
  const Vec Mr = Mf * r;

  std::vector<ModeReportRow> rows;
  for (int i = 0; i < num_modes; ++i) {
    ModeReportRow row;
    row.index = i + 1;
    row.full_hz = full_hz[i];
    row.rigid_body = i < n_full_rigid;
    const Vec phi_f = full.eigenvectors.col(i);
    const double gamma = phi_f.dot(Mr);
    row.effective_mass = gamma * gamma / phi_f.dot(Mf * phi_f);
    const int j = row.rigid_body ? (i < n_red_rigid ? i : -1) : i - shift;
    if (j >= 0 && j < n) {
      row.reduced_hz = red_hz[j];
      Vec phi_r_full = reduced.basis * red.eigenvectors.col(j);
      Vec phi_r(nfree);
      for (int k = 0; k < nfree; ++k) phi_r[k] = phi_r_full[free[k]];
      const double c = phi_f.dot(phi_r);
      row.mac = c * c / (phi_f.squaredNorm() * phi_r.squaredNorm());
      row.rel_error =
          row.rigid_body || row.full_hz == 0.0 ? 0.0 : (row.reduced_hz - row.full_hz) / row.full_hz;
    } else if (row.rigid_body) {
      row.reduced_hz = 0.0;  // carried by the floating frame
      row.mac = 1.0;
    } else {
      row.reduced_hz = std::nan("");
      row.mac = std::nan("");
      row.rel_error = std::nan("");
    }
    rows.push_back(row);
  }
  return rows;
}

// ---- HDF5 round trip --------------------------------------------------------------------
namespace {

void WriteRodSpec(const h5::Node& g, const RodSpec& rod) {
  g.SetAttr("material.name", rod.material.name);
  g.SetAttr("material.source", rod.material.source);
  g.SetAttr("material.E", rod.material.youngs_modulus, "Pa");
  g.SetAttr("material.nu", rod.material.poisson_ratio, "1");
  g.SetAttr("material.rho", rod.material.density, "kg/m^3");
  g.SetAttr("material.yield", rod.material.yield_strength, "Pa");
  g.SetAttr("rod.thickness", rod.section.thickness, "m");
  g.SetAttr("rod.height", rod.section.height, "m");
  g.SetAttr("rod.bending", ToString(rod.section.in_plane));
  g.SetAttr("rod.length", rod.length, "m");
  g.SetAttr("rod.elements", rod.num_elements, "1");
  g.SetAttr("rod.element",
            rod.theory == BeamTheory::kTimoshenko ? "timoshenko" : "euler-bernoulli");
  g.SetAttr("rod.mass", rod.mass_kind == MassKind::kLumped ? "lumped" : "consistent");
  g.SetAttr("rod.dim", rod.dim == MeshDim::kSpatial ? "spatial" : "planar");
  g.SetAttr("rod.attachments", static_cast<double>(rod.attachments.size()), "1");
  for (size_t i = 0; i < rod.attachments.size(); ++i) {
    const RigidAttachment& a = rod.attachments[i];
    const std::string p = "attachment" + std::to_string(i) + ".";
    g.SetAttr(p + "name", a.name);
    g.SetAttr(p + "node", a.node, "1");
    g.SetAttr(p + "mass", a.mass, "kg");
    g.SetAttr(p + "inertia", a.inertia, "kg*m^2");
    g.SetAttr(p + "com_x", a.com_offset.x(), "m");
    g.SetAttr(p + "com_y", a.com_offset.y(), "m");
  }
}

RodSpec ReadRodSpec(const h5::Node& g) {
  RodSpec rod;
  rod.material.name = g.GetString("material.name");
  rod.material.source = g.GetString("material.source");
  rod.material.youngs_modulus = g.GetDouble("material.E");
  rod.material.poisson_ratio = g.GetDouble("material.nu");
  rod.material.density = g.GetDouble("material.rho");
  rod.material.yield_strength = g.GetDouble("material.yield");
  rod.section.thickness = g.GetDouble("rod.thickness");
  rod.section.height = g.GetDouble("rod.height");
  rod.section.in_plane = BendingAxisFromString("rod.bending", g.GetString("rod.bending"));
  rod.length = g.GetDouble("rod.length");
  rod.num_elements = static_cast<int>(g.GetDouble("rod.elements"));
  rod.theory = g.GetString("rod.element") == "timoshenko" ? BeamTheory::kTimoshenko
                                                          : BeamTheory::kEulerBernoulli;
  rod.mass_kind = g.GetString("rod.mass") == "lumped" ? MassKind::kLumped : MassKind::kConsistent;
  rod.dim = g.GetString("rod.dim") == "spatial" ? MeshDim::kSpatial : MeshDim::kPlanar;
  const int na = static_cast<int>(g.GetDouble("rod.attachments"));
  for (int i = 0; i < na; ++i) {
    const std::string p = "attachment" + std::to_string(i) + ".";
    RigidAttachment a;
    a.name = g.GetString(p + "name");
    a.node = static_cast<int>(g.GetDouble(p + "node"));
    a.mass = g.GetDouble(p + "mass");
    a.inertia = g.GetDouble(p + "inertia");
    a.com_offset = Vec2(g.GetDouble(p + "com_x"), g.GetDouble(p + "com_y"));
    rod.attachments.push_back(a);
  }
  return rod;
}

Vec IntsToVec(const std::vector<int>& v) {
  Vec out(v.size());
  for (size_t i = 0; i < v.size(); ++i) out[i] = v[i];
  return out;
}
std::vector<int> VecToInts(const Vec& v) {
  std::vector<int> out(v.size());
  for (int i = 0; i < v.size(); ++i) out[i] = static_cast<int>(std::lround(v[i]));
  return out;
}

}  // namespace

void WriteReducedRod(const ReducedRod& rr, const std::string& path) {
  const std::string tmp = path + ".tmp";
  {
    h5::Node f = h5::CreateFile(tmp);
    f.SetAttr("format", "flexrod reduced rod v3");
    WriteRodSpec(f, rr.rod);
    f.SetAttr("reduction.method", ToString(rr.reduction.method));
    f.SetAttr("reduction.modes", rr.reduction.num_modes, "1");
    f.SetAttr("reduction.cutoff", rr.reduction.cutoff_hz, "Hz");
    f.WriteVector("fixed_dofs", IntsToVec(rr.reduction.fixed_dofs), "1");
    f.WriteVector("interface_nodes", IntsToVec(rr.reduction.interface_nodes), "1");
    f.WriteMatrix("basis", rr.basis, "1", true);
    f.WriteMatrix("K", rr.K, "N/m (generalised)");
    f.WriteMatrix("M", rr.M, "kg (generalised)");
    f.SetAttr("reduction.axial_load_modes", rr.reduction.axial_load_modes ? 1.0 : 0.0, "1");
    f.SetAttr("element_axial_stiffness", rr.element_axial_stiffness, "N/m");
    f.WriteMatrix("element_Kg", Mat(rr.element_Kg), "1/m per N of axial tension");
    f.WriteVector("frequencies", rr.frequencies_hz, "Hz");
    const h5::Node in = f.CreateGroup("inertia");
    in.SetAttr("mass", rr.inertia.mass, "kg");
    in.SetAttr("J0", rr.inertia.J0, "kg*m^2");
    in.WriteVector("S0", rr.inertia.S0, "kg*m");
    in.WriteMatrix("S", rr.inertia.S, "kg");
    in.WriteVector("I1", rr.inertia.I1, "kg*m");
    in.WriteVector("Ibar", rr.inertia.Ibar, "kg*m");
    in.WriteMatrix("Mff", rr.inertia.Mff, "kg");
    in.WriteMatrix("Stilde", rr.inertia.Stilde, "kg");
  }
  if (std::rename(tmp.c_str(), path.c_str()) != 0) {
    throw NumericalError("could not rename " + tmp + " to " + path);
  }
}

ReducedRod ReadReducedRod(const std::string& path) {
  const h5::Node f = h5::OpenFile(path);
  if (!f.HasAttr("format") || f.GetString("format") != "flexrod reduced rod v3") {
    throw InputError("reduced rod file", path, "is not a flexrod reduced rod (format v3)");
  }
  ReducedRod rr;
  rr.rod = ReadRodSpec(f);
  rr.reduction.method =
      ReductionMethodFromString("reduction.method", f.GetString("reduction.method"));
  rr.reduction.num_modes = static_cast<int>(f.GetDouble("reduction.modes"));
  rr.reduction.cutoff_hz = f.GetDouble("reduction.cutoff");
  rr.reduction.fixed_dofs = VecToInts(f.ReadVector("fixed_dofs"));
  rr.reduction.interface_nodes = VecToInts(f.ReadVector("interface_nodes"));
  rr.basis = f.ReadMatrix("basis");
  rr.K = f.ReadMatrix("K");
  rr.M = f.ReadMatrix("M");
  rr.reduction.axial_load_modes = f.GetDouble("reduction.axial_load_modes") != 0.0;
  rr.element_axial_stiffness = f.GetDouble("element_axial_stiffness");
  rr.element_Kg = f.ReadMatrix("element_Kg");
  rr.frequencies_hz = f.ReadVector("frequencies");
  const h5::Node in = f.OpenGroup("inertia");
  rr.inertia.mass = in.GetDouble("mass");
  rr.inertia.J0 = in.GetDouble("J0");
  rr.inertia.S0 = in.ReadVector("S0");
  rr.inertia.S = in.ReadMatrix("S");
  rr.inertia.I1 = in.ReadVector("I1");
  rr.inertia.Ibar = in.ReadVector("Ibar");
  rr.inertia.Mff = in.ReadMatrix("Mff");
  rr.inertia.Stilde = in.ReadMatrix("Stilde");
  if (rr.rod.dim == MeshDim::kPlanar) rr.nodes = PlanarNodeShapes(rr.rod, rr.basis);
  return rr;
}

}  // namespace flexrod::fem
