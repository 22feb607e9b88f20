// multibody/sample_view.cc — the solution at one time as a view (SampleView: markers, reactions,
// drivers, elements, energies, constraint violation) and inside one step (StepInterpolant).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <algorithm>

#include "multibody/dae.h"
#include "multibody/dae_kernels.h"
#include "multibody/outputs.h"
#include "multibody/simulate.h"

namespace flexrod::multibody {

SampleView::SampleView(const Mechanism& model, RunData* data, double t, const double* y,
                       const double* yp)
    : model_(model), data_(data), t_(t), y_(y), yp_(yp) {}

void SampleView::Ready() const {
  if (!ready_) {
    UpdateKinematics(model_, data_, y_);
    ready_ = true;
  }
}

const MarkerKinematics& SampleView::Marker(MarkerId m) const {
  // Before a full update, this marker alone: the impact log asks for a clearance joint's two
  // markers at a solution point and at the points of a search inside each step of an impact.
  if (!ready_) {
    dae_kernels::UpdateMarkerAlone(model_, m.index, data_, y_, y_ + model_.num_coordinates());
  }
  return MarkerState(*data_, m);
}
Vec2 SampleView::MarkerAcceleration(MarkerId m) const {
  Ready();
  return multibody::MarkerAcceleration(model_, *data_, m, yp_);
}
JointReaction SampleView::Reaction(JointId j) const {
  Ready();
  return CalcJointReaction(model_, *data_, j, y_);
}
DriverState SampleView::Driver(DriverId d) const { return CalcDriverState(model_, d, y_); }
ElementReport SampleView::Element(ElementId e) const {
  Ready();
  return CalcElementReport(model_, data_, e, t_, y_);
}
EnergyReport SampleView::Energies() const {
  Ready();
  return CalcEnergies(model_, data_, y_, known_);
}
double SampleView::ConstraintViolation() const {
  Ready();
  return MaxConstraintViolation(model_, data_, t_, y_);
}

SampleView StepInterpolant::At(double t) const {
  const double tc = std::clamp(t, t_begin_, t_end_);
  evaluate_(tc, y_->data(), yp_->data());
  return SampleView(model_, data_, tc, y_->data(), yp_->data());
}

SampleView StepInterpolant::ElementAt(double t, ElementId e) const {
  const double tc = std::clamp(t, t_begin_, t_end_);
  evaluate_element_(tc, e, y_->data());
  return SampleView(model_, data_, tc, y_->data(), yp_->data());
}

}  // namespace flexrod::multibody
