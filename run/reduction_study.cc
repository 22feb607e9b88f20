// SPDX-License-Identifier: GPL-3.0-or-later
#include "run/reduction_study.h"

#include <algorithm>
#include <cmath>

#include "run/rigid_rig_studies.h"

namespace flexrod {

std::vector<ReductionVariant> ReductionVariants() {
  // The full FE rod runs at sim.abs_tol = 1e-8, not the default 1e-10: its stiffest modes
  // (every element's) then hold the step near their period (the flexible rig, 0.3 s simulated:
  // 9552 steps at 1e-8, none of 1e-9 and 1e-10 done in 60 s).
  std::vector<ReductionVariant> v = {
      {"exact", {"rod.type=exact"}, -1},
      {"full", {"rod.type=flexible", "reduction.method=full", "sim.abs_tol=1e-8"}, -1}};
  for (int k : {0, 1, 2, 4, 8, 16}) {
    v.push_back({"cb-" + std::to_string(k),
                 {"rod.type=flexible", "reduction.method=craig-bampton",
                  "reduction.modes=" + std::to_string(k)},
                 k});
  }
  v.push_back({"orthonormal-cb-8",
               {"rod.type=flexible", "reduction.method=orthonormal-cb", "reduction.modes=8"},
               -1});
  v.push_back({"free-free-8",
               {"rod.type=flexible", "reduction.method=free-free", "reduction.modes=8"},
               -1});
  return v;
}

const char* ReductionFigures::Name(int i) {
  static const char* names[kCount] = {"peak |slider acc.| [m/s^2]",
                                      "p95 per-rev. peak |slider acc.| [m/s^2]",
                                      "amplification + (p95)",
                                      "amplification - (p95)",
                                      "peak bearing force [N]",
                                      "peak gauge strain [1]",
                                      "first impact [s]"};
  return names[i];
}

ReductionFigures FiguresOf(const nlohmann::json& s, double first_impact_time) {
  auto at = [&](std::initializer_list<const char*> path) -> double {
    const nlohmann::json* j = &s;
    for (const char* k : path) {
      if (!j->contains(k) || (*j)[k].is_null()) return NAN;
      j = &(*j)[k];
    }
    return j->get<double>();
  };
  ReductionFigures f;
  f.value[0] = std::max(at({"slider_acceleration", "peak_positive"}),
                        at({"slider_acceleration", "peak_negative"}));
  f.value[1] = at({"slider_acceleration", "per_revolution_abs", "p95"});
  f.value[2] = at({"load_amplification", "slider_acceleration_positive_p95"});
  f.value[3] = at({"load_amplification", "slider_acceleration_negative_p95"});
  f.value[4] = at({"channels", "bearing_force", "peak_abs"});
  double strain = NAN;
  if (s.contains("channels")) {
    for (const auto& [name, c] : s["channels"].items()) {
      if (name.rfind("strain_", 0) == 0)
        strain = std::isnan(strain) ? c["peak_abs"].get<double>()
                                    : std::max(strain, c["peak_abs"].get<double>());
    }
  }
  f.value[5] = strain;
  f.value[6] = first_impact_time;
  return f;
}

ReductionTable TabulateReduction(const std::vector<ReductionVariant>& variants,
                                 const std::vector<ReductionFigures>& figures,
                                 const std::vector<std::string>& outcomes,
                                 const std::vector<double>& walls, double within) {
  ReductionTable t;
  t.header = {"variant", "outcome"};
  for (int c = 0; c < ReductionFigures::kCount; ++c) {
    t.header.push_back(ReductionFigures::Name(c));
    t.header.emplace_back("diff. to exact [%]");
  }
  t.header.push_back("max |diff.| [%]");
  t.header.push_back("wall [s]");
  const ReductionFigures& ref = figures.front();
  for (size_t i = 0; i < variants.size(); ++i) {
    std::vector<std::string> row = {variants[i].name, outcomes[i]};
    double worst = 0.0;
    for (int c = 0; c < ReductionFigures::kCount; ++c) {
      const double v = figures[i].value[c], e = ref.value[c];
      const double diff =
          std::isfinite(v) && std::isfinite(e) && e != 0.0 ? 100.0 * (v - e) / std::abs(e) : NAN;
      if (std::isfinite(diff)) worst = std::max(worst, std::abs(diff));
      row.push_back(StudyNumber(nlohmann::json(v)));
      row.push_back(StudyNumber(nlohmann::json(diff)));
    }
    row.push_back(StudyNumber(nlohmann::json(worst)));
    row.push_back(StudyNumber(nlohmann::json(walls[i])));
    if (variants[i].modes >= 0) {  // the smallest k from which every larger k stays within
      const bool ok = worst <= within && outcomes[i] == "completed";
      if (!ok) t.smallest_k = -1;
      if (ok && t.smallest_k < 0) t.smallest_k = variants[i].modes;
    }
    t.rows.push_back(row);
  }
  return t;
}

}  // namespace flexrod
