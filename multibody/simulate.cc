// multibody/simulate.cc — consistent initial conditions, the IDA adapter, the options and
// status of a run (its loop: multibody/simulation_loop.cc; sample views: multibody/sample_view.cc).
// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/simulate.h"

#include <Eigen/LU>
#include <Eigen/QR>
#include <algorithm>
#include <cmath>
#include <limits>
#include <sstream>

#include "common/error.h"
#include "multibody/simulate_internal.h"

namespace flexrod::multibody {
namespace {

std::vector<int> Complement(int n, const std::vector<bool>& fixed) {
  std::vector<int> out;
  for (int i = 0; i < n; ++i)
    if (!fixed[i]) out.push_back(i);
  return out;
}

Mat Columns(const Mat& A, const std::vector<int>& cols) {
  Mat out(A.rows(), static_cast<int>(cols.size()));
  for (size_t k = 0; k < cols.size(); ++k) out.col(static_cast<int>(k)) = A.col(cols[k]);
  return out;
}

constexpr double kRestartPositionTolerance = 1e-12;  // |g|∞ [m or rad] per unit of |p|∞
constexpr int kRestartNewtonIterations = 10;

/// Newton on g(t, p) = 0 with minimum-norm steps over the coordinates `free` (the others held),
/// to |g|∞ <= tol. NumericalError if it does not converge, or if G over `free` has a rank below
/// the number of constraints (redundant constraints, a dead centre, too many held coordinates).
void SolvePositionConstraints(const Mechanism& model, RunData* data, double t,
                              const std::vector<int>& free, double tol, int max_iterations,
                              const std::string& context, Vec* p) {
  const int nc = model.num_constraints();
  if (nc == 0) return;
  Vec g, gt;
  Mat G;
  for (int it = 0; it <= max_iterations; ++it) {
    CalcConstraints(model, data, t, *p, &g);
    const bool met = g.lpNorm<Eigen::Infinity>() <= tol;
    if (!met && it == max_iterations) break;
    CalcConstraintJacobian(model, data, t, *p, &G, &gt);
    Eigen::CompleteOrthogonalDecomposition<Mat> cod(Columns(G, free));
    if (cod.rank() < nc) {
      throw NumericalError(context +
                           ": the constraint Jacobian over the free coordinates has rank " +
                           std::to_string(cod.rank()) + " < " + std::to_string(nc) +
                           " constraints: redundant constraints, a dead-centre configuration, "
                           "or too many fixed coordinates");
    }
    if (met) return;
    const Vec dx = cod.solve(-g);  // minimum-norm Newton step over the free coordinates
    for (size_t k = 0; k < free.size(); ++k) (*p)(free[k]) += dx(static_cast<int>(k));
  }
  const int worst = WorstIndex(g);
  throw NumericalError(context + ": position Newton did not converge in " +
                       std::to_string(max_iterations) +
                       " iterations; |g| = " + FormatValue(g.lpNorm<Eigen::Infinity>()) + " at " +
                       model.VariableName(model.lambda_offset() + worst) +
                       " (check the initial guess and the assembly)");
}

/// The minimum-norm change of v over the coordinates `free` that meets G v + g_t = 0 at p.
/// NumericalError if the held velocities make that impossible.
void SolveVelocityConstraints(const Mechanism& model, RunData* data, double t, const Vec& p,
                              const std::vector<int>& free, const std::string& context, Vec* v) {
  if (model.num_constraints() == 0) return;
  Mat G;
  Vec gt;
  CalcConstraintJacobian(model, data, t, p, &G, &gt);
  const Vec rhs = -gt - G * *v;
  Eigen::CompleteOrthogonalDecomposition<Mat> cod(Columns(G, free));
  const Vec dv = cod.solve(rhs);
  for (size_t k = 0; k < free.size(); ++k) (*v)(free[k]) += dv(static_cast<int>(k));
  const double err = (G * *v + gt).lpNorm<Eigen::Infinity>();
  if (!(err <= 1e-9 * std::max(1.0, v->lpNorm<Eigen::Infinity>()))) {
    throw NumericalError(
        context + ": velocity constraints cannot be met with the fixed velocities (residual " +
        FormatValue(err) + ")");
  }
}

void InitializeElements(const Mechanism& model, RunData* data, Vec* y) {
  UpdateKinematics(model, data, y->data());
  std::fill(data->element_memory.begin(), data->element_memory.end(), 0.0);
  y->tail(model.size() - model.z_offset()).setZero();
  for (const ElementSlot& e : model.elements()) {
    e.element->Initialize(data->markers[e.marker_i].kin, data->markers[e.marker_j].kin,
                          y->data() + model.z_offset() + e.state_offset,
                          data->element_memory.data() + e.memory_offset);
  }
}

}  // namespace

int WorstIndex(const Vec& r) {
  int worst = -1;
  double value = -1.0;
  for (int i = 0; i < r.size(); ++i) {
    const double a = std::isfinite(r(i)) ? std::abs(r(i)) : std::numeric_limits<double>::infinity();
    if (a > value) {
      value = a;
      worst = i;
    }
  }
  return worst;
}

double InitialEnergy(const Mechanism& model, RunData* data, const Vec& y) {
  UpdateKinematics(model, data, y.data());
  const double saved = data->reference_energy;
  data->reference_energy = 0.0;
  const double e = CalcEnergies(model, data, y.data()).total();
  data->reference_energy = saved;
  return e;
}

// ---- initial conditions -------------------------------------------------------------------------
void InitialConditionSpec::Validate(const Mechanism& model) const {
  const int np = model.num_coordinates();
  Require(coordinates.size() == 0 || coordinates.size() == np, "initial.coordinates",
          static_cast<double>(coordinates.size()),
          "must be empty or have one entry per coordinate");
  Require(velocities.size() == 0 || velocities.size() == np, "initial.velocities",
          static_cast<double>(velocities.size()), "must be empty or have one entry per coordinate");
  Require(coordinates.allFinite() && velocities.allFinite(), "initial", 0.0,
          "coordinates and velocities must be finite");
  for (int i : fixed_coordinates) {
    Require(i >= 0 && i < np, "initial.fixed_coordinates", i, "must be a coordinate index");
  }
  for (int i : fixed_velocities) {
    Require(i >= 0 && i < np, "initial.fixed_velocities", i, "must be a coordinate index");
  }
  RequirePositive("initial.position_tolerance", position_tolerance);
  Require(max_newton_iterations >= 1, "initial.max_newton_iterations", max_newton_iterations,
          "must be >= 1");
  Require(max_equilibrium_iterations >= 1, "initial.max_equilibrium_iterations",
          max_equilibrium_iterations, "must be >= 1");
}

void ComputeConsistentDerivatives(const Mechanism& model, RunData* data, double t, Vec* y,
                                  Vec* yp) {
  const int np = model.num_coordinates(), nc = model.num_constraints(), N = model.size();
  const int nz = N - model.z_offset();
  y->segment(model.lambda_offset(), 2 * nc).setZero();
  yp->setZero(N);
  yp->head(np) = y->segment(np, np);
  Vec r(N);
  // Twice: ż = f(t, y) first (F5 = ż − f at ż = 0), since the co-rotated dampings' forces
  // depend on their states' rates.
  for (int pass = 0; pass < 2; ++pass) {
    if (CalcResidual(model, data, t, y->data(), yp->data(), r.data()) != 0) {
      throw NumericalError("consistent derivatives at t = " + FormatValue(t) +
                           " s: the residual failed (element failure or non-finite forces)");
    }
    if (pass == 0) yp->tail(nz) = -r.tail(nz);
  }
  const Vec Q = -r.segment(np, np);  // with v̇ = 0 and λ = 0, F2 = −Q
  const Vec p = y->head(np), v = y->segment(np, np);
  Mat M, G;
  Vec gt, gamma;
  CalcMassMatrix(model, data, p, &M);
  CalcConstraintJacobian(model, data, t, p, &G, &gt);
  CalcConstraintAccelerationRhs(model, data, t, p, v, &gamma);
  Mat aug = Mat::Zero(np + nc, np + nc);
  aug.topLeftCorner(np, np) = M;
  aug.topRightCorner(np, nc) = G.transpose();
  aug.bottomLeftCorner(nc, np) = G;
  Vec rhs(np + nc);
  rhs << Q, gamma;
  Eigen::FullPivLU<Mat> lu(aug);
  if (!lu.isInvertible()) {
    throw NumericalError("consistent accelerations at t = " + FormatValue(t) +
                         " s: the augmented matrix [M Gᵀ; G 0] is singular (rank " +
                         std::to_string(lu.rank()) + " of " + std::to_string(np + nc) +
                         "): redundant constraints, a dead-centre configuration or a "
                         "coordinate without mass and constraint");
  }
  const Vec sol = lu.solve(rhs);
  yp->segment(np, np) = sol.head(np);
  y->segment(model.lambda_offset(), nc) = sol.tail(nc);
  // ż = f(t, y) including the driver power, which depends on λ: F5 = ż − f.
  if (CalcResidual(model, data, t, y->data(), yp->data(), r.data()) != 0) {
    throw NumericalError("consistent derivatives at t = " + FormatValue(t) +
                         " s: the residual failed");
  }
  yp->tail(nz) -= r.tail(nz);
}

void ProjectOntoConstraints(const Mechanism& model, RunData* data, double t,
                            const std::vector<int>& movable, Vec* y, Vec* yp) {
  const int np = model.num_coordinates();
  Vec p = y->head(np), v = y->segment(np, np);
  const std::string context = "restart at t = " + FormatValue(t) + " s";
  SolvePositionConstraints(model, data, t, movable,
                           kRestartPositionTolerance * std::max(1.0, p.lpNorm<Eigen::Infinity>()),
                           kRestartNewtonIterations, context, &p);
  SolveVelocityConstraints(model, data, t, p, movable, context, &v);
  y->head(np) = p;
  y->segment(np, np) = v;
  ComputeConsistentDerivatives(model, data, t, y, yp);
}

namespace {

/// One fixed-point step towards static equilibrium of the elastic coordinates: hold q̈ = 0 with
/// extra multipliers ρ (the generalized force still needed on q) and move each body's q by
/// K Δq = ρ. Returns the largest |Δq|; *qmax receives the largest |q| after the step.
double StaticEquilibriumStep(const Mechanism& model, RunData* data, double t0,
                             const std::vector<int>& qidx, const Vec& v, Vec* y, Vec* p,
                             double* qmax) {
  const int np = model.num_coordinates(), nc = model.num_constraints(), N = model.size();
  const int nq = static_cast<int>(qidx.size());
  *qmax = 0.0;
  Vec yp = Vec::Zero(N);
  yp.head(np) = v;
  Vec r(N);
  y->segment(model.lambda_offset(), 2 * nc).setZero();
  if (CalcResidual(model, data, t0, y->data(), yp.data(), r.data()) != 0) {
    throw NumericalError("static equilibrium: the residual failed");
  }
  const Vec Q = -r.segment(np, np);
  Mat M, G;
  Vec gt, gamma;
  CalcMassMatrix(model, data, *p, &M);
  CalcConstraintJacobian(model, data, t0, *p, &G, &gt);
  CalcConstraintAccelerationRhs(model, data, t0, *p, v, &gamma);
  const int na = np + nc + nq;
  Mat aug = Mat::Zero(na, na);
  aug.topLeftCorner(np, np) = M;
  aug.block(0, np, np, nc) = G.transpose();
  aug.block(np, 0, nc, np) = G;
  for (int k = 0; k < nq; ++k) {
    aug(qidx[k], np + nc + k) = 1.0;
    aug(np + nc + k, qidx[k]) = 1.0;
  }
  Vec rhs = Vec::Zero(na);
  rhs.head(np) = Q;
  rhs.segment(np, nc) = gamma;
  Eigen::FullPivLU<Mat> lu(aug);
  if (!lu.isInvertible()) {
    throw NumericalError("static equilibrium: singular augmented matrix (rank " +
                         std::to_string(lu.rank()) + " of " + std::to_string(na) + ")");
  }
  const Vec sol = lu.solve(rhs);
  double change = 0.0;
  int offset = 0;
  for (const Body& b : model.bodies()) {
    const int n = b.num_modes;
    if (n == 0) continue;
    const Vec rho = sol.segment(np + nc + offset, n);
    Eigen::FullPivLU<Mat> klu(b.K);
    if (!klu.isInvertible()) {
      throw NumericalError("static equilibrium: the stiffness of body " + b.name +
                           " is singular (rigid-body content in the basis); use an "
                           "undeformed start");
    }
    const Vec dq = klu.solve(rho);
    p->segment(b.coordinate(kFirstMode), n) += dq;
    change = std::max(change, dq.lpNorm<Eigen::Infinity>());
    *qmax = std::max(*qmax, p->segment(b.coordinate(kFirstMode), n).lpNorm<Eigen::Infinity>());
    offset += n;
  }
  return change;
}

}  // namespace

ConsistentState ComputeConsistentState(const Mechanism& model, RunData* data, double t0,
                                       const InitialConditionSpec& spec) {
  spec.Validate(model);
  FLEXROD_ASSERT(data->model == &model);
  const int np = model.num_coordinates(), N = model.size();
  Vec p = spec.coordinates.size() == np ? spec.coordinates : Vec::Zero(np);
  Vec v = spec.velocities.size() == np ? spec.velocities : Vec::Zero(np);
  std::vector<bool> fix_p(np, false), fix_v(np, false);
  for (int i : spec.fixed_coordinates) fix_p[i] = true;
  for (int i : spec.fixed_velocities) fix_v[i] = true;
  bool any_flexible = false;
  for (const Body& b : model.bodies()) {
    for (int k = 0; k < b.num_modes; ++k) {
      fix_p[b.coordinate(kFirstMode + k)] = true;
      fix_v[b.coordinate(kFirstMode + k)] = true;
      any_flexible = true;
    }
  }
  const std::vector<int> free_p = Complement(np, fix_p), free_v = Complement(np, fix_v);

  auto solve_positions = [&]() {
    SolvePositionConstraints(model, data, t0, free_p, spec.position_tolerance,
                             spec.max_newton_iterations, "initial conditions", &p);
  };
  auto solve_velocities = [&]() {
    SolveVelocityConstraints(model, data, t0, p, free_v, "initial conditions", &v);
  };
  Vec y = Vec::Zero(N), yp = Vec::Zero(N);
  auto assemble = [&]() {
    y.head(np) = p;
    y.segment(np, np) = v;
    InitializeElements(model, data, &y);
  };

  solve_positions();
  solve_velocities();
  assemble();
  if (spec.elastic == ElasticInitialState::kStaticEquilibrium && any_flexible) {
    // Fixed point: hold q̈ = 0 with extra multipliers ρ (the generalized force still needed
    // on q); update K Δq = ρ until ρ vanishes.
    std::vector<int> qidx;
    for (const Body& b : model.bodies())
      for (int k = 0; k < b.num_modes; ++k) qidx.push_back(b.coordinate(kFirstMode + k));
    bool converged = false;
    double last_change = 0.0;
    for (int it = 0; it < spec.max_equilibrium_iterations && !converged; ++it) {
      double qmax = 0.0;
      const double change = StaticEquilibriumStep(model, data, t0, qidx, v, &y, &p, &qmax);
      solve_positions();
      solve_velocities();
      assemble();
      last_change = change;
      converged = change <= 1e-13 + 1e-10 * qmax;
    }
    if (!converged) {
      throw NumericalError("static equilibrium of the elastic coordinates did not converge in " +
                           std::to_string(spec.max_equilibrium_iterations) +
                           " iterations (last change " + FormatValue(last_change) + ")");
    }
  }
  ComputeConsistentDerivatives(model, data, t0, &y, &yp);
  ConsistentState state;
  state.t = t0;
  state.y = std::move(y);
  state.yp = std::move(yp);
  data->reference_energy = InitialEnergy(model, data, state.y);
  return state;
}

bool ApplyElementRoots(const Mechanism& model, RunData* data, double t, double* y,
                       const int* roots) {
  UpdateKinematics(model, data, y);
  bool must_restart = false;
  for (const ElementSlot& e : model.elements()) {
    for (int k = 0; k < e.num_roots; ++k) {
      const int dir = roots[e.root_offset + k];
      if (dir == 0) continue;
      must_restart |= e.element->OnRoot(
          k, dir, t, data->markers[e.marker_i].kin, data->markers[e.marker_j].kin,
          y + model.z_offset() + e.state_offset, data->element_memory.data() + e.memory_offset);
    }
  }
  return must_restart;
}

void SetBodyPose(const Mechanism& model, BodyId body, const Vec2& origin, double angle, Vec* p) {
  if (p->size() != model.num_coordinates()) p->setZero(model.num_coordinates());
  (*p)(model.coordinate(body, kX)) = origin.x();
  (*p)(model.coordinate(body, kY)) = origin.y();
  (*p)(model.coordinate(body, kTheta)) = angle;
}

void SetBodyVelocity(const Mechanism& model, BodyId body, const Vec2& velocity,
                     double angular_velocity, Vec* v) {
  if (v->size() != model.num_coordinates()) v->setZero(model.num_coordinates());
  (*v)(model.coordinate(body, kX)) = velocity.x();
  (*v)(model.coordinate(body, kY)) = velocity.y();
  (*v)(model.coordinate(body, kTheta)) = angular_velocity;
}

// ---- MechanismDae -------------------------------------------------------------------------------
MechanismDae::MechanismDae(const Mechanism& model, RunData* data,
                           const PrescribedMotion& prescribed, std::optional<IndexEventSpec> index,
                           double velocity_tol_scale, double energy_tol_scale)
    : model_(model),
      data_(data),
      prescribed_(prescribed),
      index_(index),
      velocity_tol_scale_(velocity_tol_scale),
      energy_tol_scale_(energy_tol_scale),
      y_full_(Vec::Zero(model.size())),
      yp_full_(Vec::Zero(model.size())),
      r_full_(Vec::Zero(model.size())),
      jac_full_(Mat::Zero(model.size(), model.size())),
      dfdyp_full_(Mat::Zero(model.size(), model.size())),
      full_pattern_(multibody::JacobianPattern(model)) {
  FLEXROD_ASSERT(data->model == &model);
  FLEXROD_ASSERT(prescribed.full_size() == model.size());
}

void MechanismDae::Expand(double t, const double* y, const double* yp) {
  prescribed_.Expand(t, y, yp, y_full_.data(), yp_full_.data());
}

int MechanismDae::num_roots() const {
  return model_.num_element_roots() + (index_.has_value() ? 1 : 0);
}

int MechanismDae::index_root() const {
  return index_.has_value() ? model_.num_element_roots() : -1;
}

void MechanismDae::DifferentialMask(double* id) const {
  Vec full(model_.size());
  multibody::DifferentialMask(model_, full.data());
  prescribed_.Reduce(full.data(), id);
}

void MechanismDae::StepScaledWeightMask(double* mask) const {
  Vec full(model_.size());
  for (int i = 0; i < model_.size(); ++i) {
    full[i] = (i >= model_.lambda_offset() && i < model_.z_offset()) ? 1.0 : 0.0;
  }
  prescribed_.Reduce(full.data(), mask);
}

void MechanismDae::AbsoluteToleranceScales(double* scales) const {
  Vec full(model_.size());
  multibody::AbsoluteToleranceScales(model_, velocity_tol_scale_, energy_tol_scale_, full.data());
  prescribed_.Reduce(full.data(), scales);
}

void MechanismDae::RelativeToleranceCaps(double* caps) const {
  Vec full = Vec::Constant(model_.size(), std::numeric_limits<double>::infinity());
  for (const ElementSlot& e : model_.elements()) {
    const double L = e.element->ResolvedLength();
    if (!(L > 0.0)) continue;
    for (int mi : {e.marker_i, e.marker_j}) {
      const Marker& mk = model_.markers()[mi];
      if (mk.body < 0) continue;
      const Body& b = model_.bodies()[mk.body];
      for (int slot : {kX, kY}) full[b.coordinate(slot)] = std::min(full[b.coordinate(slot)], L);
      const double arm = mk.position.norm();
      if (arm > 0.0) full[b.coordinate(kTheta)] = std::min(full[b.coordinate(kTheta)], L / arm);
    }
  }
  prescribed_.Reduce(full.data(), caps);
}

int MechanismDae::Residual(double t, const double* y, const double* yp, double* r) {
  Expand(t, y, yp);
  const int rc = CalcResidual(model_, data_, t, y_full_.data(), yp_full_.data(), r_full_.data());
  const std::vector<int>& rows = prescribed_.kept_rows();
  for (size_t i = 0; i < rows.size(); ++i) r[i] = r_full_[rows[i]];
  return rc;
}

int MechanismDae::Jacobian(double t, double cj, const double* y, const double* yp, double* jac) {
  return AddJacobians(t, cj, y, yp, jac, nullptr);
}

int MechanismDae::JacobianAndDerivativePart(double t, double cj, const double* y, const double* yp,
                                            double* jac, double* dfdyp) {
  return AddJacobians(t, cj, y, yp, jac, dfdyp);
}

int MechanismDae::AddJacobians(double t, double cj, const double* y, const double* yp, double* jac,
                               double* dfdyp) {
  if (prescribed_.num_prescribed_coordinates() == 0) {
    return AddJacobian(model_, data_, t, cj, y, yp, jac, model_.size(), dfdyp);
  }
  Expand(t, y, yp);
  const int rc =
      AddJacobian(model_, data_, t, cj, y_full_.data(), yp_full_.data(), jac_full_.data(),
                  model_.size(), dfdyp != nullptr ? dfdyp_full_.data() : nullptr);
  prescribed_.MoveReducedMatrix(full_pattern_, jac_full_.data(), jac);
  if (dfdyp != nullptr) prescribed_.MoveReducedMatrix(full_pattern_, dfdyp_full_.data(), dfdyp);
  // An entry outside the pattern is neither moved nor cleared: a model bug, looked for as
  // IdaIntegrator looks in the reduced matrix (kPatternCheckInterval).
  if (jacobians_++ % kPatternCheckInterval == 0) {
    for (Eigen::Index c = 0; c < jac_full_.cols(); ++c) {
      for (Eigen::Index r = 0; r < jac_full_.rows(); ++r) {
        if (jac_full_(r, c) == 0.0) continue;
        jac_full_.setZero();
        throw NumericalError("Jacobian entry (" + std::to_string(r) + ", " + std::to_string(c) +
                             ") of the full mechanism lies outside its sparsity pattern (model "
                             "bug)");
      }
    }
  }
  return rc;
}

SparsityPattern MechanismDae::JacobianPattern() const {
  return prescribed_.ReducePattern(full_pattern_);
}

int MechanismDae::Roots(double t, const double* y, const double* yp, double* g) {
  Expand(t, y, yp);
  CalcElementRoots(model_, data_, t, y_full_.data(), g);
  if (index_.has_value()) {
    const double theta = y_full_[model_.coordinate(index_->body, kTheta)];
    g[model_.num_element_roots()] = std::sin(0.5 * (theta - index_->angle));
  }
  return 0;
}

double AutoVelocityTolScale(const Mechanism& model) {
  auto elastic = [&model](int marker) {
    const Marker& m = model.markers()[marker];
    return m.body >= 0 && m.active_slots.size() > 3;  // moves with some elastic coordinate
  };
  for (const Joint& j : model.joints()) {
    if (j.kind != JointKind::kGround && (elastic(j.marker_i) || elastic(j.marker_j))) {
      return kElasticJointVelocityTolScale;
    }
  }
  for (const ElementSlot& e : model.elements()) {
    if (elastic(e.marker_i) || elastic(e.marker_j) || e.element->structural()) {
      return kElasticJointVelocityTolScale;
    }
  }
  return 1.0;
}

// ---- run loop -----------------------------------------------------------------------------------
void SimulationOptions::Validate(const Mechanism& model) const {
  Require(std::isfinite(t_start), "simulation.t_start", t_start, "must be finite");
  Require(t_end > t_start && std::isfinite(t_end), "simulation.t_end", t_end,
          "must be finite and > t_start");
  RequirePositive("simulation.sample_rate", sample_rate);
  Require(std::isfinite(sample_start), "simulation.sample_start", sample_start, "must be finite");
  RequireNonNegative("simulation.max_steps", static_cast<double>(max_steps));
  RequireNonNegative("simulation.velocity_tol_scale", velocity_tol_scale);
  RequirePositive("simulation.energy_tol_scale", energy_tol_scale);
  if (start_sampling_at_index && !index_event.has_value()) {
    throw InputError("simulation.start_sampling_at_index", "true", "needs an index_event");
  }
  if (index_event.has_value()) {
    Require(index_event->body.index >= 0 && index_event->body.index < model.num_bodies(),
            "simulation.index_event.body", index_event->body.index, "must be a body");
    Require(std::isfinite(index_event->angle), "simulation.index_event.angle", index_event->angle,
            "must be finite");
  }
  integrator.Validate();
}

const char* ToString(SimulationOutcome outcome) {
  switch (outcome) {
    case SimulationOutcome::kCompleted:
      return "completed";
    case SimulationOutcome::kIntegratorFailure:
      return "integrator-failure";
    case SimulationOutcome::kStepLimit:
      return "step-limit";
    case SimulationOutcome::kWallTimeLimit:
      return "wall-time-limit";
    case SimulationOutcome::kInitialConditionFailure:
      return "initial-condition-failure";
    case SimulationOutcome::kInterrupted:
      return "interrupted";
  }
  return "?";
}

std::string CaughtStepControlNote(const IntegratorStats& stats) {
  if (stats.steps < 1000) return "";
  const char* cause =
      "stiff elastic coordinates coupled to joints catch the step control at this tolerance; "
      "loosened tolerances can cause this: tighten sim.rel_tol and sim.abs_tol (the defaults "
      "1e-6 and 1e-10, or tighter)";
  std::ostringstream os;
  if (stats.error_test_failures > stats.steps / 2) {
    os << "error-test failures on most steps (" << stats.error_test_failures << " of "
       << stats.steps << "): " << cause;
  } else if (static_cast<double>(stats.steps_by_order[1]) >=
             kCaughtOrderOneShare * static_cast<double>(stats.steps)) {
    os << std::lround(100.0 * static_cast<double>(stats.steps_by_order[1]) /
                      static_cast<double>(stats.steps))
       << " % of the steps at BDF order 1 (" << stats.steps_by_order[1] << " of " << stats.steps
       << "), so it can take more steps than at a tighter tolerance: " << cause;
  }
  return os.str();
}

std::string SimulationStatus::Summary() const {
  std::ostringstream os;
  os << ToString(outcome) << " at t = " << t_reached << " s";
  if (!ok()) {
    os << ": " << message << "\n  hint: " << hint << "\n  |p| = " << norm_coordinates
       << ", |v| = " << norm_velocities << ", |lambda| = " << norm_multipliers;
    for (size_t k = 0; k < failure_state.size(); ++k) {
      os << (k % 3 == 0 ? "\n  " : ", ") << failure_state[k].first << " = "
         << failure_state[k].second;
    }
    if (worst_residual_index >= 0) {
      os << "\n  largest residual " << worst_residual << " at " << worst_residual_variable;
    }
    if (worst_error_index >= 0) {
      os << "\n  largest weighted local error " << worst_weighted_error << " at "
         << worst_error_variable;
    }
  }
  if (const std::string note = CaughtStepControlNote(stats); !note.empty()) {
    os << "\n  note: " << note;
  }
  os << "\n  steps " << stats.steps << ", residuals " << stats.residual_evaluations
     << ", Jacobians " << stats.jacobian_evaluations << ", Newton iterations "
     << stats.nonlinear_iterations << ", convergence failures "
     << stats.nonlinear_convergence_failures << ", error-test failures "
     << stats.error_test_failures << ", roots " << stats.roots_found << ", samples " << num_samples;
  return os.str();
}

SimulationStatus Simulate(const Mechanism& model, RunData* data, const InitialConditionSpec& ic,
                          const SimulationOptions& options, const SimulationCallbacks& callbacks) {
  options.Validate(model);
  ConsistentState state;
  try {
    state = ComputeConsistentState(model, data, options.t_start, ic);
  } catch (const NumericalError& e) {
    SimulationStatus status;
    status.outcome = SimulationOutcome::kInitialConditionFailure;
    status.t_reached = options.t_start;
    status.message = e.what();
    status.hint =
        "check the initial guess (assembly), the fixed coordinates and for redundant "
        "constraints";
    return status;
  }
  return Simulate(model, data, state, options, callbacks);
}

}  // namespace flexrod::multibody
