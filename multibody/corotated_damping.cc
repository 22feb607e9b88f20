// SPDX-License-Identifier: GPL-3.0-or-later
#include "multibody/corotated_damping.h"

#include <cmath>

#include "common/error.h"

namespace flexrod::multibody {
namespace {

Vec2 Perp(const Vec2& a) { return Vec2(-a.y(), a.x()); }  // J a
double Cross(const Vec2& a, const Vec2& b) { return a.x() * b.y() - a.y() * b.x(); }
Mat2 Rotation(double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  Mat2 R;
  R << c, -s, s, c;
  return R;
}

/// The chain's frame at p, v: offsets of its bodies' coordinates, R(θ_0), θ̇_0, r_0, ṙ_0.
struct Chain {
  const Mechanism& m;
  const CorotatedDamping& d;
  const double* p;
  const double* v;
  int offset(int k) const { return m.bodies()[d.bodies[k]].coordinate_offset; }
  int size() const { return static_cast<int>(d.bodies.size()); }
  Vec2 r(int k) const { return Vec2(p[offset(k)], p[offset(k) + 1]); }
  Vec2 dr(int k) const { return r(k) - r(0); }
  Mat2 R() const { return Rotation(p[offset(0) + kTheta]); }
  double omega() const { return v[offset(0) + kTheta]; }
};

/// ḋ (3(n−1)).
void Rates(const Chain& ch, double* rates) {
  const Mat2 Rt = ch.R().transpose();
  const int o0 = ch.offset(0);
  const double c = ch.omega();
  for (int k = 1; k < ch.size(); ++k) {
    const int ok = ch.offset(k);
    const Vec2 dv(ch.v[ok] - ch.v[o0], ch.v[ok + 1] - ch.v[o0 + 1]);
    const Vec2 u = Rt * (dv - c * Perp(ch.dr(k)));
    double* out = rates + 3 * (k - 1);
    out[0] = u.x();
    out[1] = u.y();
    out[2] = ch.v[ok + kTheta] - ch.v[o0 + kTheta];
  }
}

/// Bᵀ σ, passed coordinate by coordinate to add(chain body k, slot, value).
template <typename Add>
void TransposeProduct(const Chain& ch, const Mat2& R, const double* sigma, Add add) {
  Vec2 force0 = Vec2::Zero();
  double moment0 = 0.0;
  for (int k = 1; k < ch.size(); ++k) {
    const double* s = sigma + 3 * (k - 1);
    const Vec2 g = R * Vec2(s[0], s[1]);
    add(k, kX, g.x());
    add(k, kY, g.y());
    add(k, kTheta, s[2]);
    force0 -= g;
    moment0 -= Cross(ch.dr(k), g) + s[2];
  }
  add(0, kX, force0.x());
  add(0, kY, force0.y());
  add(0, kTheta, moment0);
}

/// σ = Y diag(c) η̇ into stress.
void ModalStress(const CorotatedDamping& d, const double* eta_dot, Vec* stress) {
  stress->setZero();
  for (int i = 0; i < d.num_states(); ++i)
    stress->noalias() += (d.coefficients(i) * eta_dot[i]) * d.modes.col(i);
}

}  // namespace

Mat CorotatedRateMap(const Mechanism& m, const std::vector<BodyId>& bodies, const Vec& p) {
  FLEXROD_ASSERT(p.size() == m.num_coordinates() && bodies.size() >= 2);
  CorotatedDamping d;
  for (const BodyId b : bodies) d.bodies.push_back(b.index);
  const int np = m.num_coordinates(), rows = 3 * (static_cast<int>(bodies.size()) - 1);
  Mat B(rows, np);
  Vec v = Vec::Zero(np);
  for (int j = 0; j < np; ++j) {  // ḋ is linear in v: column j is ḋ at v = e_j
    v(j) = 1.0;
    Rates(Chain{m, d, p.data(), v.data()}, B.col(j).data());
    v(j) = 0.0;
  }
  return B;
}

void ResizeCorotatedScratch(const CorotatedDamping& d, CorotatedScratch* s) {
  const int rows = static_cast<int>(d.modes.rows());
  s->rates = Vec::Zero(rows);
  s->stress = Vec::Zero(rows);
  s->forces = Mat::Zero(3 * static_cast<int>(d.bodies.size()), d.num_states());
}

void AddCorotatedDampingResidual(const Mechanism& m, const CorotatedDamping& d, CorotatedScratch* s,
                                 const double* p, const double* v, const double* zd, double* Q,
                                 double* r5, double* dissipation) {
  const Chain ch{m, d, p, v};
  Rates(ch, s->rates.data());
  const double* eta_dot = zd + d.state_offset;
  ModalStress(d, eta_dot, &s->stress);
  for (int i = 0; i < d.num_states(); ++i) {
    r5[d.state_offset + i] = eta_dot[i] - d.modes.col(i).dot(s->rates);
    *dissipation += d.coefficients(i) * eta_dot[i] * eta_dot[i];
  }
  TransposeProduct(ch, ch.R(), s->stress.data(),
                   [&](int k, int slot, double x) { Q[ch.offset(k) + slot] -= x; });
}

void AddCorotatedDampingJacobian(const Mechanism& m, const CorotatedDamping& d, CorotatedScratch* s,
                                 double cj, const double* p, const double* v, const double* zd,
                                 double* jac, int ld, double* dfdyp) {
  const int np = m.num_coordinates(), F5 = m.z_offset() + d.state_offset;
  const int QD = m.quadrature_offset() + kDissipatedDamping;
  auto J = [&](int r, int c) -> double& { return jac[static_cast<long>(c) * ld + r]; };
  auto D = [&](int r, int c) -> double& { return dfdyp[static_cast<long>(c) * ld + r]; };
  const Chain ch{m, d, p, v};
  const Mat2 R = ch.R();
  const double omega = ch.omega();
  const int n = ch.size(), th0 = ch.offset(0) + kTheta;
  Rates(ch, s->rates.data());
  const double* eta_dot = zd + d.state_offset;

  // U = Bᵀ Y: F2 rows × η̇ columns (c_i U_i) and F5 rows × v columns (−U_iᵀ).
  for (int i = 0; i < d.num_states(); ++i) {
    s->forces.col(i).setZero();
    TransposeProduct(ch, R, d.modes.col(i).data(),
                     [&](int k, int slot, double x) { s->forces(3 * k + slot, i) += x; });
    const double ci = d.coefficients(i);
    for (int k = 0; k < n; ++k) {
      for (int slot = 0; slot < 3; ++slot) {
        const int g = ch.offset(k) + slot;
        const double u = s->forces(3 * k + slot, i);
        J(np + g, F5 + i) += cj * ci * u;
        if (dfdyp != nullptr) D(np + g, F5 + i) += ci * u;
        J(F5 + i, np + g) -= u;
      }
    }
    // F5 rows × p columns: −Yᵢᵀ ∂ḋ/∂p with ∂ḋ_k/∂θ_0 = −J ḋ_k, ∂ḋ_k/∂r_k = −θ̇_0 Rᵀ J = −∂ḋ_k/∂r_0.
    for (int k = 1; k < n; ++k) {
      const Vec2 y = d.modes.col(i).segment<2>(3 * (k - 1));
      const Vec2 rate = s->rates.segment<2>(3 * (k - 1));
      J(F5 + i, th0) += y.dot(Perp(rate));
      const Vec2 dk = omega * Perp(R * y);
      const int ok = ch.offset(k), o0 = ch.offset(0);
      J(F5 + i, ok) -= dk.x();
      J(F5 + i, ok + 1) -= dk.y();
      J(F5 + i, o0) += dk.x();
      J(F5 + i, o0 + 1) += dk.y();
    }
    // Dissipation Σ c_i η̇_i².
    J(QD, F5 + i) -= cj * 2.0 * ci * eta_dot[i];
    if (dfdyp != nullptr) D(QD, F5 + i) -= 2.0 * ci * eta_dot[i];
  }

  // F2 rows × p columns at fixed σ: F2 holds +Bᵀ σ, which turns with R and whose moment on
  // body 0 has the arms r_k − r_0.
  ModalStress(d, eta_dot, &s->stress);
  const int o0 = ch.offset(0);
  for (int k = 1; k < n; ++k) {
    const Vec2 g = R * s->stress.segment<2>(3 * (k - 1));
    const Vec2 Jg = Perp(g);
    const int ok = ch.offset(k);
    J(np + ok, th0) += Jg.x();
    J(np + ok + 1, th0) += Jg.y();
    J(np + o0, th0) -= Jg.x();
    J(np + o0 + 1, th0) -= Jg.y();
    J(np + th0, th0) -= ch.dr(k).dot(g);
    J(np + th0, ok) += Jg.x();
    J(np + th0, ok + 1) += Jg.y();
    J(np + th0, o0) -= Jg.x();
    J(np + th0, o0 + 1) -= Jg.y();
  }
}

}  // namespace flexrod::multibody
