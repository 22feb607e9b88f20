// fem/exact_beam.cc — the planar Simo–Reissner element kernel with its analytic tangents, the
// lumped node inertia, the static Newton solver with load stepping and the linearised
// frequencies about the straight reference.
// SPDX-License-Identifier: GPL-3.0-or-later
#include "fem/exact_beam.h"

#include <Eigen/SparseCholesky>
#include <algorithm>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"
#include "fem/eigensolver.h"

namespace flexrod::fem {
namespace {

constexpr int kDofsPerNode = 3;  // x, y, θ

// Static solver (see SolveExactBeamStatic). Residuals are scaled by a force scale
// F_s = max(EI/L², the largest applied force, the largest applied moment / L) for forces and
// F_s·L for moments. Their round-off floor is not small: the axial force EA ε comes from
// node coordinates differenced over one element, so it carries ~EA·ε_mach·(L/L0) ≈ 1e-7 N for
// the rig rod at 40 elements, ~1e-9 F_s. Hence two ways to converge:
// * the scaled residual is below kResidualTol, or
// * a plain Newton update (positive definite tangent, no shift) is shorter than
//   kIncrementTol (translations over L, rotations in rad) and the scaled residual is below
//   kLooseResidualTol: near a regular solution the Newton update is the remaining error, and
//   the round-off floor of the update (~1e-10 L for a cantilever) lies below kIncrementTol.
constexpr double kResidualTol = 1e-10;
constexpr double kIncrementTol = 1e-9;
constexpr double kLooseResidualTol = 1e-6;
constexpr int kMaxNewtonIterations = 100;
constexpr int kMaxLineSearchHalvings = 40;
constexpr double kArmijo = 1e-4;  // sufficient-decrease constant (Nocedal & Wright §3.1)
/// Largest rotation and translation (fraction of the rod length) of one Newton update; longer
/// steps are scaled down before the line search, since a linearisation about θ says nothing
/// useful a radian away.
constexpr double kMaxRotationStep = 0.5;      // [rad]
constexpr double kMaxTranslationStep = 0.25;  // [-] of rod.length
/// Levenberg-type shift μ·diag(K) tried when K is not positive definite: μ = 1e-10, 1e-9, …
constexpr double kFirstShift = 1e-10;
constexpr double kShiftGrowth = 10.0;
constexpr double kMaxShift = 1e4;

std::string PairKey(const std::string& list, size_t i, const char* field) {
  return "exact_beam." + list + "[" + std::to_string(i) + "]." + field;
}

void ValidateNodeDofs(const std::vector<std::pair<int, int>>& fixed, int num_nodes) {
  for (size_t i = 0; i < fixed.size(); ++i) {
    const auto [node, dof] = fixed[i];
    if (node < 0 || node >= num_nodes)
      throw InputError(PairKey("fixed", i, "node"), std::to_string(node),
                       "must be a node index in [0, " + std::to_string(num_nodes - 1) + "]");
    if (dof < 0 || dof >= kDofsPerNode)
      throw InputError(PairKey("fixed", i, "dof"), std::to_string(dof),
                       "must be 0 (x), 1 (y) or 2 (θ)");
  }
}

/// Fixed dof indices (node·3 + dof), sorted, unique.
std::vector<int> FixedDofIndices(const std::vector<std::pair<int, int>>& fixed) {
  std::vector<int> out;
  out.reserve(fixed.size());
  for (const auto& [node, dof] : fixed) out.push_back(node * kDofsPerNode + dof);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

/// Reference dofs [x, y, θ] of every node: straight along x plus the optional offsets.
Vec ReferenceDofs(const RodSpec& rod, const std::vector<Vec2>& offset) {
  Vec q = Vec::Zero(rod.num_nodes() * kDofsPerNode);
  for (int k = 0; k < rod.num_nodes(); ++k) {
    q[kDofsPerNode * k] = rod.node_x(k);
    if (!offset.empty()) {
      q[kDofsPerNode * k] += offset[static_cast<size_t>(k)].x();
      q[kDofsPerNode * k + 1] += offset[static_cast<size_t>(k)].y();
    }
  }
  return q;
}

/// The element dofs d (6) of element e in the node-major global vector.
Vec6 ElementDofs(const Vec& q, int e) { return q.segment<6>(kDofsPerNode * e); }

/// Internal forces (and, if K is non-null, the tangent's triplets) of the whole rod at rest
/// (ḋ = 0); returns the elastic energy.
double AssembleInternal(const ReissnerStiffness& s, double L0,
                        const std::vector<ReissnerStrains>& reference, const Vec& q, Vec* f,
                        std::vector<Triplet>* K) {
  f->setZero(q.size());
  if (K) K->clear();
  double energy = 0.0;
  const Vec6 at_rest = Vec6::Zero();
  Vec6 fe;
  Mat6 Ke;
  for (int e = 0; e < static_cast<int>(reference.size()); ++e) {
    energy += CalcReissnerElement(s, L0, 0.0, reference[static_cast<size_t>(e)], ElementDofs(q, e),
                                  at_rest, &fe, K ? &Ke : nullptr, nullptr);
    const int first = kDofsPerNode * e;
    f->segment<6>(first) += fe;
    if (K) {
      for (int c = 0; c < 6; ++c)
        for (int r = 0; r < 6; ++r) K->emplace_back(first + r, first + c, Ke(r, c));
    }
  }
  return energy;
}

}  // namespace

ReissnerStiffness ReissnerStiffnessOf(const Material& material, const RectSection& section) {
  material.Validate("rod");
  section.Validate("rod");
  const double A = section.area();
  return ReissnerStiffness{
      .EA = material.youngs_modulus * A,
      .GA = RectSection::CowperShearFactor(material.poisson_ratio) * material.shear_modulus() * A,
      .EI = material.youngs_modulus * section.inertia_in_plane()};
}

ReissnerStrains CalcReissnerStrains(double L0, const Vec6& d) {
  const double inv_L0 = 1.0 / L0;
  const double px = (d[3] - d[0]) * inv_L0, py = (d[4] - d[1]) * inv_L0;  // x'
  const double theta_m = 0.5 * (d[2] + d[5]);
  const double c = std::cos(theta_m), s = std::sin(theta_m);
  // Γ = R(θ_m)ᵀ x' − e1
  return ReissnerStrains{.axial = c * px + s * py - 1.0,
                         .shear = -s * px + c * py,
                         .curvature = (d[5] - d[2]) * inv_L0};
}

double CalcReissnerElement(const ReissnerStiffness& s, double L0, double beta, const Vec6& d,
                           const Vec6& d_dot, Vec6* f, Mat6* K, Mat6* C) {
  return CalcReissnerElement(s, L0, beta, ReissnerStrains{0.0, 0.0, 0.0}, d, d_dot, f, K, C);
}

// Derivatives. With x' = (x_b − x_a)/L0 = (p_x, p_y), θ_m = (θ_a + θ_b)/2, c = cos θ_m,
// s = sin θ_m:
//   1 + ε = c p_x + s p_y,  γ = −s p_x + c p_y,
//   ∂ε/∂θ_m = γ,  ∂γ/∂θ_m = −(1 + ε),  ∂(ε, γ)/∂x' = rows (c, s) and (−s, c).
// Strain gradients B = ∂(ε, γ, κ)/∂d (rows over d = [x_a, y_a, θ_a, x_b, y_b, θ_b]):
//   B_ε = [−c/L0, −s/L0, γ/2, c/L0, s/L0, γ/2]
//   B_γ = [ s/L0, −c/L0, −(1+ε)/2, −s/L0, c/L0, −(1+ε)/2]
//   B_κ = [0, 0, −1/L0, 0, 0, 1/L0]
// Hessians (κ is linear): with t = ∂θ_m/∂d = [0, 0, ½, 0, 0, ½] and
//   g_ε = ∂²ε/∂d∂θ_m restricted to the translations = [s/L0, −c/L0, 0, −s/L0, c/L0, 0],
//   g_γ = [c/L0, s/L0, 0, −c/L0, −s/L0, 0],
//   H_ε = g_ε tᵀ + t g_εᵀ − (1+ε) t tᵀ,   H_γ = g_γ tᵀ + t g_γᵀ − γ t tᵀ.
// Resultants S_i (ε_i − ε_i0 + β ε̇_i) with ε̇_i = B_i·ḋ give f = L0 Σ_i S_i B_i and
//   K = L0 Σ_i [ k_i B_i (B_i + β H_i ḋ)ᵀ + S_i H_i ],   C = L0 β Σ_i k_i B_i B_iᵀ,
// k_i ∈ {EA, GA, EI} (H_i symmetric, so ∂(B_i·ḋ)/∂d = H_i ḋ).
double CalcReissnerElement(const ReissnerStiffness& s, double L0, double beta,
                           const ReissnerStrains& reference, const Vec6& d, const Vec6& d_dot,
                           Vec6* f, Mat6* K, Mat6* C) {
  FLEXROD_ASSERT(L0 > 0.0 && beta >= 0.0);
  const double inv_L0 = 1.0 / L0;
  const double px = (d[3] - d[0]) * inv_L0, py = (d[4] - d[1]) * inv_L0;
  const double theta_m = 0.5 * (d[2] + d[5]);
  const double c = std::cos(theta_m), sn = std::sin(theta_m);
  const double stretch = c * px + sn * py;  // 1 + ε
  const double shear = -sn * px + c * py;   // γ
  const double curvature = (d[5] - d[2]) * inv_L0;
  const double dev_axial = stretch - 1.0 - reference.axial;
  const double dev_shear = shear - reference.shear;
  const double dev_curvature = curvature - reference.curvature;
  const double energy = 0.5 * L0 *
                        (s.EA * dev_axial * dev_axial + s.GA * dev_shear * dev_shear +
                         s.EI * dev_curvature * dev_curvature);
  if (!f && !K && !C) return energy;

  const double cL = c * inv_L0, sL = sn * inv_L0;
  Vec6 B_axial, B_shear, B_curv;
  B_axial << -cL, -sL, 0.5 * shear, cL, sL, 0.5 * shear;
  B_shear << sL, -cL, -0.5 * stretch, -sL, cL, -0.5 * stretch;
  B_curv << 0.0, 0.0, -inv_L0, 0.0, 0.0, inv_L0;

  const double N = s.EA * (dev_axial + beta * B_axial.dot(d_dot));
  const double Q = s.GA * (dev_shear + beta * B_shear.dot(d_dot));
  const double M = s.EI * (dev_curvature + beta * B_curv.dot(d_dot));
  if (f) *f = L0 * (N * B_axial + Q * B_shear + M * B_curv);

  if (K) {
    Vec6 t, g_axial, g_shear;
    t << 0.0, 0.0, 0.5, 0.0, 0.0, 0.5;
    g_axial << sL, -cL, 0.0, -sL, cL, 0.0;
    g_shear << cL, sL, 0.0, -cL, -sL, 0.0;
    const Mat6 H_axial =
        g_axial * t.transpose() + t * g_axial.transpose() - stretch * (t * t.transpose());
    const Mat6 H_shear =
        g_shear * t.transpose() + t * g_shear.transpose() - shear * (t * t.transpose());
    Vec6 row_axial = B_axial, row_shear = B_shear;  // ∂(ε + β ε̇)/∂d, ∂(γ + β γ̇)/∂d
    if (beta != 0.0) {
      row_axial.noalias() += beta * (H_axial * d_dot);
      row_shear.noalias() += beta * (H_shear * d_dot);
    }
    K->noalias() =
        L0 * (s.EA * B_axial * row_axial.transpose() + s.GA * B_shear * row_shear.transpose() +
              s.EI * B_curv * B_curv.transpose() + N * H_axial + Q * H_shear);
  }
  if (C) {
    C->noalias() =
        (L0 * beta) * (s.EA * B_axial * B_axial.transpose() + s.GA * B_shear * B_shear.transpose() +
                       s.EI * B_curv * B_curv.transpose());
  }
  return energy;
}

std::vector<NodeInertia> ExactBeamNodeInertia(const RodSpec& rod) {
  rod.Validate();
  const double rho = rod.material.density;
  const double rho_A = rho * rod.section.area();
  const double rho_I = rho * rod.section.inertia_in_plane();
  const double h = rod.element_length();
  const int n = rod.num_nodes();
  std::vector<NodeInertia> nodes(static_cast<size_t>(n));
  for (int k = 0; k < n; ++k) {
    // Interior nodes carry [x_k − h/2, x_k + h/2] (centroid at the node); the end nodes the
    // half segment on the rod side, centroid h/4 inside. With one element both nodes are ends.
    double len = h, com_x = 0.0;
    if (k == 0) {
      len = 0.5 * h, com_x = 0.25 * h;
    } else if (k == n - 1) {
      len = 0.5 * h, com_x = -0.25 * h;
    }
    const double m = rho_A * len;
    nodes[static_cast<size_t>(k)] = NodeInertia{
        .mass = m, .com = Vec2(com_x, 0.0), .inertia = m * len * len / 12.0 + rho_I * len};
  }
  for (const RigidAttachment& a : rod.attachments) {
    NodeInertia& node = nodes[static_cast<size_t>(a.node)];
    if (a.mass == 0.0) {  // a massless attachment adds only its inertia
      node.inertia += a.inertia;
      continue;
    }
    // Combined body: mass-weighted centre, inertias moved to it (parallel-axis theorem).
    const double m = node.mass + a.mass;
    const Vec2 com = (node.mass * node.com + a.mass * a.com_offset) / m;
    node.inertia = node.inertia + node.mass * (node.com - com).squaredNorm() + a.inertia +
                   a.mass * (a.com_offset - com).squaredNorm();
    node.mass = m;
    node.com = com;
  }
  return nodes;
}

Eigen::Matrix3d NodeMassMatrix(const NodeInertia& node) {
  const double m = node.mass, cx = node.com.x(), cy = node.com.y();
  Eigen::Matrix3d M;
  M << m, 0.0, -m * cy,  //
      0.0, m, m * cx,    //
      -m * cy, m * cx, node.inertia + m * (cx * cx + cy * cy);
  return M;
}

void ExactBeamStaticProblem::Validate() const {
  rod.Validate();
  const int n = rod.num_nodes();
  if (!initial_offset.empty()) {
    if (static_cast<int>(initial_offset.size()) != n)
      throw InputError("exact_beam.initial_offset",
                       std::to_string(initial_offset.size()) + " entries",
                       "must be empty or one per node (" + std::to_string(n) + ")");
    for (size_t k = 0; k < initial_offset.size(); ++k) {
      if (!initial_offset[k].allFinite())
        throw InputError("exact_beam.initial_offset[" + std::to_string(k) + "]",
                         "(" + FormatValue(initial_offset[k].x()) + ", " +
                             FormatValue(initial_offset[k].y()) + ") m",
                         "must be finite");
    }
  }
  ValidateNodeDofs(fixed, n);
  for (size_t i = 0; i < loads.size(); ++i) {
    const auto& [node, load] = loads[i];
    if (node < 0 || node >= n)
      throw InputError(PairKey("loads", i, "node"), std::to_string(node),
                       "must be a node index in [0, " + std::to_string(n - 1) + "]");
    if (!load.allFinite())
      throw InputError(PairKey("loads", i, "value"),
                       "(" + FormatValue(load.x()) + " N, " + FormatValue(load.y()) + " N, " +
                           FormatValue(load.z()) + " N m)",
                       "must be finite");
  }
  if (load_steps < 1)
    throw InputError("exact_beam.load_steps", std::to_string(load_steps), "must be >= 1");
}

namespace {

/// Newton's method at one load level of SolveExactBeamStatic (see there for the method): the
/// problem's fixed data (reference, dead load, free dofs, residual scales) and the work
/// vectors and factorisation that every iteration reuses.
class StaticNewton {
 public:
  /// `p` validated; `load_factor` finite.
  StaticNewton(const ExactBeamStaticProblem& p, double load_factor);

  /// Reference dofs [x, y, θ] of every node [m, m, rad].
  const Vec& reference_dofs() const { return q_ref_; }
  /// Newton updates over all calls so far.
  int total_iterations() const { return total_iterations_; }

  /// Moves *q to the equilibrium at λ F (load step `step`, for the messages). Throws
  /// NumericalError if no shifted tangent is positive definite, if the line search finds no
  /// decrease, or after kMaxNewtonIterations updates.
  void SolveStep(int step, double lambda, Vec* q);

 private:
  /// Π(x) = U(x) − λ Fᵀ(x − q_ref) [J]; *magnitude = |U| + |W|, the size of its terms.
  double Potential(const Vec& x, double lambda, double* magnitude) const;
  /// max over the free dofs of |res_i| / (F_s or F_s L).
  double ScaledResidualNorm(const Vec& res) const;
  /// Solves (K + μ D) Δ = −r on the free dofs from triplets_ and r_ into delta_free_ and
  /// delta_ (zero on the fixed dofs), with the smallest tried μ whose factorisation succeeds;
  /// returns μ (0: plain Newton).
  double SolveShiftedUpdate(double lambda, int iteration);
  /// Limits the update to kMaxRotationStep and kMaxTranslationStep, then halves it until Π
  /// satisfies the Armijo condition; moves *q and returns true, or returns false.
  bool LineSearch(double lambda, double shift, double max_rotation, double max_translation,
                  Vec* q) const;

  double load_factor_;
  int load_steps_;
  double rod_length_;  // [m]
  ReissnerStiffness stiffness_;
  double L0_;  // element length [m]
  Vec q_ref_;
  std::vector<ReissnerStrains> reference_;
  Vec F_;  // dead loads times load_factor [N, N, N m per node]
  std::vector<int> free_;
  Vec inv_scale_;  // 1/F_s for forces, 1/(F_s L) for moments
  Vec f_int_, r_, r_free_, delta_free_, delta_;
  std::vector<Triplet> triplets_;
  SpMat K_full_;
  Eigen::SimplicialLLT<SpMat, Eigen::Lower> llt_;
  int total_iterations_{0};
};

StaticNewton::StaticNewton(const ExactBeamStaticProblem& p, double load_factor)
    : load_factor_(load_factor),
      load_steps_(p.load_steps),
      rod_length_(p.rod.length),
      stiffness_(ReissnerStiffnessOf(p.rod.material, p.rod.section)),
      L0_(p.rod.element_length()) {
  const RodSpec& rod = p.rod;
  const int n_dofs = rod.num_nodes() * kDofsPerNode;

  q_ref_ = ReferenceDofs(rod, p.initial_offset);
  reference_.resize(static_cast<size_t>(rod.num_elements));
  for (int e = 0; e < rod.num_elements; ++e)
    reference_[static_cast<size_t>(e)] = CalcReissnerStrains(L0_, ElementDofs(q_ref_, e));

  F_ = Vec::Zero(n_dofs);
  for (const auto& [node, load] : p.loads) F_.segment<3>(kDofsPerNode * node) += load;
  F_ *= load_factor;

  free_ = FreeDofs(n_dofs, FixedDofIndices(p.fixed));
  const int n_free = static_cast<int>(free_.size());

  // Residual scales: forces by F_s, moments by F_s L.
  double force_scale = stiffness_.EI / (rod.length * rod.length);
  for (int i = 0; i < n_dofs; ++i) {
    const bool is_moment = i % kDofsPerNode == 2;
    force_scale = std::max(force_scale, std::abs(F_[i]) / (is_moment ? rod.length : 1.0));
  }
  inv_scale_.resize(n_dofs);
  for (int i = 0; i < n_dofs; ++i)
    inv_scale_[i] = 1.0 / (i % kDofsPerNode == 2 ? force_scale * rod.length : force_scale);

  r_.resize(n_dofs);
  r_free_.resize(n_free);
  delta_.resize(n_dofs);
  K_full_.resize(n_dofs, n_dofs);
}

double StaticNewton::Potential(const Vec& x, double lambda, double* magnitude) const {
  Vec f_unused;
  const double U = AssembleInternal(stiffness_, L0_, reference_, x, &f_unused, nullptr);
  const double W = lambda * F_.dot(x - q_ref_);
  *magnitude = std::abs(U) + std::abs(W);
  return U - W;
}

double StaticNewton::ScaledResidualNorm(const Vec& res) const {
  double m = 0.0;
  for (int i : free_) m = std::max(m, std::abs(res[i]) * inv_scale_[i]);
  return m;
}

void StaticNewton::SolveStep(int step, double lambda, Vec* q) {
  const int n_dofs = static_cast<int>(q->size());
  double residual_norm = 0.0;
  for (int iteration = 0; iteration <= kMaxNewtonIterations; ++iteration) {
    AssembleInternal(stiffness_, L0_, reference_, *q, &f_int_, &triplets_);
    r_ = f_int_ - lambda * F_;
    residual_norm = ScaledResidualNorm(r_);
    if (residual_norm <= kResidualTol) return;
    if (iteration == kMaxNewtonIterations) break;

    const double shift = SolveShiftedUpdate(lambda, iteration);
    double max_rotation = 0.0, max_translation = 0.0;
    for (int i = 0; i < n_dofs; ++i) {
      if (i % kDofsPerNode == 2)
        max_rotation = std::max(max_rotation, std::abs(delta_[i]));
      else
        max_translation = std::max(max_translation, std::abs(delta_[i]));
    }
    if (shift == 0.0 && residual_norm <= kLooseResidualTol &&
        std::max(max_rotation, max_translation / rod_length_) <= kIncrementTol) {
      *q += delta_;  // the last, tiny Newton update
      ++total_iterations_;
      return;
    }
    const bool accepted = LineSearch(lambda, shift, max_rotation, max_translation, q);
    ++total_iterations_;
    if (!accepted) {
      throw NumericalError(
          "SolveExactBeamStatic: the line search found no decrease of the potential at load "
          "factor " +
          FormatValue(lambda * load_factor_) + " (iteration " + std::to_string(iteration) +
          ", scaled residual " + FormatValue(residual_norm) +
          "); try more load_steps or check the supports");
    }
  }
  throw NumericalError("SolveExactBeamStatic: no convergence at load factor " +
                       FormatValue(lambda * load_factor_) + " (step " + std::to_string(step) +
                       " of " + std::to_string(load_steps_) + ", " +
                       std::to_string(kMaxNewtonIterations) + " iterations, scaled residual " +
                       FormatValue(residual_norm) + " > " + FormatValue(kResidualTol) +
                       "); try more load_steps, or check that the supports prevent rigid motion");
}

double StaticNewton::SolveShiftedUpdate(double lambda, int iteration) {
  const int n_free = static_cast<int>(free_.size());
  K_full_.setFromTriplets(triplets_.begin(), triplets_.end());
  SpMat K_free = Restrict(K_full_, free_);
  for (int i = 0; i < n_free; ++i) r_free_[i] = r_[free_[static_cast<size_t>(i)]];
  const Vec diag = K_free.diagonal().cwiseAbs().cwiseMax(
      std::numeric_limits<double>::min());  // zero only for a dof with no stiffness at all
  double shift = 0.0;
  SpMat A = K_free;
  llt_.analyzePattern(A);
  llt_.factorize(A);
  while (llt_.info() != Eigen::Success) {
    shift = shift == 0.0 ? kFirstShift : shift * kShiftGrowth;
    if (shift > kMaxShift)
      throw NumericalError(
          "SolveExactBeamStatic: no positive definite shifted tangent at load factor " +
          FormatValue(lambda * load_factor_) + " (iteration " + std::to_string(iteration) +
          "); is the rod free to move as a rigid body? fix enough dofs");
    A = K_free;
    for (int i = 0; i < n_free; ++i) A.coeffRef(i, i) += shift * diag[i];
    llt_.factorize(A);
  }
  delta_free_ = llt_.solve(-r_free_);
  delta_.setZero();
  for (int i = 0; i < n_free; ++i) delta_[free_[static_cast<size_t>(i)]] = delta_free_[i];
  return shift;
}

bool StaticNewton::LineSearch(double lambda, double shift, double max_rotation,
                              double max_translation, Vec* q) const {
  double step_length = 1.0;
  if (max_rotation > kMaxRotationStep) step_length = kMaxRotationStep / max_rotation;
  if (max_translation * step_length > kMaxTranslationStep * rod_length_)
    step_length = kMaxTranslationStep * rod_length_ / max_translation;
  const double slope = r_free_.dot(delta_free_);  // dΠ/dt at t = 0, < 0
  double magnitude = 0.0;
  const double pi_0 = Potential(*q, lambda, &magnitude);
  for (int halving = 0; halving <= kMaxLineSearchHalvings; ++halving) {
    const Vec trial = *q + step_length * delta_;
    double trial_magnitude = 0.0;
    const double pi_t = Potential(trial, lambda, &trial_magnitude);
    // Round-off allowance: Π is a sum of terms of size `magnitude`.
    const double allowance =
        64.0 * std::numeric_limits<double>::epsilon() * (magnitude + trial_magnitude);
    if (std::isfinite(pi_t) &&
        pi_t <= pi_0 + kArmijo * step_length * slope + (shift == 0.0 ? allowance : 0.0)) {
      *q = trial;
      return true;
    }
    step_length *= 0.5;
  }
  return false;
}

}  // namespace

// Newton's method for the total potential Π(q) = Σ_e U_e(q) − λ Fᵀ(q − q_ref) (dead loads are
// conservative; a dead moment does work M Δθ in the plane). The residual is r = ∂Π/∂q = f − λF
// and the tangent ∂²Π/∂q² = K (symmetric at rest). Each update solves (K + μ D) Δ = −r on the
// free dofs with D = diag(K) and μ = 0 whenever K is positive definite (plain Newton, quadratic
// convergence near a stable equilibrium); otherwise μ grows until the Cholesky factorisation
// succeeds (a Levenberg-type modified Newton, Nocedal & Wright §3.4), so Δ is a descent
// direction. Backtracking on Π with the Armijo condition then makes every accepted update
// lower the potential, which keeps the iteration away from unstable equilibria.
ExactBeamStaticSolution SolveExactBeamStatic(const ExactBeamStaticProblem& p, double load_factor) {
  p.Validate();
  if (!std::isfinite(load_factor))
    throw InputError("exact_beam.load_factor", FormatValue(load_factor), "must be finite");
  StaticNewton newton(p, load_factor);
  Vec q = newton.reference_dofs();
  Vec q_previous = q;  // the equilibrium of the step before, for the predictor
  for (int step = 1; step <= p.load_steps; ++step) {
    const double lambda = static_cast<double>(step) / p.load_steps;  // of F (load_factor in F)
    // Predictor: linear extrapolation 2 q_n − q_{n−1} along the path (equal load increments).
    // It follows the rotation of the elements, so it roughly halves the iterations against a
    // restart from q_n, whose first linearised update stretches the rotating elements (large
    // axial forces that take several iterations to relax). Its chord stretch can raise the
    // potential above that of q_n, but the line-searched iteration is safe from any start.
    if (step > 1) {
      const Vec extrapolated = 2.0 * q - q_previous;
      q_previous = q;
      q = extrapolated;
    }
    newton.SolveStep(step, lambda, &q);
  }

  ExactBeamStaticSolution out;
  out.nodes.resize(static_cast<size_t>(p.rod.num_nodes()));
  for (int k = 0; k < p.rod.num_nodes(); ++k)
    out.nodes[static_cast<size_t>(k)] = q.segment<3>(kDofsPerNode * k);
  out.newton_iterations = newton.total_iterations();
  return out;
}

std::vector<double> ExactBeamFrequencies(const RodSpec& rod,
                                         const std::vector<std::pair<int, int>>& fixed, int count) {
  rod.Validate();
  ValidateNodeDofs(fixed, rod.num_nodes());
  const int n_dofs = rod.num_nodes() * kDofsPerNode;
  const std::vector<int> free = FreeDofs(n_dofs, FixedDofIndices(fixed));
  if (count < 1 || count > static_cast<int>(free.size()))
    throw InputError("exact_beam.frequency_count", std::to_string(count),
                     "must be in [1, " + std::to_string(free.size()) + "] (the free dofs)");

  // Tangent stiffness at the straight, unloaded reference (no geometric terms: N = Q = M = 0).
  const ReissnerStiffness stiffness = ReissnerStiffnessOf(rod.material, rod.section);
  const double L0 = rod.element_length();
  const std::vector<ReissnerStrains> reference(static_cast<size_t>(rod.num_elements),
                                               ReissnerStrains{0.0, 0.0, 0.0});
  std::vector<Triplet> k_triplets, m_triplets;
  Vec f_unused;
  AssembleInternal(stiffness, L0, reference, ReferenceDofs(rod, {}), &f_unused, &k_triplets);
  const std::vector<NodeInertia> inertia = ExactBeamNodeInertia(rod);
  for (int k = 0; k < rod.num_nodes(); ++k) {
    const Eigen::Matrix3d block = NodeMassMatrix(inertia[static_cast<size_t>(k)]);
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r)
        if (block(r, c) != 0.0)
          m_triplets.emplace_back(kDofsPerNode * k + r, kDofsPerNode * k + c, block(r, c));
  }
  SpMat K(n_dofs, n_dofs), M(n_dofs, n_dofs);
  K.setFromTriplets(k_triplets.begin(), k_triplets.end());
  M.setFromTriplets(m_triplets.begin(), m_triplets.end());
  EigenRequest request;
  request.num_modes = count;
  const EigenResult modes = SolveEigenArpack(Restrict(K, free), Restrict(M, free), request);
  const Vec hz = modes.frequencies_hz();
  return std::vector<double>(hz.data(), hz.data() + hz.size());
}

}  // namespace flexrod::fem
