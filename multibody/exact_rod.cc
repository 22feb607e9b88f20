// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/exact_rod.h"

#include <cmath>

#include "common/error.h"

namespace flexrod::multibody {
namespace {

fem::Vec6 Dofs(const MarkerKinematics& i, const MarkerKinematics& j) {
  fem::Vec6 d;
  d << i.position.x(), i.position.y(), i.angle, j.position.x(), j.position.y(), j.angle;
  return d;
}

fem::Vec6 Rates(const MarkerKinematics& i, const MarkerKinematics& j) {
  fem::Vec6 d;
  d << i.velocity.x(), i.velocity.y(), i.angular_velocity, j.velocity.x(), j.velocity.y(),
      j.angular_velocity;
  return d;
}

// Column of κ (kElementKinematicColumns) for element dof k of d (position/angle) and of ḋ (rates).
constexpr int kDofColumn[6] = {0, 1, 4, 6, 7, 10};
constexpr int kRateColumn[6] = {2, 3, 5, 8, 9, 11};

}  // namespace

ReissnerBeamElement::ReissnerBeamElement(const fem::ReissnerStiffness& stiffness, double length,
                                         double beta)
    : stiffness_(stiffness), length_(length), beta_(beta) {
  RequirePositive("exact_rod.element_length", length);
  RequireNonNegative("exact_rod.beta", beta);
}

bool ReissnerBeamElement::Evaluate(double /*t*/, const MarkerKinematics& i,
                                   const MarkerKinematics& j, const double* /*z*/,
                                   const double* /*memory*/, ElementOutput* out) const {
  const fem::Vec6 d = Dofs(i, j), dd = Rates(i, j);
  fem::Vec6 f, f_elastic;
  fem::CalcReissnerElement(stiffness_, length_, beta_, d, dd, &f, nullptr, nullptr);
  // The nodes receive −f. Dissipation: the damping forces' power ḋᵀ(f − ∂U/∂d) >= 0.
  out->force_i = -f.head<2>();
  out->moment_i = -f(2);
  out->force_j = -f.segment<2>(3);
  out->moment_j = -f(5);
  if (beta_ > 0.0) {
    fem::CalcReissnerElement(stiffness_, length_, 0.0, d, dd, &f_elastic, nullptr, nullptr);
    out->dissipation = dd.dot(f - f_elastic);
  }
  return f.allFinite();
}

bool ReissnerBeamElement::EvaluateJacobian(double /*t*/, const MarkerKinematics& i,
                                           const MarkerKinematics& j, const double* /*z*/,
                                           const double* /*memory*/, Mat* jac,
                                           Mat* /*d_states*/) const {
  const fem::Vec6 d = Dofs(i, j), dd = Rates(i, j);
  fem::Vec6 f, f_elastic;
  fem::Mat6 K, C, K_elastic;
  fem::CalcReissnerElement(stiffness_, length_, beta_, d, dd, &f, &K, &C);
  for (int c = 0; c < 6; ++c) {
    jac->block<6, 1>(0, kDofColumn[c]) = -K.col(c);
    jac->block<6, 1>(0, kRateColumn[c]) = -C.col(c);
  }
  if (beta_ > 0.0) {
    // D = ḋᵀ f_d with f_d = f − f_elastic = C ḋ (linear in ḋ, C symmetric):
    // ∂D/∂ḋ = 2 f_dᵀ, ∂D/∂d = ḋᵀ (K − K_elastic).
    fem::CalcReissnerElement(stiffness_, length_, 0.0, d, dd, &f_elastic, &K_elastic, nullptr);
    const fem::Vec6 fd = f - f_elastic;
    const fem::Vec6 dDd = (K - K_elastic).transpose() * dd;
    for (int c = 0; c < 6; ++c) {
      (*jac)(6, kDofColumn[c]) = dDd(c);
      (*jac)(6, kRateColumn[c]) = 2.0 * fd(c);
    }
  }
  return jac->allFinite();
}

double ReissnerBeamElement::PotentialEnergy(const MarkerKinematics& i, const MarkerKinematics& j,
                                            const double* /*z*/, const double* /*memory*/) const {
  // The energy alone: no forces (a sample asks for every element's energy).
  return fem::CalcReissnerElement(stiffness_, length_, 0.0, Dofs(i, j), fem::Vec6::Zero(), nullptr,
                                  nullptr, nullptr);
}

fem::ReissnerStrains ReissnerBeamElement::Strains(const MarkerKinematics& i,
                                                  const MarkerKinematics& j) const {
  return fem::CalcReissnerStrains(length_, Dofs(i, j));
}

ExactRod AddExactRod(MechanismBuilder* b, const ExactRodSpec& spec) {
  if (spec.rod.dim != fem::MeshDim::kPlanar) {
    throw InputError(spec.name + ".rod.dim", "spatial", "the exact rod is planar");
  }
  spec.rod.Validate();
  RequireNonNegative(spec.name + ".beta", spec.beta);
  ExactRod out;
  out.rod = spec.rod;
  const std::vector<fem::NodeInertia> inertia = fem::ExactBeamNodeInertia(spec.rod);
  for (int k = 0; k < spec.rod.num_nodes(); ++k) {
    const std::string name = spec.name + ".node" + std::to_string(k);
    const fem::NodeInertia& in = inertia[k];
    out.nodes.push_back(b->AddRigidBody({name, in.mass, in.inertia, in.com}));
    out.node_markers.push_back(b->AddBodyMarker(out.nodes.back(), name + ".axis", Vec2::Zero()));
  }
  out.element = std::make_shared<const ReissnerBeamElement>(
      fem::ReissnerStiffnessOf(spec.rod.material, spec.rod.section), spec.rod.element_length(),
      spec.beta);
  for (int e = 0; e < spec.rod.num_elements; ++e) {
    out.elements.push_back(b->AddForceElement(spec.name + ".element" + std::to_string(e),
                                              out.node_markers[e], out.node_markers[e + 1],
                                              out.element));
  }
  if (spec.modal_damping_coefficients.size() > 0) {
    b->AddCorotatedDamping(spec.name + ".modal_damping", out.nodes, spec.modal_damping_modes,
                           spec.modal_damping_coefficients);
  }
  return out;
}

void SetExactRodPose(const Mechanism& m, const ExactRod& rod, const Vec2& R, double theta, Vec* p) {
  const Vec2 axis(std::cos(theta), std::sin(theta));
  for (size_t k = 0; k < rod.nodes.size(); ++k) {
    const Vec2 x = R + rod.rod.node_x(static_cast<int>(k)) * axis;
    (*p)[m.coordinate(rod.nodes[k], kX)] = x.x();
    (*p)[m.coordinate(rod.nodes[k], kY)] = x.y();
    (*p)[m.coordinate(rod.nodes[k], kTheta)] = theta;
  }
}

}  // namespace flexrod::multibody
