// mechanisms/drawing.h — a run's mechanism drawn in the world plane, as data: the layout (which
// point is which, the cells joining them, the same for every frame) and the frames (every point
// in the world, with per-point data). The recorder that fills them from output samples is
// run/vtk.h; each recipe draws its own parts (MechanismRecipe::LayOutParts); the files are
// written by io/run_vtk.h (VTK XML, ParaView).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <vector>

#include "common/eigen.h"
#include "input/options.h"
#include "multibody/simulate.h"

namespace flexrod::study {

/// What a cell draws (the integer cell-data array "part").
enum class VtkPart : int {
  kRod = 0,
  kClamp = 1,
  kCrank = 2,
  kSlider = 3,
  kBush = 4,
  kPin = 5,
  kRocker = 6
};

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
  int rod_first{0};    ///< rod centre-line nodes, FE node order (big end first)
  int rod_count{0};    ///< FE nodes of a flexible rod; 2 (the clamp nodes) for a rigid rod
  int big_end{-1};     ///< big-end joint point carried by the rod (the crank-pin centre)
  int small_end{-1};   ///< small-end joint point carried by the rod (the bush centre)
  int crank_axis{-1};  ///< p_WO (a mechanism with a crank)
  int crank_pin{-1};   ///< p_WC from the crank
  int bush_first{-1};  ///< bush circle (clearance joint), circle_points points
  int pin_first{-1};   ///< pin circle (clearance joint), circle_points points
  int circle_points{0};
  // The recipes' own parts (MechanismRecipe::LayOutParts).
  int slider_first{-1};  ///< slider-crank: 4 slider corners, counter-clockwise; mean = p_WJ
  int rocker_axis{-1};   ///< four-bar: the rocker's ground pivot
  int rocker_tip{-1};    ///< four-bar: the rocker's tip (its joint with the rod's small end)
  std::vector<VtkCell> cells;

  /// Adds `count` points and returns the first one's index.
  int AddPoints(int count) {
    const int first = num_points;
    num_points += count;
    return first;
  }
};

/// One frame: every layout point in the world and the per-point data.
struct VtkFrame {
  double time{0.0};          ///< [s]
  double crank_angle{0.0};   ///< θ of the crank [rad] (NaN without a crank)
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

/// What draws a recipe's own parts (MechanismRecipe::LayOutParts) in each frame.
class PartsDrawing {
 public:
  virtual ~PartsDrawing() = default;
  /// Sets the points it laid out in `f` from sample `s`.
  virtual void Draw(const multibody::SampleView& s, VtkFrame* f) const = 0;
};

}  // namespace flexrod::study
