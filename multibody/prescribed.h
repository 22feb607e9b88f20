// multibody/prescribed.h — the coordinates that constraints to the ground fix as known
// functions of time, and the smaller DAE the integrator solves without them. What does not live
// here: the equations themselves (multibody/dae.h, always evaluated on the full unknowns), the
// run loop (simulate.h).
//
// Found from the topology (each body at most once):
//  - held: a body with a ground joint; x, y, θ constant (its 3 rows);
//  - driven: a rigid body on a revolute to a ground marker P, turned by a constraint driver
//    (constant speed or speed profile); θ(t) from the driver, R = P − A(θ) ū with ū the body's
//    marker (the revolute's 2 rows and the driver's row);
//  - guided: a rigid body on a prismatic whose guide marker (marker i) is on the ground and runs
//    exactly along a world axis; the held angle and the cross-guide frame coordinate are
//    constant (the prismatic's 2 rows).
// Each set's rows involve only its own coordinates and are as many as its coordinates. The
// reduced DAE drops, per prescribed coordinate c and per row k of its set, the unknowns p_c,
// v_c, μ_k and the residual rows F1_c, F3_k, F4_k (dae.h). It keeps λ_k, now fixed by the kept
// equation-of-motion rows F2_c evaluated at the prescribed acceleration (an index-1 algebraic
// unknown: G_kkᵀ is square and regular), so the reactions and the driver torque stay in y and
// every output reads them as before. For the rigid slider-crank this is 36 → 21 unknowns; the
// residual and Jacobian kernels still run on the full layout (Expand, then gather rows and
// columns), the gain is in the integrator's vector operations and the sparse LU.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <optional>
#include <vector>

#include "multibody/ida_integrator.h"
#include "multibody/mechanism.h"

namespace flexrod::multibody {

class PrescribedMotion {
 public:
  /// enabled = false: nothing is prescribed (the reduced DAE is the full one).
  PrescribedMotion(const Mechanism& model, bool enabled);

  int full_size() const { return full_size_; }
  int size() const { return static_cast<int>(kept_unknowns_.size()); }
  int num_prescribed_coordinates() const { return num_prescribed_; }
  /// Full index of each reduced unknown (ascending).
  const std::vector<int>& kept_unknowns() const { return kept_unknowns_; }
  /// Full residual row of each reduced row (ascending).
  const std::vector<int>& kept_rows() const { return kept_rows_; }

  /// Starts an integration segment at t. A speed-profile driver's acceleration jumps at its
  /// knots (the run stops and restarts there, Mechanism::Breakpoints); within a segment it is
  /// the one at its start, so the steps that end on the next knot keep the left limit.
  void StartSegment(double t) { segment_start_ = t; }
  /// The full y and ẏ at t from the reduced ones: kept entries copied; prescribed p, v from the
  /// motion (ṗ = v, v̇ = its acceleration in the current segment); the dropped μ and μ̇ zero.
  void Expand(double t, const double* y, const double* yp, double* y_full, double* yp_full) const;
  /// The part of Expand that does not read the kept entries: prescribed p, v and their rates,
  /// the dropped μ and μ̇ zero (for a caller that has written the kept entries itself).
  void ExpandPrescribed(double t, double* y_full, double* yp_full) const;
  /// ExpandPrescribed for one body's prescribed coordinates alone (nothing if it has none).
  void ExpandPrescribedBody(double t, int body, double* y_full, double* yp_full) const;
  /// Gathers the kept unknowns of a full vector.
  void Reduce(const double* full, double* reduced) const;
  /// Moves the kept rows and kept columns of a full column-major N×N matrix (ld = N) into the
  /// reduced n×n one (ld = n), adding, reading and zeroing only the entries of `pattern` (the
  /// full Jacobian's), every column's: a matrix written inside its pattern is zero after, at a
  /// cost of nnz, not N².
  void MoveReducedMatrix(const SparsityPattern& pattern, double* full, double* reduced) const;
  /// The kept rows and columns of a full pattern, renumbered.
  SparsityPattern ReducePattern(const SparsityPattern& full) const;

 private:
  enum class Kind { kHeld, kDriven, kGuided };
  struct Set {
    Kind kind{Kind::kHeld};
    int body{-1};
    int driver{-1};          ///< kDriven
    Vec2 pivot{0.0, 0.0};    ///< kDriven: ground point P [m]
    Vec2 marker{0.0, 0.0};   ///< kDriven: ū of the body's pivot marker [m]
    Vec2 held{0.0, 0.0};     ///< kHeld: (x, y) [m]
    double angle{0.0};       ///< kHeld, kGuided: θ held [rad]
    int cross_slot{kY};      ///< kGuided: kX or kY, the frame coordinate held
    double cross{0.0};       ///< kGuided: its value [m]
    std::vector<int> slots;  ///< body slots prescribed (kX, kY, kTheta)
    std::vector<int> rows;   ///< constraint rows (into λ and μ) that fix them
  };
  /// The set of a ground joint: its body held.
  static Set HeldSet(const Joint& jt);
  /// The set of a revolute between a ground marker and a rigid body that a constraint driver
  /// turns; nullopt if the joint is not one.
  static std::optional<Set> DrivenSet(const Mechanism& model, const Joint& jt);
  /// The set of a prismatic whose guide is on the ground along a world axis and whose slider
  /// is rigid; nullopt if the joint is not one.
  static std::optional<Set> GuidedSet(const Mechanism& model, const Joint& jt);
  /// kept_unknowns_, kept_rows_ and row_to_reduced_ from sets_ (see the file comment).
  void BuildIndexMaps();
  /// One set's part of ExpandPrescribed.
  void ExpandSet(const Set& s, double t, double* y_full, double* yp_full) const;
  /// p, v, a of the set's slots at t, in the order of Set::slots.
  void Motion(const Set& s, double t, double* p, double* v, double* a) const;

  const Mechanism& model_;
  int full_size_{0};
  std::vector<Set> sets_;
  int num_prescribed_{0};  ///< prescribed coordinates, all sets
  std::vector<int> kept_unknowns_, kept_rows_;
  std::vector<int> row_to_reduced_;  ///< full row → reduced row, −1 if dropped
  double segment_start_{0.0};
};

}  // namespace flexrod::multibody
