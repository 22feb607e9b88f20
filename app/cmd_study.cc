// SPDX-License-Identifier: GPL-3.0-or-later
// `flexrod study rigid-rig-laws` (thesis §3.3: every normal law at 101 and 177 rpm, 1 mm
// clearance) and `flexrod study rigid-rig-friction` (thesis §3.4 / Fig. 39: clearance 0.5 and
// 1.0 mm × joint friction 0.2, 0.4, 0.6). Each writes a Markdown and a CSV table, and the runs'
// channels for the plots, into --out.
#include <CLI/CLI.hpp>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <map>
#include <memory>
#include <sstream>

#include "app/commands.h"
#include "app/plotting.h"
#include "common/error.h"
#include "common/files.h"
#include "contact/normal_law.h"
#include "input/presets.h"
#include "io/run_files.h"
#include "mechanisms/mechanism_model.h"
#include "run/reduction_study.h"
#include "run/run.h"

namespace flexrod::app {
namespace {

struct StudyOptions {
  std::string name;
  std::string input{"flexible-rig"};  ///< reduction: the case (preset or TOML file)
  bool input_given{false};            ///< the input positional was given
  std::string out_dir{"out/study"};
  std::vector<std::string> sets;
  bool no_plot{false};
  double within{2.0};  ///< reduction: the agreement asked of a Craig–Bampton basis [%]
};

std::string Num(const nlohmann::json& j) {
  if (j.is_null() || std::isnan(j.get<double>())) return "n/a";
  std::ostringstream os;
  os.precision(4);
  os << j.get<double>();
  return os.str();
}

void WriteTables(const std::string& dir, const std::string& title,
                 const std::vector<std::string>& header,
                 const std::vector<std::vector<std::string>>& rows) {
  std::ostringstream md, csv;
  md << "# " << title << "\n\n|";
  for (const auto& h : header) md << " " << h << " |";
  md << "\n|";
  for (size_t i = 0; i < header.size(); ++i) md << "---|";
  md << "\n";
  for (size_t i = 0; i < header.size(); ++i) csv << (i ? "," : "") << header[i];
  csv << "\n";
  for (const auto& r : rows) {
    md << "|";
    for (const auto& c : r) md << " " << c << " |";
    md << "\n";
    for (size_t i = 0; i < r.size(); ++i) csv << (i ? "," : "") << r[i];
    csv << "\n";
  }
  WriteFileAtomic(dir + "/table.md", md.str());
  WriteFileAtomic(dir + "/table.csv", csv.str());
  std::fputs(md.str().c_str(), stdout);
}

/// The output directory where each shared ideal twin was first written (the cases at one speed
/// share one twin; the later cases link to it).
using TwinDirs = std::map<const study::TimeSeries*, std::string>;

/// Integrator tolerances of every study case (a --set overrides them). Impact peaks on this rig
/// need them. Measured at joint friction 0.6, 177 rpm, 0.5 mm (peak / median per-revolution
/// peak |a| [m/s^2]): 1326 / 1200 at the run default 1e-6/1e-8 (one revolution's outlier,
/// above the 1256 of 1.0 mm: Fig. 39's clearance order reversed), 1191.3 / 1190.3 at
/// 1e-8/1e-10, 1191.3 / 1190.4 at 1e-9/1e-11. 1.0 mm: 1256 / 1254, 1252.5 / 1249.5,
/// 1252.4 / 1249.7. The cost is 1.4 times the steps (tests/run/clearance_trends_slowtest.cc
/// runs at these too).
const std::vector<std::string> kStudyTolerances = {"sim.rel_tol=1e-8", "sim.abs_tol=1e-10"};

/// A case of a rigid-rig study: the rigid-rig preset with the case's and the user's overrides,
/// checked as a run would check it (InputError before any run or file).
Config CaseConfig(const StudyOptions& opt, const std::vector<std::string>& sets) {
  Config cfg;
  cfg.LoadToml(FindPreset("rigid-rig")->toml, "rigid-rig");
  for (const std::string& s : kStudyTolerances) cfg.SetAssignment(s);
  for (const std::string& s : sets) cfg.SetAssignment(s);
  for (const std::string& s : opt.sets) cfg.SetAssignment(s);
  CheckRunInput(cfg, BuildMechanism(cfg, nullptr));
  return cfg;
}

/// One case of a study, run and written to dir/<tag>.
std::vector<std::string> RunCase(const StudyOptions& opt, const std::string& tag, const Config& cfg,
                                 TwinCache* twins, TwinDirs* twin_dirs) {
  const auto t0 = std::chrono::steady_clock::now();
  RunOutputOptions outputs;
  outputs.twins = twins;
  const RunResult r = RunSimulation(cfg, nullptr, false, outputs);
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const std::string dir = opt.out_dir + "/" + tag;
  const auto shared = r.ideal ? twin_dirs->find(r.ideal.get()) : twin_dirs->end();
  WriteRunFiles(dir, cfg, r, shared == twin_dirs->end() ? "" : shared->second);
  if (r.ideal && shared == twin_dirs->end()) (*twin_dirs)[r.ideal.get()] = dir;
  if (!opt.no_plot) PlotRun(opt.out_dir + "/" + tag);  // slider acceleration against the ideal twin
  const auto& s = r.summary;
  auto get = [&](const char* a, const char* b) {
    return s.contains(a) && s[a].contains(b) ? Num(s[a][b]) : std::string("n/a");
  };
  std::string peak = "n/a", median = "n/a";
  if (s.contains("slider_acceleration")) {
    const nlohmann::json& a = s["slider_acceleration"];
    peak = Num(std::max(a["peak_positive"].get<double>(), a["peak_negative"].get<double>()));
    median = Num(a["per_revolution_abs"]["median"]);
  }
  return {multibody::ToString(r.status.outcome),
          peak,
          median,
          get("load_amplification", "slider_acceleration_positive"),
          get("load_amplification", "slider_acceleration_negative"),
          get("impacts", "per_revolution"),
          get("load_amplification", "bearing_force_peak_real [N]"),
          Num(wall)};
}

// ---- the modal reduction study (variants and figures: run/reduction_study.h) ------------

int RunReductionStudy(const StudyOptions& opt) {
  Require(opt.within > 0.0 && std::isfinite(opt.within), "--within", opt.within,
          "must be a finite percentage > 0 [%]");
  Config base;
  if (const Preset* preset = FindPreset(opt.input)) {
    base.LoadToml(preset->toml, opt.input);
  } else {
    base.LoadTomlFile(opt.input);
  }
  for (const std::string& s : opt.sets) base.SetAssignment(s);
  const std::vector<ReductionVariant> variants = ReductionVariants();
  std::vector<Config> configs;
  for (const ReductionVariant& v : variants) {  // every variant's input checked before any run
    Config cfg = base;
    for (const std::string& s : v.sets) cfg.SetAssignment(s);
    cfg.Resolve();
    CheckRunInput(cfg, BuildMechanism(cfg, nullptr));  // InputError before any run
    configs.push_back(cfg);
  }
  EnsureDirectory("--out", opt.out_dir);
  std::vector<ReductionFigures> figures;
  std::vector<double> walls;
  std::vector<std::string> outcomes;
  for (size_t i = 0; i < variants.size(); ++i) {
    std::fprintf(stderr, "study reduction: %s\n", variants[i].name.c_str());
    const auto t0 = std::chrono::steady_clock::now();
    const RunResult r = RunSimulation(configs[i], nullptr, false, RunOutputOptions{});
    walls.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count());
    outcomes.push_back(multibody::ToString(r.status.outcome));
    figures.push_back(FiguresOf(r.summary, r.impacts.empty() ? NAN : r.impacts.front().time));
    // Each variant's summary and input (its channels would be 0.5 GB a variant on the rig).
    const std::string dir = opt.out_dir + "/" + variants[i].name;
    EnsureDirectory("--out", dir);
    WriteFileAtomic(dir + "/resolved.toml", configs[i].ResolvedToml({}));
    WriteFileAtomic(dir + "/summary.json", r.summary.dump(2) + "\n");
  }
  // Differences to the exact rod, and the smallest Craig–Bampton k within opt.within on all.
  const ReductionFigures& ref = figures.front();
  std::vector<std::string> header = {"variant", "outcome"};
  for (int c = 0; c < ReductionFigures::kCount; ++c) {
    header.push_back(ReductionFigures::Name(c));
    header.push_back(std::string("diff. to exact [%]"));
  }
  header.push_back("max |diff.| [%]");
  header.push_back("wall [s]");
  std::vector<std::vector<std::string>> rows;
  int smallest_k = -1;
  for (size_t i = 0; i < variants.size(); ++i) {
    std::vector<std::string> row = {variants[i].name, outcomes[i]};
    double worst = 0.0;
    for (int c = 0; c < ReductionFigures::kCount; ++c) {
      const double v = figures[i].value[c], e = ref.value[c];
      const double diff =
          std::isfinite(v) && std::isfinite(e) && e != 0.0 ? 100.0 * (v - e) / std::abs(e) : NAN;
      if (std::isfinite(diff)) worst = std::max(worst, std::abs(diff));
      row.push_back(Num(nlohmann::json(v)));
      row.push_back(Num(nlohmann::json(diff)));
    }
    row.push_back(Num(nlohmann::json(worst)));
    row.push_back(Num(nlohmann::json(walls[i])));
    if (variants[i].modes >= 0) {  // the smallest k from which every larger k stays within
      const bool within = worst <= opt.within && outcomes[i] == "completed";
      if (!within) smallest_k = -1;
      if (within && smallest_k < 0) smallest_k = variants[i].modes;
    }
    rows.push_back(row);
  }
  WriteTables(opt.out_dir, "Modal reduction study: " + opt.input + " (reference: the exact rod)",
              header, rows);
  std::ostringstream verdict;
  verdict << "smallest Craig-Bampton k from which every larger k is within " << opt.within
          << " % of the exact rod on every figure: "
          << (smallest_k >= 0 ? std::to_string(smallest_k)
                              : std::string("none of 0, 1, 2, 4, 8, 16"))
          << "\n";
  std::fputs(verdict.str().c_str(), stdout);
  WriteFileAtomic(opt.out_dir + "/verdict.txt", verdict.str());
  if (!opt.no_plot) RunPlotScript({"reduction", opt.out_dir});
  return 0;
}

int RunStudy(const StudyOptions& opt) {
  if (opt.name == "reduction") return RunReductionStudy(opt);
  struct Case {
    std::string tag;
    std::vector<std::string> row, sets;
  };
  if (opt.input_given) {
    throw InputError("input", opt.input,
                     "only the reduction study takes an input; the rigid-rig studies run the "
                     "rigid-rig preset (change it with --set)");
  }
  std::vector<Case> cases;
  std::string title;
  std::vector<std::string> header;
  if (opt.name == "rigid-rig-laws") {
    title = "Rigid rig, 1 mm clearance: every normal law (thesis section 3.3)";
    header = {"law", "speed [rpm]"};
    for (const std::string& law : contact::NormalLawNames()) {
      for (const char* rpm : {"101", "177"}) {
        cases.push_back({law + "-" + rpm + "rpm",
                         {law, rpm},
                         {"joint.type=clearance", "joint.clearance=1 mm", "joint.law=" + law,
                          "drive.speed=" + std::string(rpm) + " rpm"}});
      }
    }
  } else {
    title = "Rigid rig: clearance x joint friction (thesis section 3.4, Fig. 39)";
    header = {"clearance [mm]", "friction [-]"};
    for (const char* c : {"0.5", "1.0"}) {
      for (const char* mu : {"0.2", "0.4", "0.6"}) {
        cases.push_back({std::string("c") + c + "mm-mu" + mu,
                         {c, mu},
                         {"joint.type=clearance", std::string("joint.clearance=") + c + " mm",
                          std::string("joint.friction=") + mu}});
      }
    }
  }
  std::vector<Config> configs;  // every case's input checked before any run or file
  for (const Case& c : cases) configs.push_back(CaseConfig(opt, c.sets));
  EnsureDirectory("--out", opt.out_dir);
  const std::vector<std::string> cols = {"outcome",
                                         "peak abs slider acc. [m/s^2]",
                                         "median per-rev. peak abs slider acc. [m/s^2]",
                                         "amplification +",
                                         "amplification -",
                                         "impacts per rev.",
                                         "peak bearing force [N]",
                                         "wall [s]"};
  std::vector<std::vector<std::string>> rows;
  TwinCache twins;  // the laws (or clearances and frictions) at one speed share one ideal twin
  TwinDirs twin_dirs;
  for (size_t i = 0; i < cases.size(); ++i) {
    std::fprintf(stderr, "study: %s\n", cases[i].tag.c_str());
    std::vector<std::string> row = cases[i].row;
    const auto res = RunCase(opt, cases[i].tag, configs[i], &twins, &twin_dirs);
    row.insert(row.end(), res.begin(), res.end());
    rows.push_back(row);
  }
  header.insert(header.end(), cols.begin(), cols.end());
  WriteTables(opt.out_dir, title, header, rows);
  if (!opt.no_plot) RunPlotScript({"study", opt.out_dir});
  return 0;
}

}  // namespace

void RegisterStudy(CLI::App& app, Handler* handler) {
  auto opt = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study", "the rigid-rig studies of the thesis (chapter 3) and the modal reduction study");
  cmd->add_option("name", opt->name, "rigid-rig-laws | rigid-rig-friction | reduction")
      ->required()
      ->check(CLI::Validator(
          [](std::string& name) {  // CLI11's IsMember leaves an empty name unquoted
            for (const char* known : {"rigid-rig-laws", "rigid-rig-friction", "reduction"}) {
              if (name == known) return std::string();
            }
            return "\"" + name + "\" not in {rigid-rig-laws, rigid-rig-friction, reduction}";
          },
          "rigid-rig-laws|rigid-rig-friction|reduction"));
  cmd->add_option("input", opt->input, "reduction: the case, a preset or a TOML file")
      ->capture_default_str()
      ->each([opt](const std::string&) { opt->input_given = true; });
  cmd->add_option("--within", opt->within,
                  "reduction: the agreement with the exact rod asked of a Craig-Bampton basis [%]")
      ->capture_default_str();
  cmd->add_option("--out", opt->out_dir, "output directory")->capture_default_str();
  cmd->add_option("--set", opt->sets, "override a key of every run, e.g. --set sim.capture=\"1 s\"")
      ->take_all();
  cmd->add_flag("--no-plot", opt->no_plot, "skip the PNG plots");
  cmd->callback([opt, handler] { *handler = [opt] { return RunStudy(*opt); }; });
}

}  // namespace flexrod::app
