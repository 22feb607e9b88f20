// run/vtk.h — ParaView output of one run: the vtk.* options, a recorder that turns output
// samples into frames of the mechanism drawn in the world plane (the rod centre line with its
// elastic deformation scaled, the clamp arms, the crank, the slider, and the bush and pin
// circles of a clearance joint), and the writer of the frames as VTK XML UnstructuredGrid
// files (.vtu, ASCII, Float64) with a .pvd collection whose timesteps are the sample times.
// What does not live here: the run loop that feeds the recorder (run/run.cc), the
// mechanism layout (mechanisms/mechanism_model.h), marker kinematics (multibody/).
//
// Geometry (mechanisms/mechanism_model.h notation). The elastic displacement of a rod point ū₀ with
// shape rows S_u is d = S_u q_f in the rod frame B (origin at the big-end clamp node). It is
// split into its chord part d_c, interpolated linearly (by the position along the undeformed
// chord) between the displacements of the rod's two end nodes, and the deflection d − d_c.
// A centre-line node is drawn at p_W = R_B + A(θ_B)(ū₀ + d_c + s·(d − d_c)), s = vtk.scale:
// only the deflection from the chord is magnified, so both end nodes stay where they are at
// every s; s = 1 is the true configuration, s = 0 the straight rod on the deformed chord. The
// big- and small-end joint points (on the clamp arms) are drawn at their true positions, on
// the crank pin and the journal. The crank, the slider and the joint circles
// are drawn at their true positions. Drawing sizes that are not physics (the slider
// rectangle) are stated where they are chosen (vtk.cc). The point array
// `deflection [m]` is |d − d_c| (unscaled).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "common/eigen.h"
#include "input/config.h"
#include "mechanisms/exact_rod_view.h"
#include "mechanisms/mechanism_model.h"
#include "multibody/simulate.h"

namespace flexrod::study {

/// The vtk.* input keys. Frames are taken from the run's output samples (no extra
/// integration): every stride-th sample of the capture window, stride = max(1,
/// round(sim.sample_rate / rate)), so the frame rate is sim.sample_rate / stride (exactly
/// `rate` when it divides the sample rate, otherwise the nearest such rate, at most
/// sim.sample_rate).
struct VtkOptions {
  double rate{1000.0};   ///< requested frame rate [Hz], > 0 (key vtk.rate)
  double scale{100.0};   ///< deformation scale factor s [1], >= 0 (key vtk.scale)
  double duration{0.0};  ///< window written from the capture start [s], >= 0; 0 = the whole
                         ///< capture (key vtk.duration)
  /// Throws InputError naming the vtk.* key, the value and the rule.
  void Validate() const;
  /// Reads and validates vtk.rate, vtk.scale, vtk.duration.
  static VtkOptions FromConfig(const Config& cfg);
};

/// What a cell draws (the integer cell-data array "part").
enum class VtkPart : int { kRod = 0, kClamp = 1, kCrank = 2, kSlider = 3, kBush = 4, kPin = 5 };

/// VTK cell types used (vtkCellType.h).
inline constexpr int kVtkLine = 3;
inline constexpr int kVtkPolyLine = 4;
inline constexpr int kVtkQuad = 9;

struct VtkCell {
  int type{kVtkLine};  ///< kVtkLine, kVtkPolyLine or kVtkQuad
  VtkPart part{VtkPart::kRod};
  std::vector<int> points;  ///< point indices
};

/// Which point is which; the same for every frame of a run. Indices are −1 when absent.
struct VtkLayout {
  int num_points{0};
  int rod_first{0};      ///< rod centre-line nodes, FE node order (big end first)
  int rod_count{0};      ///< FE nodes of a flexible rod; 2 (the clamp nodes) for a rigid rod
  int big_end{-1};       ///< big-end joint point carried by the rod (the crank-pin centre)
  int small_end{-1};     ///< small-end joint point carried by the rod (the bush centre)
  int crank_axis{-1};    ///< p_WO (slider-crank only)
  int crank_pin{-1};     ///< p_WC from the crank
  int slider_first{-1};  ///< 4 slider corners, counter-clockwise; their mean is p_WJ
  int bush_first{-1};    ///< bush circle (clearance joint), circle_points points
  int pin_first{-1};     ///< pin circle (clearance joint), circle_points points
  int circle_points{0};
  std::vector<VtkCell> cells;
};

/// One frame: every layout point in the world and the per-point data.
struct VtkFrame {
  double time{0.0};          ///< [s]
  double crank_angle{0.0};   ///< θ of the crank [rad] (NaN for the pendulum)
  std::vector<Vec2> points;  ///< p_W [m], rod deformation scaled by s
  std::vector<double>
      displacement;  ///< |S_u q_f|, unscaled elastic displacement [m]; 0 off the rod
  /// Surface stresses at the rod nodes (0 elsewhere and for a rigid rod), at the fibre
  /// y = +half depth in the mechanism plane: E times the gauge rows (fem::ReducedRod::Gauge),
  /// each node the mean of the limits from the elements on its two sides.
  std::vector<double> bending_stress;  ///< −E y κ [Pa]
  std::vector<double> axial_stress;    ///< E (u' + the second-order membrane strain) [Pa]
};

struct VtkSeries {
  VtkOptions options;
  VtkLayout layout;
  double frame_rate{0.0};  ///< effective frame rate sim.sample_rate / stride [Hz]
  long stride{1};          ///< samples per frame
  std::vector<VtkFrame> frames;
};

/// Builds frames from the samples of one run. The model must outlive the recorder.
class VtkRecorder {
 public:
  /// `sample_rate` [Hz] is the run's output rate. Reads rod.length (the drawn rigid rod) and
  /// joint.bush_radius (the slider size) from cfg.
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
  void LayOutReducedRod(const Config& cfg, int* next_point);
  void LayOutExactRod(int* next_point);
  void LayOutSliderCrank(const Config& cfg, int* next_point);
  // CalcFrame's parts: the points the rod's frame carries (any rod; `q` the reduced rod's
  // elastic coordinates, with its stresses), the exact rod's nodes and stresses, the crank and
  // slider with the clearance joint's circles.
  void DrawCarriedPoints(const Vec2& R, const Mat2& A, const Vec& q, VtkFrame* f) const;
  void DrawExactRod(const double* y, VtkFrame* f) const;
  void DrawCrankAndSlider(const multibody::SampleView& s, VtkFrame* f) const;

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
  double exact_E_{0.0}, exact_fibre_{0.0};                    ///< [Pa], [m]
  double slider_half_length_{0.0}, slider_half_height_{0.0};  ///< [m]
  double bush_radius_{0.0}, pin_radius_{0.0};                 ///< [m]
};

/// Writes `<dir>/<stem>_NNNNNN.vtu` for every frame and then `<dir>/<stem>.pvd` (each file
/// whole: temporary + rename; the collection last, so an interrupted write never leaves a
/// collection naming missing files). Creates dir. Returns the path of the .pvd.
std::string WriteVtkSeries(const std::string& dir, const VtkSeries& series,
                           const std::string& stem = "run");

/// File name of frame i (without the directory).
std::string VtkFrameFileName(const std::string& stem, size_t i);

}  // namespace flexrod::study
