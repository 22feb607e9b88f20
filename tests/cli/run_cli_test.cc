// SPDX-License-Identifier: GPL-3.0-or-later
// The documented interface: `flexrod run`, `flexrod modes`, presets (examples run in CI on a
// short horizon), exit codes and "no half-written output".
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "common/hdf5.h"
#include "io/run_writer.h"
#include "multibody/mechanism.h"
#include "sweep/sweep_store.h"
#include "tests/test_util.h"

namespace {

using flexrod::IsStandardChannel;
using flexrod::Vec;
namespace h5 = flexrod::h5;
namespace study = flexrod::study;

namespace fs = std::filesystem;
using flexrod::test::CommandResult;
using flexrod::test::Flexrod;
using flexrod::test::ScratchPath;
using flexrod::test::Shell;

/// Each command, with `--out DIR` appended, exits with 2 and DIR is never created.
void ExpectExitTwoAndNoOutput(const std::string& name, const std::vector<std::string>& commands) {
  const fs::path out = ScratchPath("cli_" + name);
  for (const std::string& c : commands) {
    EXPECT_EQ(Flexrod(c + " --out " + out.string()).exit_code, 2) << c;
    EXPECT_FALSE(fs::exists(out)) << c;
  }
}

TEST(RunCli, EveryPresetRunsOnAShortHorizon) {
  for (const std::string preset :
       {"flexible-rig", "rigid-rig", "simeon-crank", "flexible-pendulum"}) {
    const fs::path out = ScratchPath("cli_" + preset);
    const int rc = Flexrod("run " + preset +
                           " --no-plot --set sim.settle=0.01s --set sim.capture=0.02s "
                           "--set sim.sample_rate=2kHz --out " +
                           out.string())
                       .exit_code;
    EXPECT_EQ(rc, 0) << preset;
    EXPECT_TRUE(fs::exists(out / "run.h5")) << preset;
    EXPECT_FALSE(fs::exists(out / "channels.csv")) << preset;  // CSV only on request
    EXPECT_TRUE(fs::exists(out / "resolved.toml")) << preset;
    std::ifstream in(out / "summary.json");
    const nlohmann::json s = nlohmann::json::parse(in);
    EXPECT_EQ(s["integrator"]["outcome"], "completed") << preset;
    fs::remove_all(out);
  }
}

// A clearance run's ideal-joint twin is a run of its own; its warnings (here: a loose
// tolerance breaks its energy balance) reach the console, marked, not only summary.json.
TEST(RunCli, TheTwinsWarningsAreShown) {
  const fs::path out = ScratchPath("cli_twin_warning");
  const CommandResult run = Flexrod(
      "run rigid-rig --no-plot --set sim.rel_tol=1e-2 --set sim.settle=0.1s "
      "--set sim.capture=0.4s --set sim.sample_rate=2kHz --out " +
      out.string());
  ASSERT_EQ(run.exit_code, 0) << run.output;
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  ASSERT_TRUE(s["ideal"].contains("warnings"));
  for (const auto& w : s["ideal"]["warnings"]) {
    EXPECT_NE(run.output.find("flexrod: warning: ideal-joint twin: " + w.get<std::string>()),
              std::string::npos)
        << run.output;
  }
  fs::remove_all(out);
}

TEST(RunCli, ExampleFilesRunAsInputFiles) {
  const fs::path out = ScratchPath("cli_file");
  EXPECT_EQ(Flexrod("run " + std::string(FLEXROD_SOURCE_DIR) +
                    "/examples/rigid-rig.toml --no-plot "
                    "--set sim.settle=0s --set sim.capture=0.02s --out " +
                    out.string())
                .exit_code,
            0);
  fs::remove_all(out);
}

TEST(RunCli, BadInputExitsWithTwoAndWritesNothing) {
  const fs::path bad_toml = ScratchPath("cli_bad_toml");
  fs::create_directories(bad_toml);
  std::ofstream(bad_toml / "x.toml") << "[rod\nheight = ";
  ExpectExitTwoAndNoOutput(
      "bad", {"run --set rod.colour=red", "run --set rod.height=-3mm", "run --set drive.speed=fast",
              "run no-such-preset", "run " + (bad_toml / "x.toml").string(),
              // Not a TOML file: a directory or a device used to run the defaults.
              "run " + bad_toml.string(), "run /dev/null",
              // Tolerances beyond the doubles' reach, named by the user's key.
              "run --set sim.abs_tol=1e-300", "run --set sim.rel_tol=1e-17",
              "run --set sim.max_steps=-1"});
  fs::remove_all(bad_toml);
}

// `run --check` repeats the run at 100x tighter tolerances and writes every headline figure's
// difference into the summary; a check that would go below the tolerance floor is refused
// before any work.
TEST(RunCli, CheckWritesTheDifferencesAtTighterTolerances) {
  const fs::path out = ScratchPath("cli_check");
  ASSERT_EQ(
      Flexrod("run rigid-rig --check --no-plot --set joint.type=clearance --set sim.settle=0s "
              "--set sim.capture=0.4s --out " +
              out.string())
          .exit_code,
      0);
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  ASSERT_TRUE(s.contains("accuracy_check"));
  const auto& c = s["accuracy_check"];
  EXPECT_DOUBLE_EQ(c["rel_tol"].get<double>(), 1e-8);  // the preset's 1e-6 / 100
  EXPECT_TRUE(c["figures"].contains("slider_acceleration.per_revolution_abs.p95"));
  EXPECT_TRUE(c["figures"].contains("load_amplification.slider_acceleration_positive"));
  EXPECT_EQ(c["reference_outcome"], "completed");
  fs::remove_all(out);
  ExpectExitTwoAndNoOutput("check_floor", {"run rigid-rig --check --set sim.rel_tol=1e-13"});
}

// `run --profile` times the integrator's calls: the summary carries their wall times, each
// within the solver wall and together no more than it, and the report prints their shares;
// it also counts, step by step, the unknown whose local error estimate set the step.
TEST(RunCli, ProfileWritesAndPrintsTheIntegratorsTimeShares) {
  const fs::path out = ScratchPath("cli_profile");
  const CommandResult r = Flexrod(
      "run rigid-rig --profile --no-plot --set sim.settle=0s --set sim.capture=0.2s --out " +
      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("solver wall shares (--profile): residuals"), std::string::npos)
      << r.output;
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  const auto& it = s["integrator"];
  const double wall = it["wall_time [s]"].get<double>();
  double sum = it["output_time [s]"].get<double>();
  for (const char* key : {"residual_time [s]", "jacobian_time [s]", "linear_solve_time [s]"}) {
    ASSERT_TRUE(it.contains(key)) << key;
    const double t = it[key].get<double>();
    EXPECT_GT(t, 0.0) << key;
    sum += t;
  }
  EXPECT_LE(sum, wall);
  // The unknowns that set the step: one per step, so their counts add up to the steps.
  EXPECT_NE(r.output.find("step set by (--profile, largest weighted local error): "),
            std::string::npos)
      << r.output;
  long counted = 0;
  for (const auto& u : it["step_limiting_unknowns"]) {
    EXPECT_FALSE(u["unknown"].get<std::string>().empty());
    counted += u["steps"].get<long>();
  }
  EXPECT_EQ(counted, it["steps"].get<long>());
  fs::remove_all(out);
  // Without the flag, nothing is timed and nothing is printed.
  const CommandResult plain = Flexrod(
      "run rigid-rig --no-plot --set sim.settle=0s --set sim.capture=0.2s --out " + out.string());
  ASSERT_EQ(plain.exit_code, 0);
  EXPECT_EQ(plain.output.find("solver wall shares"), std::string::npos);
  std::ifstream in2(out / "summary.json");
  const nlohmann::json plain_integrator = nlohmann::json::parse(in2)["integrator"];
  EXPECT_FALSE(plain_integrator.contains("residual_time [s]"));
  EXPECT_FALSE(plain_integrator.contains("step_limiting_unknowns"));
  EXPECT_EQ(plain.output.find("step set by"), std::string::npos);
  fs::remove_all(out);
}

// An --out that cannot be a directory (a regular file) is refused before the run, not after
// it (the whole simulation used to be lost), and the file is left as it was.
TEST(RunCli, OutThatCannotBeADirectoryExitsWithTwoBeforeTheRun) {
  const fs::path dir = ScratchPath("cli_out_file");
  fs::create_directories(dir);
  const fs::path file = dir / "a_file";
  std::ofstream(file) << "keep";
  EXPECT_EQ(Flexrod("run --out " + file.string()).exit_code, 2);  // the default 4.2 s flexible rig
  EXPECT_EQ(Flexrod("run --out " + (file / "sub").string()).exit_code, 2);
  std::ifstream in(file);
  std::string text;
  in >> text;
  EXPECT_EQ(text, "keep");
  fs::remove_all(dir);
}

// A run that fails numerically exits 1, keeps what it computed and reports the time, the
// state (norms, the variable with the largest residual) and a hint naming the user's key.
TEST(RunCli, NumericalFailureReportsTimeStateAndHint) {
  const fs::path out = ScratchPath("cli_failure");
  const CommandResult run = Flexrod(
      "run rigid-rig --no-plot --set sim.settle=0s --set sim.capture=0.05s "
      "--set sim.max_steps=10 --out " +
      out.string());
  EXPECT_EQ(run.exit_code, 1);
  for (const char* part :
       {"step-limit at t = ", "hint: increase the step budget (sim.max_steps)",
        "|p| = ", "p[crank.theta] = ", "v[slider.x] = ", "largest residual", "kept "}) {
    EXPECT_NE(run.output.find(part), std::string::npos) << part << "\n" << run.output;
  }
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  fs::remove_all(out);
}

TEST(ModesCli, JsonHasTheDocumentedKeys) {
  const fs::path dir = ScratchPath("cli_modes");
  fs::create_directories(dir);
  const fs::path json = dir / "modes.json";
  ASSERT_EQ(
      Flexrod("modes --material brass --height 12.7mm --modes 6 --json " + json.string()).exit_code,
      0);
  std::ifstream in(json);
  const nlohmann::json j = nlohmann::json::parse(in);
  ASSERT_TRUE(j.contains("modes"));
  ASSERT_GE(j["modes"].size(), 9u);
  for (const char* key :
       {"full_hz", "reduced_hz", "rel_error", "mac", "effective_mass", "rigid_body"}) {
    EXPECT_TRUE(j["modes"][0].contains(key)) << key;
  }
  // Craig–Bampton frequencies are upper bounds; the first modes are accurate.
  const double f1 = j["modes"][0]["full_hz"], r1 = j["modes"][0]["reduced_hz"];
  EXPECT_GE(r1, f1 * (1 - 1e-12));
  EXPECT_LT(r1 / f1 - 1, 1e-5);  // 8 fixed-interface modes
  EXPECT_GT(j["modes"][0]["mac"].get<double>(), 0.9999);
  EXPECT_EQ(j["inputs"]["rod.material"]["value"], "brass");
  // The run's rod in its mechanism, with the band's ratio of each mode (issue 57 item 3): the
  // ratios are the band's at each frequency, 1 % on the first (below 70.7 Hz), critical above
  // 1.414 kHz, in between where the band is smooth.
  ASSERT_GE(j["mechanism_modes"].size(), 5u);
  const flexrod::multibody::DampingSpec band = flexrod::multibody::DampingSpec::FrequencyBand();
  double previous = 0.0;
  for (const auto& m : j["mechanism_modes"]) {
    const double f = m["frequency_hz"], zeta = m["damping_ratio"];
    EXPECT_GT(f, previous);
    previous = f;
    EXPECT_DOUBLE_EQ(zeta, band.BandRatio(f)) << f << " Hz";
  }
  EXPECT_EQ(j["mechanism_modes"][0]["damping_ratio"].get<double>(), 0.01);
  EXPECT_EQ(j["units"]["frequency_hz"], "Hz");
  fs::remove_all(dir);
}

TEST(ModesCli, BadFlagsExitWithTwoAndWriteNothing) {
  const fs::path dir = ScratchPath("cli_modes_bad");
  fs::create_directories(dir);
  const fs::path json = dir / "m.json";
  for (const std::string args :
       {"--height -3mm", "--material unobtainium", "--E abc", "--modes 5000", "--elements 0",
        "--bc glued", "--reduction magic", "--interface 999", "--length \"3 kg\""}) {
    EXPECT_EQ(Flexrod("modes " + args + " --json " + json.string()).exit_code, 2) << args;
    EXPECT_FALSE(fs::exists(json)) << args;
  }
  fs::remove_all(dir);
}

TEST(ModesCli, FreeFreeReportsRigidBodyModes) {
  const fs::path dir = ScratchPath("cli_modes_ff");
  fs::create_directories(dir);
  const fs::path json = dir / "m.json";
  ASSERT_EQ(Flexrod("modes --bc free-free --reduction free-free --modes 4 --json " + json.string())
                .exit_code,
            0);
  std::ifstream in(json);
  const nlohmann::json j = nlohmann::json::parse(in);
  int rigid = 0;
  for (const auto& m : j["modes"]) rigid += m["rigid_body"].get<bool>();
  EXPECT_EQ(rigid, 3);
  fs::remove_all(dir);
}

}  // namespace

namespace {

TEST(StudyCli, FrictionStudyWritesItsTablesAndRejectsUnknownStudies) {
  const fs::path out = ScratchPath("cli_study");
  ASSERT_EQ(
      Flexrod("study rigid-rig-friction --no-plot --set sim.settle=0s --set sim.capture=0.05s "
              "--set sim.sample_rate=5kHz --out " +
              out.string())
          .exit_code,
      0);
  std::ifstream in(out / "table.csv");
  std::string line, header;
  int rows = 0;
  while (std::getline(in, line)) {
    if (rows++ == 0) header = line;
  }
  EXPECT_EQ(rows, 1 + 6);  // header + clearance {0.5, 1.0} × friction {0.2, 0.4, 0.6}
  EXPECT_NE(header.find("median per-rev. peak abs slider acc. [m/s^2]"), std::string::npos)
      << header;
  EXPECT_TRUE(fs::exists(out / "table.md"));
  EXPECT_TRUE(fs::exists(out / "c1.0mm-mu0.6" / "summary.json"));
  // Study cases run at the study's tolerances (app/cmd_study.cc, kStudyTolerances).
  std::ifstream resolved(out / "c1.0mm-mu0.6" / "resolved.toml");
  const std::string text((std::istreambuf_iterator<char>(resolved)),
                         std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("rel_tol = 1e-08"), std::string::npos);
  EXPECT_NE(text.find("abs_tol = 1e-10"), std::string::npos);
  // The six cases share one ideal twin: it is written once, into the first case's run.h5;
  // the others hold an external link to it, which reads back the same data.
  {
    const h5::Node first = h5::OpenFile((out / "c0.5mm-mu0.2" / "run.h5").string());
    const Vec twin = first.ReadVector("ideal/channels/slider_acceleration");
    ASSERT_GT(twin.size(), 100);
    for (const char* tag :
         {"c0.5mm-mu0.4", "c0.5mm-mu0.6", "c1.0mm-mu0.2", "c1.0mm-mu0.4", "c1.0mm-mu0.6"}) {
      const h5::Node f = h5::OpenFile((out / tag / "run.h5").string());
      EXPECT_TRUE(f.IsExternalLink("ideal")) << tag;
      EXPECT_TRUE(f.ReadVector("ideal/channels/slider_acceleration") == twin) << tag;
    }
  }
  fs::remove_all(out);
  EXPECT_EQ(Flexrod("study rigid-rig-everything --out " + out.string()).exit_code, 2);
  EXPECT_FALSE(fs::exists(out));
  // A key that fails a case (the 1 mm clearance does not fit a 0.8 mm bush) is refused before
  // any case runs or any file is written (it used to write three cases first).
  EXPECT_EQ(Flexrod("study rigid-rig-friction --no-plot --set joint.bush_radius=0.8mm --out " +
                    out.string())
                .exit_code,
            2);
  EXPECT_FALSE(fs::exists(out));
}

/// True if `path` starts with the 8-byte PNG signature (a picture matplotlib finished).
bool IsPng(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  char sig[8] = {};
  in.read(sig, 8);
  return in.gcount() == 8 && std::string(sig, 8) == "\x89PNG\r\n\x1a\n";
}

// The plots of a run (scripts/flexrod_plots.py, Debian's python3-matplotlib): the slider
// acceleration against the ideal twin, spectrum, Poincare map, journal orbit and bearing force
// of a clearance run (0.4 s: more than one revolution at 177 rpm, for the Poincare map); the
// strain gauges of a flexible one; none left half-written.
TEST(RunCli, RunWritesItsPlots) {
  const fs::path rigid = ScratchPath("cli_plots_rigid");
  ASSERT_EQ(
      Flexrod(
          "run rigid-rig --set sim.settle=0s --set sim.capture=0.4s --set sim.sample_rate=20kHz "
          "--out " +
          rigid.string())
          .exit_code,
      0);
  for (const char* png : {"slider_acceleration.png", "spectrum.png", "poincare.png",
                          "journal_orbit.png", "bearing_force.png"}) {
    EXPECT_TRUE(IsPng(rigid / png)) << png;
  }
  const fs::path flexible = ScratchPath("cli_plots_flexible");
  ASSERT_EQ(Flexrod("run flexible-rig --set sim.settle=0.01s --set sim.capture=0.05s --set "
                    "sim.sample_rate=20kHz "
                    "--out " +
                    flexible.string())
                .exit_code,
            0);
  EXPECT_TRUE(IsPng(flexible / "rod_strain.png"));
  for (const fs::path& dir : {rigid, flexible}) {
    for (const auto& entry : fs::directory_iterator(dir)) {
      EXPECT_EQ(entry.path().string().find(".tmp."), std::string::npos) << entry.path();
    }
    fs::remove_all(dir);
  }
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  std::stringstream ss;
  ss << in.rdbuf();
  return ss.str();
}

// The resolved input names the contact parameters the run derived (issue 4: "the resolved
// values are written into the run's resolved input"), as comments, so that the file still
// loads as an input (0 = derive) and reruns the same mechanism.
// A flexible rod's resolved.toml sets every material override to its default 0 ("the
// material's"): it runs again as an input, with the same summary (was: "rod.E = 0 Pa").
TEST(RunCli, AFlexibleRodsResolvedInputRunsAgain) {
  const fs::path first = ScratchPath("cli_resolved_flexible"),
                 again = ScratchPath("cli_resolved_flexible_again");
  const std::string sets =
      " --no-plot --ensemble 1 --set sim.settle=0s --set sim.capture=0.02s --set "
      "damping.type=material --out ";
  ASSERT_EQ(Flexrod("run flexible-rig" + sets + first.string()).exit_code, 0);
  const auto r = Flexrod("run " + (first / "resolved.toml").string() + sets + again.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream a(first / "summary.json"), b(again / "summary.json");
  const nlohmann::json sa = nlohmann::json::parse(a), sb = nlohmann::json::parse(b);
  EXPECT_EQ(sa["rod"]["mechanism_damping_ratios"], sb["rod"]["mechanism_damping_ratios"]);
  EXPECT_EQ(sa["rod"]["mechanism_damping_ratios"][0].get<double>(), 2e-4);  // steel: eta / 2
}

TEST(RunCli, ResolvedInputShowsTheDerivedContactParametersAndLoadsBack) {
  const fs::path first = ScratchPath("cli_resolved_first"),
                 again = ScratchPath("cli_resolved_again");
  ASSERT_EQ(Flexrod("run rigid-rig --no-plot --set sim.settle=0s --set sim.capture=0.1s --set "
                    "joint.exponent=1.4 "
                    "--out " +
                    first.string())
                .exit_code,
            0);
  const std::string toml = ReadText(first / "resolved.toml");
  // Hybrid law, steel on steel: the stiffness is fitted to ESDU-78035; the user's exponent was used
  // as given, so it gets no note.
  EXPECT_TRUE(std::regex_search(
      toml, std::regex("\nstiffness = 0  # \\[SI\\] default; used: [0-9.e+]+ N/m\\^1\\.4 "
                       "\\(derived\\)\n")))
      << toml;
  EXPECT_NE(toml.find("\nexponent = 1.4  # [1] set\n"), std::string::npos) << toml;
  EXPECT_NE(toml.find("# resolved joint.pin_radius = 0.008525 m (derived)\n"), std::string::npos)
      << toml;
  ASSERT_EQ(
      Flexrod("run " + (first / "resolved.toml").string() + " --no-plot --out " + again.string())
          .exit_code,
      0);
  std::ifstream a(first / "summary.json"), b(again / "summary.json");
  const nlohmann::json sa = nlohmann::json::parse(a), sb = nlohmann::json::parse(b);
  EXPECT_EQ(sa["joint_parameters"].size(), sb["joint_parameters"].size());
  for (const auto& [name, p] : sa["joint_parameters"].items()) {
    EXPECT_NEAR(p["value"].get<double>(), sb["joint_parameters"][name]["value"].get<double>(),
                1e-9 * std::abs(p["value"].get<double>()))
        << name;
  }
  // The resolved input holds SI values to 12 digits. The rerun is the same mechanism, but a
  // 1e-12 change of a parameter can change the integrator's step decisions, so an impact peak
  // agrees to the integration tolerance (sim.rel_tol = 1e-6; observed 3e-6), not to 12 digits.
  const double peak = sa["channels"]["slider_acceleration"]["peak_abs"].get<double>();
  EXPECT_NEAR(sb["channels"]["slider_acceleration"]["peak_abs"].get<double>(), peak, 1e-5 * peak);
  fs::remove_all(first);
  fs::remove_all(again);
}

/// The numeric rows of a CSV file (header skipped), and its header.
std::vector<std::vector<double>> ReadCsvRows(const fs::path& path, std::string* header) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, *header);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::stringstream ss(line);
    std::string cell;
    while (std::getline(ss, cell, ',')) row.push_back(std::stod(cell));
    rows.push_back(std::move(row));
  }
  return rows;
}

// run.h5 (the default) holds the standard channels of the run and of its ideal twin, the
// impact log and the summary, bit for bit the numbers of the CSV files (%.17g round-trips).
TEST(RunCli, RunFileHoldsTheChannelsTwinImpactsAndSummaryOfTheCsv) {
  const fs::path out = ScratchPath("cli_run_h5");
  ASSERT_EQ(Flexrod("run rigid-rig --no-plot --set sim.settle=0s --set sim.capture=0.2s "
                    "--set sim.sample_rate=20kHz --set output.format=hdf5,csv --out " +
                    out.string())
                .exit_code,
            0);
  const h5::Node file = h5::OpenFile((out / "run.h5").string());
  EXPECT_EQ(file.GetString("format"), "flexrod-run 1");
  const study::StoredRun run = study::ReadStoredRun(file);
  std::string header;
  const auto rows = ReadCsvRows(out / "channels.csv", &header);
  ASSERT_EQ(rows.size(), 4000u);
  // The CSV holds the same standard selection, after its time column.
  std::string expected = "time [s]";
  for (const study::StoredSeries& c : run.channels) {
    EXPECT_TRUE(IsStandardChannel(c.name)) << c.name;
    expected += "," + c.name + " [" + c.unit + "]";
  }
  EXPECT_EQ(header, expected);
  for (const char* name : {"slider_acceleration", "bearing_force", "journal_eccentricity_x",
                           "contact_normal_force", "crank_angle"}) {
    EXPECT_NE(header.find(std::string(name) + " ["), std::string::npos) << name;
  }
  EXPECT_EQ(header.find("penetration ["), std::string::npos);  // derived: not standard
  for (std::size_t c = 0; c < run.channels.size(); ++c) {
    ASSERT_EQ(run.channels[c].values.size(), rows.size());
    for (std::size_t i = 0; i < rows.size(); ++i) {
      ASSERT_EQ(run.channels[c].values[i], rows[i][c + 1]) << run.channels[c].name << " " << i;
    }
  }
  EXPECT_EQ(run.channel_rate, 20000.0);
  EXPECT_EQ(run.channel_start, rows[0][0]);
  // The ideal twin.
  const Vec ideal = file.ReadVector("ideal/channels/slider_acceleration");
  const auto ideal_rows = ReadCsvRows(out / "ideal" / "channels.csv", &header);
  const std::size_t col = static_cast<std::size_t>(
      std::count(header.begin(), header.begin() + header.find("slider_acceleration ["), ','));
  ASSERT_EQ(static_cast<std::size_t>(ideal.size()), ideal_rows.size());
  for (std::size_t i = 0; i < ideal_rows.size(); ++i) ASSERT_EQ(ideal[i], ideal_rows[i][col]);
  // The impact log.
  const auto impacts = ReadCsvRows(out / "impacts.csv", &header);
  ASSERT_GT(impacts.size(), 0u);
  const Vec peak = file.ReadVector("impacts/peak_force");
  ASSERT_EQ(static_cast<std::size_t>(peak.size()), impacts.size());
  for (std::size_t i = 0; i < impacts.size(); ++i) EXPECT_EQ(peak[i], impacts[i][3]);
  // The summary, as in summary.json.
  std::ifstream in(out / "summary.json");
  const nlohmann::json s = nlohmann::json::parse(in);
  EXPECT_EQ(nlohmann::json::parse(run.summary_json), s);
  EXPECT_EQ(run.Summary("peak_positive"), s["slider_acceleration"]["peak_positive"].get<double>());
  // examples/read_store.py reads it, and finds a unit on every dataset.
  const CommandResult units =
      Shell(std::string(FLEXROD_PYTHON) + " " FLEXROD_SOURCE_DIR "/examples/read_store.py " +
            (out / "run.h5").string() + " --check-units");
  EXPECT_EQ(units.exit_code, 0) << units.output;
  // A run into the same directory that writes HDF5 only removes the CSV files it replaces.
  ASSERT_EQ(Flexrod("run rigid-rig --no-plot --set sim.settle=0s --set sim.capture=0.01s --out " +
                    out.string())
                .exit_code,
            0);
  EXPECT_TRUE(fs::exists(out / "run.h5"));
  EXPECT_FALSE(fs::exists(out / "channels.csv"));
  EXPECT_FALSE(fs::exists(out / "ideal"));
  EXPECT_FALSE(fs::exists(out / "impacts.csv"));
  fs::remove_all(out);
}

// A full disk at the channel file (fault injection: FLEXROD_FAIL_WRITE=3 fails the third file
// committed, run.h5, after resolved.toml and summary.json, with ENOSPC): exit 3 naming the file
// and the reason, the summary kept, no run.h5 and no temporary.
TEST(RunCli, FullDiskAtTheChannelFileExitsWithThreeAndKeepsTheSummary) {
  const fs::path out = ScratchPath("cli_full_disk");
  const CommandResult run = Shell("FLEXROD_FAIL_WRITE=3 " + std::string(FLEXROD_BINARY) +
                                  " run rigid-rig --no-plot --set sim.settle=0s "
                                  "--set sim.capture=0.02s --out " +
                                  out.string());
  EXPECT_EQ(run.exit_code, 3);
  EXPECT_NE(run.output.find("I/O error: No space left on device: " + (out / "run.h5").string()),
            std::string::npos)
      << run.output;
  EXPECT_TRUE(fs::exists(out / "summary.json"));
  EXPECT_FALSE(fs::exists(out / "run.h5"));
  EXPECT_FALSE(fs::exists(out / "run.h5.tmp"));
  fs::remove_all(out);
}

// output.channels / output.rate: what a run's channel files hold.
TEST(RunCli, CsvHoldsTheSelectedChannelsAtTheSelectedRate) {
  const fs::path out = ScratchPath("cli_csv_select");
  ASSERT_EQ(
      Flexrod(
          "run rigid-rig --no-plot --set sim.settle=0s --set sim.capture=0.05s "
          "--set output.channels=\"slider_acceleration, penetration\" --set output.rate=\"10 kHz\" "
          "--set output.format=csv --out " +
          out.string())
          .exit_code,
      0);
  EXPECT_FALSE(fs::exists(out / "run.h5"));
  std::ifstream in(out / "channels.csv");
  std::string header, line;
  std::getline(in, header);
  EXPECT_EQ(header, "time [s],slider_acceleration [m/s^2],penetration [m]");
  int rows = 0;
  std::string first, second;
  while (std::getline(in, line)) {
    if (rows == 0) first = line;
    if (rows == 1) second = line;
    ++rows;
  }
  EXPECT_EQ(rows, 500);  // 0.05 s at 10 kHz: every 10th of the 5000 samples at 100 kHz
  const double dt =
      std::stod(second.substr(0, second.find(','))) - std::stod(first.substr(0, first.find(',')));
  EXPECT_NEAR(dt, 1e-4, 1e-12);
  // The ideal twin has no contact channels: its CSV keeps those of the selection it has.
  std::ifstream ideal(out / "ideal" / "channels.csv");
  std::getline(ideal, header);
  EXPECT_EQ(header, "time [s],slider_acceleration [m/s^2]");
  fs::remove_all(out);
}

TEST(RunCli, BadCsvSelectionExitsWithTwoBeforeTheRun) {
  ExpectExitTwoAndNoOutput(
      "csv_bad",
      {"run rigid-rig --set output.channels=penetrashun",
       "run rigid-rig --set output.rate=\"30 kHz\"", "run rigid-rig --set output.rate=\"-1 kHz\"",
       "run rigid-rig --set output.format=xml", "run rigid-rig --set output.format=\"\""});
}

// `flexrod run --vtk DIR`: the ParaView output of one run, and its bad-input path.
TEST(RunCli, VtkWritesACollectionOfExistingFrames) {
  const fs::path root = ScratchPath("cli_vtk_run");
  const fs::path vtk = root / "vtk";
  ASSERT_EQ(Flexrod("run rigid-rig --set sim.settle=\"0 s\" --set sim.capture=\"0.1 s\" --vtk " +
                    vtk.string() + " --no-plot --out " + (root / "out").string())
                .exit_code,
            0);
  ASSERT_TRUE(fs::exists(vtk / "run.pvd"));
  std::ifstream in(vtk / "run.pvd");
  std::stringstream ss;
  ss << in.rdbuf();
  const std::string pvd = ss.str();
  const std::regex entry("<DataSet timestep=\"([^\"]+)\"[^>]*file=\"([^\"]+)\"");
  int count = 0;
  double last = -1.0;
  for (auto it = std::sregex_iterator(pvd.begin(), pvd.end(), entry); it != std::sregex_iterator();
       ++it) {
    EXPECT_TRUE(fs::exists(vtk / (*it)[2].str())) << (*it)[2].str();
    const double t = std::stod((*it)[1].str());
    EXPECT_GT(t, last);
    last = t;
    ++count;
  }
  // 0.1 s captured at the preset's 100 kHz, one frame per 100 samples (vtk.rate = 1 kHz).
  EXPECT_EQ(count, 100);
  fs::remove_all(root);
}

TEST(RunCli, BadVtkKeyExitsWithTwoAndWritesNoCollection) {
  const fs::path root = ScratchPath("cli_vtk_bad");
  EXPECT_EQ(Flexrod("run rigid-rig --set vtk.scale=-1 --set sim.settle=\"0 s\" --set "
                    "sim.capture=\"0.01 s\" --vtk " +
                    (root / "vtk").string() + " --no-plot --out " + (root / "out").string())
                .exit_code,
            2);
  // Bad input writes nothing, not even the directories.
  EXPECT_FALSE(fs::exists(root));
  fs::remove_all(root);
}

TEST(RunCli, VtkDirectoryThatCannotExistExitsWithTwo) {
  const fs::path root = ScratchPath("cli_vtk_file");
  fs::create_directories(root);
  std::ofstream(root / "plain") << "x";
  EXPECT_EQ(
      Flexrod("run rigid-rig --set sim.settle=\"0 s\" --set sim.capture=\"0.01 s\" --vtk " +
              (root / "plain" / "vtk").string() + " --no-plot --out " + (root / "out").string())
          .exit_code,
      2);
  EXPECT_FALSE(fs::exists(root / "out"));
  fs::remove_all(root);
}

}  // namespace
