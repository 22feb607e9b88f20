// SPDX-License-Identifier: GPL-3.0-or-later
// `flexrod compare SWEEP.h5 [--group I|II|III] [--comparison N] [--out DIR]`: the thesis's
// comparison groups (RIG.md §4) from a sweep store: per comparison a ranking table (Markdown
// and CSV), the agglomerated turning points (CSV) and their 3-D scatter plot and plan view.
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "app/commands.h"
#include "app/plotting.h"
#include "common/error.h"
#include "common/files.h"
#include "sweep/sweep_compare.h"

namespace flexrod::app {
namespace {

struct CompareOptions {
  std::string store;
  std::string group;
  int comparison{0};  ///< 0 = all (when --comparison is not given)
  bool comparison_given{false};
  std::string out{"out/compare"};
  bool no_plot{false};
};

int Compare(const CompareOptions& opt) {
  if (!opt.group.empty() && opt.group != "I" && opt.group != "II" && opt.group != "III") {
    throw InputError("--group", opt.group, "must be I, II or III");
  }
  const auto& all = study::ThesisComparisons();
  if (opt.comparison_given &&
      (opt.comparison < 1 || opt.comparison > static_cast<int>(all.size()))) {
    throw InputError("--comparison", std::to_string(opt.comparison),
                     "must be 1 to " + std::to_string(all.size()));
  }
  std::vector<study::ComparisonDef> defs;
  for (const study::ComparisonDef& d : all) {
    if ((opt.group.empty() || d.group == opt.group) &&
        (opt.comparison == 0 || d.number == opt.comparison)) {
      defs.push_back(d);
    }
  }
  if (defs.empty()) {
    throw InputError("--comparison", std::to_string(opt.comparison),
                     "is not in group " + opt.group);
  }
  const study::SweepStore store = study::ReadStore(opt.store, false);
  const std::vector<study::ComparisonResult> results = study::RunComparisons(defs, store.runs);
  EnsureDirectory("--out", opt.out);
  for (const study::ComparisonResult& r : results) {
    study::WriteComparisonFiles(r, opt.out);
    std::printf("comparison %2d (group %s): %s\n", r.def.number, r.def.group.c_str(),
                r.verdict.c_str());
  }
  study::WriteComparisonIndex(results, opt.store, opt.out);
  std::printf("tables in %s (comparisons.md, comparison_NN.md/.csv/_points.csv)\n",
              opt.out.c_str());
  if (!opt.no_plot) RunPlotScript({"compare", opt.out});
  return 0;
}

}  // namespace

void RegisterCompare(CLI::App& app, Handler* handler) {
  auto opt = std::make_shared<CompareOptions>();
  CLI::App* cmd = app.add_subcommand("compare",
                                     "the thesis's 25 comparisons (groups I-III) from a sweep "
                                     "store: rankings, tables, scatter plots");
  cmd->add_option("store", opt->store, "sweep store FILE.h5 (flexrod sweep)")->required();
  cmd->add_option("--group", opt->group, "only group I, II or III");
  CLI::Option* comparison =
      cmd->add_option("--comparison", opt->comparison, "only comparison N (1-25)");
  cmd->add_option("--out", opt->out, "output directory")->capture_default_str();
  cmd->add_flag("--no-plot", opt->no_plot, "skip the PNG plots");
  cmd->callback([opt, handler, comparison] {
    opt->comparison_given = comparison->count() > 0;
    *handler = [opt] { return Compare(*opt); };
  });
}

}  // namespace flexrod::app
