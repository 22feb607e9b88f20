// SPDX-License-Identifier: GPL-3.0-or-later
// `flexrod study`: runs the rigid-rig studies (run/rigid_rig_studies.h) and the modal reduction
// study (run/reduction_study.h) and writes, into --out, a Markdown and a CSV table, and the runs'
// files for the plots.
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
#include "input/presets.h"
#include "io/run_writer.h"
#include "mechanisms/mechanism_model.h"
#include "run/ensemble.h"
#include "run/reduction_study.h"
#include "run/rigid_rig_studies.h"
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

/// A case of a rigid-rig study: the rigid-rig preset with the case's and the user's overrides,
/// checked as a run would check it (InputError before any run or file).
Config CaseConfig(const StudyOptions& opt, const std::vector<std::string>& sets) {
  Config cfg;
  cfg.LoadToml(FindPreset("rigid-rig")->toml, "rigid-rig");
  for (const std::string& s : RigidRigStudyTolerances()) cfg.SetAssignment(s);
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
  WriteRun({dir, shared == twin_dirs->end() ? "" : shared->second, ""}, cfg, r);
  if (r.ideal && shared == twin_dirs->end()) (*twin_dirs)[r.ideal.get()] = dir;
  if (!opt.no_plot) PlotRun(opt.out_dir + "/" + tag);  // slider acceleration against the ideal twin
  return RigidRigStudyFigures(multibody::ToString(r.status.outcome), r.summary, wall);
}

/// The case of the reduction and damping studies: the input (a preset or a TOML file) with the
/// user's --set overrides.
Config StudyInput(const StudyOptions& opt) {
  Config base;
  if (const Preset* preset = FindPreset(opt.input)) {
    base.LoadToml(preset->toml, opt.input);
  } else {
    base.LoadTomlFile(opt.input);
  }
  for (const std::string& s : opt.sets) base.SetAssignment(s);
  return base;
}

// ---- the modal reduction study (variants and figures: run/reduction_study.h) ------------

int RunReductionStudy(const StudyOptions& opt) {
  Require(opt.within > 0.0 && std::isfinite(opt.within), "--within", opt.within,
          "must be a finite percentage > 0 [%]");
  const Config base = StudyInput(opt);
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
  const ReductionTable table = TabulateReduction(variants, figures, outcomes, walls, opt.within);
  WriteTables(opt.out_dir, "Modal reduction study: " + opt.input + " (reference: the exact rod)",
              table.header, table.rows);
  std::ostringstream verdict;
  verdict << "smallest Craig-Bampton k from which every larger k is within " << opt.within
          << " % of the exact rod on every figure: "
          << (table.smallest_k >= 0 ? std::to_string(table.smallest_k)
                                    : std::string("none of 0, 1, 2, 4, 8, 16"))
          << "\n";
  std::fputs(verdict.str().c_str(), stdout);
  WriteFileAtomic(opt.out_dir + "/verdict.txt", verdict.str());
  if (!opt.no_plot) RunPlotScript({"reduction", opt.out_dir});
  return 0;
}

// ---- the damping study: one case under every damping model ----------------------------

/// The damping models the study puts side by side; the first is the default (the reference).
struct DampingVariant {
  const char* name;
  std::vector<std::string> sets;
};
const std::vector<DampingVariant>& DampingVariants() {
  static const std::vector<DampingVariant> variants = {
      {"band", {"damping.type=band"}},
      {"material", {"damping.type=material"}},
      {"ratio-1%", {"damping.type=ratio", "damping.ratio=0.01"}},
      {"ratio-2%", {"damping.type=ratio", "damping.ratio=0.02"}},
      {"ratio-5%", {"damping.type=ratio", "damping.ratio=0.05"}},
      {"rayleigh-2e-5", {"damping.type=rayleigh", "damping.alpha=0", "damping.beta=2e-5 s"}}};
  return variants;
}

/// The ensemble figures a damping study tabulates: (summary.json ensemble.figures name, column).
const std::vector<std::pair<const char*, const char*>>& DampingFigures() {
  static const std::vector<std::pair<const char*, const char*>> figures = {
      {"slider_acceleration_positive_p95", "amplification + (p95)"},
      {"slider_acceleration_negative_p95", "amplification - (p95)"},
      {"bearing_force_p95", "bearing-force amplification (p95)"},
      {"gauge_stress_p95 [Pa]", "gauge stress p95 [MPa]"}};
  return figures;
}

int RunDampingStudy(const StudyOptions& opt) {
  const Config base = StudyInput(opt);
  std::vector<Config> configs;
  for (const DampingVariant& v : DampingVariants()) {  // every variant checked before any run
    Config cfg = base;
    for (const std::string& s : v.sets) cfg.SetAssignment(s);
    cfg.Resolve();
    CheckRunInput(cfg, BuildMechanism(cfg, nullptr));
    configs.push_back(cfg);
  }
  EnsureDirectory("--out", opt.out_dir);
  std::vector<nlohmann::json> ensembles;
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> header = {"damping", "outcome", "steady states"};
  for (const auto& [key, column] : DampingFigures()) {
    header.push_back(column);
    header.push_back(std::string(column) + " 95 % interval");
    header.push_back("vs band [%]");
  }
  for (size_t i = 0; i < configs.size(); ++i) {
    const DampingVariant& v = DampingVariants()[i];
    std::fprintf(stderr, "study damping: %s\n", v.name);
    RunOutputOptions outputs;
    outputs.keep_channel = [](const std::string&) { return false; };
    const RunResult r = RunEnsemble(configs[i], outputs);
    const std::string dir = opt.out_dir + "/" + v.name;
    EnsureDirectory("--out", dir);
    WriteFileAtomic(dir + "/resolved.toml", configs[i].ResolvedToml({}));
    WriteFileAtomic(dir + "/summary.json", r.summary.dump(2) + "\n");
    const nlohmann::json e = r.summary.value("ensemble", nlohmann::json::object());
    ensembles.push_back(e);
    std::vector<std::string> row = {
        v.name, multibody::ToString(r.status.outcome),
        e.contains("regime") ? std::to_string(e["regime"]["steady_states"].get<int>()) : "-"};
    for (const auto& [key, column] : DampingFigures()) {
      const double scale = std::string(key).find("[Pa]") != std::string::npos ? 1e-6 : 1.0;
      auto figure = [&](const nlohmann::json& ens) -> const nlohmann::json* {
        return ens.contains("figures") && ens["figures"].contains(key) ? &ens["figures"][key]
                                                                       : nullptr;
      };
      const nlohmann::json* f = figure(e);
      const nlohmann::json* ref = figure(ensembles.front());
      char c[32] = "-", in[64] = "-", d[32] = "-";
      if (f) {
        std::snprintf(c, sizeof c, "%.4g", (*f)["centre"].get<double>() * scale);
        std::snprintf(in, sizeof in, "%.4g .. %.4g", (*f)["interval"][0].get<double>() * scale,
                      (*f)["interval"][1].get<double>() * scale);
        if (ref) {
          std::snprintf(
              d, sizeof d, "%+.1f",
              100.0 * ((*f)["centre"].get<double>() / (*ref)["centre"].get<double>() - 1.0));
        }
      }
      row.insert(row.end(), {c, in, d});
    }
    rows.push_back(row);
  }
  WriteTables(opt.out_dir,
              "Damping study: " + opt.input +
                  " (each damping model's ensemble; reference: band, the default)",
              header, rows);
  if (!opt.no_plot) RunPlotScript({"damping", opt.out_dir});
  return 0;
}

int RunStudy(const StudyOptions& opt) {
  if (opt.name == "reduction") return RunReductionStudy(opt);
  if (opt.name == "damping") return RunDampingStudy(opt);
  if (opt.input_given) {
    throw InputError("input", opt.input,
                     "only the reduction and damping studies take an input; the rigid-rig studies "
                     "run the "
                     "rigid-rig preset (change it with --set)");
  }
  const RigidRigStudy study = FindRigidRigStudy(opt.name);
  std::vector<Config> configs;  // every case's input checked before any run or file
  for (const StudyCase& c : study.cases) configs.push_back(CaseConfig(opt, c.sets));
  EnsureDirectory("--out", opt.out_dir);
  std::vector<std::vector<std::string>> rows;
  TwinCache twins;  // the laws (or clearances and frictions) at one speed share one ideal twin
  TwinDirs twin_dirs;
  for (size_t i = 0; i < study.cases.size(); ++i) {
    const StudyCase& c = study.cases[i];
    std::fprintf(stderr, "study: %s\n", c.tag.c_str());
    std::vector<std::string> row = c.row;
    const auto res = RunCase(opt, c.tag, configs[i], &twins, &twin_dirs);
    row.insert(row.end(), res.begin(), res.end());
    rows.push_back(row);
  }
  WriteTables(opt.out_dir, study.title, study.header, rows);
  if (!opt.no_plot) RunPlotScript({"study", opt.out_dir});
  return 0;
}

}  // namespace

void RegisterStudy(CLI::App& app, Handler* handler) {
  auto opt = std::make_shared<StudyOptions>();
  CLI::App* cmd = app.add_subcommand(
      "study",
      "the rigid-rig studies of the thesis (chapter 3), the modal reduction study and the "
      "damping study (one case's ensemble under band, material, ratio 1/2/5 % and Rayleigh "
      "damping)");
  cmd->add_option("name", opt->name, "rigid-rig-laws | rigid-rig-friction | reduction | damping")
      ->required()
      ->check(CLI::Validator(
          [](std::string& name) {  // CLI11's IsMember leaves an empty name unquoted
            for (const char* known :
                 {"rigid-rig-laws", "rigid-rig-friction", "reduction", "damping"}) {
              if (name == known) return std::string();
            }
            return "\"" + name +
                   "\" not in {rigid-rig-laws, rigid-rig-friction, reduction, damping}";
          },
          "rigid-rig-laws|rigid-rig-friction|reduction|damping"));
  cmd->add_option("input", opt->input, "reduction, damping: the case, a preset or a TOML file")
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
