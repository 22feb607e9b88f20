// Benchmarks of the contact module: one evaluation of each normal law (the multibody residual
// calls it at every Newton iteration), the friction laws, the clearance kinematics, and a
// whole single impact. Measures only; correctness lives in tests/contact/.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <benchmark/benchmark.h>

#include <string>

#include "contact/friction_law.h"
#include "contact/geometry.h"
#include "contact/impact.h"
#include "contact/normal_law.h"

namespace flexrod::contact {
namespace {

// Steel pin in a steel bush: 3/4 in bore, 0.5 mm clearance, 12.7 mm long.
const ContactMaterials kSteel{200e9, 0.29, 200e9, 0.29, 0.9};
const ContactGeometry kRig{9.525e-3, 9.025e-3, 12.7e-3};

NormalLaw Law(int index) {
  const std::string& name = NormalLawNames().at(index);
  ParameterMap p;
  for (const std::string& key : NormalLawParameterKeys(name)) {
    if (key == "effective-mass") p[key] = 2.71;
  }
  return MakeNormalLaw(name, kSteel, kRig, p);
}

void BM_NormalForce(benchmark::State& state) {
  const NormalLaw law = Law(static_cast<int>(state.range(0)));
  state.SetLabel(std::string(NormalLawName(law)));
  LawState s = InitialLawState(law);
  double d = 1e-7;
  for (auto _ : state) {
    d = d * 1.0001 + 1e-12;
    if (d > 1e-5) d = 1e-7;
    benchmark::DoNotOptimize(CalcNormalForce(law, d, 0.3, 0.5, s));
  }
}
BENCHMARK(BM_NormalForce)->DenseRange(0, 15);

void BM_FrictionForce(benchmark::State& state) {
  const FrictionLaw law = MakeFrictionLaw(FrictionLawNames().at(state.range(0)));
  state.SetLabel(std::string(FrictionLawName(law)));
  double v = -0.5;
  for (auto _ : state) {
    v += 1e-6;
    if (v > 0.5) v = -0.5;
    benchmark::DoNotOptimize(CalcFrictionForce(law, v, 800.0, 1e-6));
  }
}
BENCHMARK(BM_FrictionForce)->DenseRange(0, 3);

void BM_ClearanceKinematics(benchmark::State& state) {
  ClearanceMotion m;
  m.pin_centre = Vec2(3e-4, 4e-4);
  m.pin_velocity = Vec2(0.2, -0.1);
  m.pin_angular_velocity = 20.0;
  for (auto _ : state) {
    m.pin_centre.x() += 1e-12;
    benchmark::DoNotOptimize(CalcClearanceKinematics(kRig, m));
  }
}
BENCHMARK(BM_ClearanceKinematics);

void BM_SingleImpact(benchmark::State& state) {
  const NormalLaw law = Law(static_cast<int>(state.range(0)));
  state.SetLabel(std::string(NormalLawName(law)));
  for (auto _ : state) benchmark::DoNotOptimize(SimulateImpact(law, 2.71, 0.5));
}
BENCHMARK(BM_SingleImpact)->Arg(4)->Arg(7)->Arg(10)->Arg(15)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace flexrod::contact

BENCHMARK_MAIN();
