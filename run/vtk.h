// run/vtk.h — the ParaView frames of one run: a recorder that turns output samples into frames
// of the mechanism drawn in the world plane (mechanisms/drawing.h): the rod centre line with its
// elastic deformation scaled, its clamp arms, the crank where there is one, the bush and pin
// circles of a clearance joint, and each recipe's own parts (MechanismRecipe::LayOutParts: the
// slider, the rocker). What does not live here: the run loop that feeds the recorder
// (run/run.cc), the mechanism layout (mechanisms/mechanism_model.h), marker kinematics
// (multibody/), the files (io/run_vtk.h).
//
// Geometry (mechanisms/mechanism_model.h notation). The elastic displacement of a rod point ū₀ with
// shape rows S_u is d = S_u q_f in the rod frame B (origin at the big-end clamp node). It is
// split into its chord part d_c, interpolated linearly (by the position along the undeformed
// chord) between the displacements of the rod's two end nodes, and the deflection d − d_c.
// A centre-line node is drawn at p_W = R_B + A(θ_B)(ū₀ + d_c + s·(d − d_c)), s = vtk.scale:
// only the deflection from the chord is magnified, so both end nodes stay where they are at
// every s; s = 1 is the true configuration, s = 0 the straight rod on the deformed chord. The
// big- and small-end joint points (on the clamp arms) are drawn at their true positions. The
// crank, the recipes' parts and the joint circles are drawn at their true positions. Drawing
// sizes that are not physics (the slider rectangle) are stated where they are chosen. The
// point array `deflection [m]` is |d − d_c| (unscaled).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common/eigen.h"
#include "input/config.h"
#include "input/options.h"
#include "mechanisms/drawing.h"
#include "mechanisms/exact_rod_view.h"
#include "mechanisms/mechanism_model.h"
#include "multibody/simulate.h"

namespace flexrod::study {

/// Builds frames from the samples of one run. The model must outlive the recorder.
class VtkRecorder {
 public:
  /// `sample_rate` [Hz] is the run's output rate. Reads rod.length (the drawn rigid rod) and
  /// rod.geometric_stiffening from cfg; the recipe reads what its parts need.
  VtkRecorder(const Config& cfg, const MechanismModel& model, const VtkOptions& options,
              double sample_rate);
  /// Offers capture sample k (k = 0 at the capture start): recorded when k is a multiple of
  /// the stride and k / sample_rate <= duration (or duration is 0).
  void Offer(long k, const multibody::SampleView& sample);
  /// The frame of any sample (whatever the grid).
  VtkFrame CalcFrame(const multibody::SampleView& sample) const;
  const VtkSeries& series() const { return series_; }
  VtkSeries Finish() { return std::move(series_); }

 private:
  // The layout's parts, each adding its points (VtkLayout::AddPoints) and cells.
  void LayOutReducedRod(const Config& cfg);
  void LayOutExactRod();
  void LayOutEndsAndCrank();
  void LayOutClearanceJoint();
  // CalcFrame's parts: the points the rod's frame carries (any rod; `q` the reduced rod's
  // elastic coordinates, with its stresses), the exact rod's nodes and stresses, the crank and
  // the clearance joint's circles.
  void DrawCarriedPoints(const Vec2& R, const Mat2& A, const Vec& q, VtkFrame* f) const;
  void DrawExactRod(const double* y, VtkFrame* f) const;
  void DrawCrankAndJoint(const multibody::SampleView& s, VtkFrame* f) const;

  const MechanismModel& model_;
  VtkSeries series_;
  /// A drawn point carried by the rod (drawn as in the header paragraph).
  struct CarriedPoint {
    int index{0};  ///< layout point
    Vec2 u0;       ///< ū₀ in frame B [m]
    Mat2X S_u;     ///< 2×n (n = 0 for a rigid rod) [m]
  };
  long last_index_{-1};  ///< last sample index recorded; −1: no limit
  std::vector<CarriedPoint> carried_;
  size_t chord_first_{0}, chord_last_{0};  ///< carried_ entries of the rod's end nodes
  Mat axial_rows_, bending_rows_;          ///< nodes × n stress rows [Pa]
  std::vector<Mat> axial_quadratic_;  ///< per node: E × the gauge's membrane matrix [Pa] (n × n)
  /// rod.type = exact: its node bodies (drawn where they are) and strains.
  std::shared_ptr<const ExactRodView> exact_;
  double exact_E_{0.0}, exact_fibre_{0.0};     ///< [Pa], [m]
  double bush_radius_{0.0}, pin_radius_{0.0};  ///< [m]
  std::unique_ptr<PartsDrawing> parts_;        ///< the recipe's own parts, or null
};

}  // namespace flexrod::study
