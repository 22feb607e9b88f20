// run/reduction_study.h — the pieces of the modal reduction study (`flexrod study
// reduction`, and examples/python/reduction_convergence.py through the Python module): one
// case with the rod as the exact body (the reference), the full FE model, Craig–Bampton with
// k = 0, 1, 2, 4, 8, 16 fixed-interface modes and the other bases at 8 modes; per variant the
// headline figures, compared with the exact rod's, and the verdict. What does not live here:
// running the variants, writing the tables and the plot (app/cmd_study.cc).
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace flexrod {

struct ReductionVariant {
  std::string name;               ///< "exact", "full", "cb-4", "free-free-8", ...
  std::vector<std::string> sets;  ///< "key=value" assignments on top of the case
  int modes{-1};                  ///< Craig–Bampton fixed-interface modes, −1 for the others
};

/// The variants in table order; the first (the exact rod) is the reference.
std::vector<ReductionVariant> ReductionVariants();

/// The figures a variant is judged by (NaN where the case has none, e.g. no clearance joint).
struct ReductionFigures {
  static constexpr int kCount = 7;
  /// With its unit: "peak |slider acc.| [m/s^2]", ..., "first impact [s]".
  static const char* Name(int i);
  double value[kCount];
};

/// The figures of a run from its summary and the time of its first impact [s] (NaN if none).
ReductionFigures FiguresOf(const nlohmann::json& summary, double first_impact_time);

/// The study's table: per variant its outcome, each figure with its difference to the
/// reference's [%], the largest |difference| [%] and the wall time [s]; and the smallest
/// Craig–Bampton k from which every larger k completed within `within` [%] on every figure
/// (−1 if none). `figures`, `outcomes` and `walls` are in the order of `variants`.
struct ReductionTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  int smallest_k{-1};
};
ReductionTable TabulateReduction(const std::vector<ReductionVariant>& variants,
                                 const std::vector<ReductionFigures>& figures,
                                 const std::vector<std::string>& outcomes,
                                 const std::vector<double>& walls, double within);

}  // namespace flexrod
