// `flexrod contact`: one impact of a mass against a rigid wall through a chosen normal contact
// law (contact/impact.h), with the law's parameters derived from pin and bush materials and
// geometry unless overridden. Prints and optionally writes (JSON) the achieved restitution, peak
// force, peak penetration and contact duration with the resolved parameters; --plot draws the
// force–penetration loop with app/plot_contact.py (python3 + matplotlib, Agg backend).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

#include "app/commands.h"
#include "common/error.h"
#include "common/files.h"
#include "common/units.h"
#include "contact/impact.h"
#include "fem/material.h"

namespace flexrod::app {
namespace {

// Default joint: steel pin in a steel bush with the flexible rig's 3/4 in bore (RIG.md §2) and
// 0.5 mm radial clearance; the bearing length is assumed (1/2 in), not given by the thesis.
constexpr const char* kDefaultBushRadius = "9.525 mm";
constexpr const char* kDefaultPinRadius = "9.025 mm";
constexpr const char* kDefaultLength = "12.7 mm";
constexpr const char* kPython = "/usr/bin/python3";

struct LawFlag {
  const char* key;  // override key in contact/normal_law.h
  Dimension dim;
  const char* help;
};

// Stiffness is special: N/m for the linear laws, N/m^n (bare SI number) for the power laws.
const LawFlag kLawFlags[] = {
    {"restitution", Dimension::kDimensionless, "coefficient of restitution c_e in (0, 1]"},
    {"stiffness", Dimension::kStiffness, "K [N/m^n, bare SI number] (k [N/m] for linear laws)"},
    {"exponent", Dimension::kDimensionless, "force exponent n"},
    {"damping", Dimension::kDamping, "dashpot damping d, e.g. \"2000 N*s/m\""},
    {"stiffness-2", Dimension::kStiffness, "standard-linear-solid arm stiffness k2"},
    {"working-penetration", Dimension::kLength, "fit range of hybrid/linear laws, e.g. \"10 um\""},
    {"min-approach-velocity", Dimension::kVelocity, "floor on v0 in the hysteresis damping"},
    {"max-damping", Dimension::kDamping, "impact: c_max"},
    {"damping-penetration", Dimension::kLength, "impact: d_max, e.g. \"0.01 mm\""},
    {"calibration-velocity", Dimension::kVelocity,
     "impact: speed for calibrating c_max (default --velocity)"},
    {"compliance", Dimension::kDimensionless, "line laws: sum of h = (1-nu^2)/(pi E) [1/Pa]"},
    {"effective-mass", Dimension::kMass, "mass used to derive damping (default --mass)"},
};

bool IsLinearLaw(const std::string& law) {
  return law == "linear-spring" || law == "kelvin-voigt" || law == "maxwell" ||
         law == "standard-linear-solid";
}

struct ContactOptions {
  std::string law;
  std::string mass, velocity;
  std::string pin_E, pin_nu, bush_E, bush_nu;
  std::string pin_radius{kDefaultPinRadius}, bush_radius{kDefaultBushRadius},
      length{kDefaultLength};
  std::vector<std::pair<std::string, std::string>> law_params;  // (key, text)
  std::string json_file, plot_file;
};

nlohmann::json Number(double v) {
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr);
}

/// Runs `/usr/bin/python3 app/plot_contact.py csv png title`; throws on failure.
void RunPlotScript(const std::string& csv, const std::string& png, const std::string& title) {
  const std::string script = std::string(FLEXROD_SOURCE_DIR) + "/app/plot_contact.py";
  std::vector<std::string> args = {kPython, script, csv, png, title};
  std::vector<char*> argv;
  for (auto& a : args) argv.push_back(a.data());
  argv.push_back(nullptr);
  std::fflush(stdout);
  const pid_t pid = fork();
  if (pid < 0) throw IoError("contact --plot: fork failed");
  if (pid == 0) {
    setenv("MPLBACKEND", "Agg", 1);
    execv(kPython, argv.data());
    _exit(127);
  }
  int status = 0;
  if (waitpid(pid, &status, 0) < 0 || !WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    throw IoError("contact --plot: " + std::string(kPython) + " " + script +
                  " failed (exit status " +
                  std::to_string(WIFEXITED(status) ? WEXITSTATUS(status) : -1) +
                  "); is matplotlib installed?");
  }
}

void WritePlot(const std::string& png, const contact::ImpactResult& result,
               const std::string& title) {
  // Temporary CSV, removed whatever happens.
  const std::filesystem::path csv = std::filesystem::temp_directory_path() /
                                    ("flexrod-contact-" + std::to_string(getpid()) + ".csv");
  struct Remove {
    std::filesystem::path p;
    ~Remove() {
      std::error_code ec;
      std::filesystem::remove(p, ec);
    }
  } remove_csv{csv};
  {
    std::ofstream out(csv);
    if (!out) throw IoError("contact --plot: cannot write " + csv.string());
    out << "time [s],penetration [m],rate [m/s],force [N]\n";
    out.precision(17);
    for (const auto& s : result.loop) {
      out << s.time << ',' << s.penetration << ',' << s.rate << ',' << s.force << '\n';
    }
    if (!out) throw IoError("contact --plot: cannot write " + csv.string());
  }
  RunPlotScript(csv.string(), png, title);
}

int RunContact(const ContactOptions& opt) {
  // ---- parse and validate everything before any work ----
  const auto& names = contact::NormalLawNames();
  if (std::find(names.begin(), names.end(), opt.law) == names.end()) {
    std::string list;
    for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
    throw InputError("law", "\"" + opt.law + "\"",
                     "unknown normal contact law; must be one of: " + list);
  }
  if (!opt.plot_file.empty()) {
    const std::string ext = std::filesystem::path(opt.plot_file).extension().string();
    if (ext != ".png") throw InputError("plot", opt.plot_file, "the plot file must end in .png");
  }
  const double mass = ParseQuantity("mass", opt.mass, Dimension::kMass);
  const double velocity = ParseQuantity("velocity", opt.velocity, Dimension::kVelocity);
  RequirePositive("mass", mass);
  RequirePositive("velocity", velocity);

  const fem::Material steel = fem::MaterialByName("steel");
  contact::ContactMaterials materials;
  materials.pin_youngs_modulus = opt.pin_E.empty()
                                     ? steel.youngs_modulus
                                     : ParseQuantity("pin-E", opt.pin_E, Dimension::kPressure);
  materials.bush_youngs_modulus = opt.bush_E.empty()
                                      ? steel.youngs_modulus
                                      : ParseQuantity("bush-E", opt.bush_E, Dimension::kPressure);
  materials.pin_poisson_ratio =
      opt.pin_nu.empty() ? steel.poisson_ratio
                         : ParseQuantity("pin-nu", opt.pin_nu, Dimension::kDimensionless);
  materials.bush_poisson_ratio =
      opt.bush_nu.empty() ? steel.poisson_ratio
                          : ParseQuantity("bush-nu", opt.bush_nu, Dimension::kDimensionless);
  contact::ContactGeometry geometry;
  geometry.bush_radius = ParseQuantity("bush-radius", opt.bush_radius, Dimension::kLength);
  geometry.pin_radius = ParseQuantity("pin-radius", opt.pin_radius, Dimension::kLength);
  geometry.length = ParseQuantity("length", opt.length, Dimension::kLength);

  contact::ParameterMap overrides;
  for (const auto& [key, text] : opt.law_params) {
    Dimension dim = Dimension::kDimensionless;
    for (const LawFlag& f : kLawFlags) {
      if (key == f.key) dim = f.dim;
    }
    if (key == "stiffness" && !IsLinearLaw(opt.law)) {
      try {
        overrides[key] = ParseQuantity(key, text, Dimension::kDimensionless);
      } catch (const InputError&) {
        throw InputError(key, "\"" + text + "\"",
                         "law '" + opt.law + "' takes K in N/m^n: give it as a bare SI number");
      }
      continue;
    }
    overrides[key] = ParseQuantity(key, text, dim);
  }
  // The impacting mass and speed are the natural calibration inputs of laws that need them.
  const auto& keys = contact::NormalLawParameterKeys(opt.law);
  auto takes = [&](const char* k) { return std::find(keys.begin(), keys.end(), k) != keys.end(); };
  if (takes("effective-mass") && !overrides.count("effective-mass"))
    overrides["effective-mass"] = mass;
  if (takes("calibration-velocity") && !overrides.count("calibration-velocity")) {
    overrides["calibration-velocity"] = velocity;
  }
  const contact::ResolvedNormalLaw resolved = [&] {
    try {
      return contact::ResolveNormalLaw(opt.law, materials, geometry, overrides);
    } catch (const InputError& e) {
      // The contact layer names its inputs contact.pin_radius, contact.bush_E, ...: report the
      // flag (pin-radius, bush-E, ...; the clearance is set through --pin-radius).
      std::string key = e.key();
      if (key.rfind("contact.", 0) != 0) throw;
      key = key == "contact.clearance" ? "pin-radius" : key.substr(8);
      std::replace(key.begin(), key.end(), '_', '-');
      throw InputError(key, e.value(), e.rule());
    }
  }();

  // ---- work ----
  const contact::ImpactResult r = contact::SimulateImpact(resolved.law, mass, velocity);

  std::printf("law: %s\n", opt.law.c_str());
  std::printf("mass %.6g kg, approach velocity %.6g m/s\n", mass, velocity);
  std::printf("%-22s %.8g\n", "achieved restitution", r.achieved_restitution);
  std::printf("%-22s %.8g N\n", "peak force", r.peak_force);
  std::printf("%-22s %.8g m\n", "peak penetration", r.peak_penetration);
  std::printf("%-22s %.8g s\n", "contact duration", r.contact_duration);
  std::printf("%-22s %.8g J\n", "dissipated energy", r.dissipated_energy);
  std::printf("resolved parameters:\n");
  std::string warning;
  for (const auto& p : resolved.parameters) {
    std::printf("  %-30s %.10g %s (%s)\n", p.name.c_str(), p.value, p.unit.c_str(),
                p.source.c_str());
    if (p.name == "min-approach-velocity" && velocity < p.value) {
      warning = "the approach velocity " + FormatValue(velocity) +
                " m/s is below min-approach-velocity = " + FormatValue(p.value) +
                " m/s: the hysteresis damping uses the floor, so the achieved restitution "
                "is above the one this law gives at its own speed; lower --min-approach-velocity "
                "to remove it";
    }
  }
  if (!warning.empty()) std::fprintf(stderr, "flexrod: warning: %s\n", warning.c_str());

  if (!opt.json_file.empty()) {
    nlohmann::json j;
    j["law"] = opt.law;
    j["achieved_restitution"] = Number(r.achieved_restitution);
    j["peak_force"] = Number(r.peak_force);
    j["peak_penetration"] = Number(r.peak_penetration);
    j["contact_duration"] = Number(r.contact_duration);
    j["dissipated_energy"] = Number(r.dissipated_energy);
    j["outgoing_speed"] = Number(r.outgoing_speed);
    j["units"] = {{"achieved_restitution", "1"}, {"peak_force", "N"},
                  {"peak_penetration", "m"},     {"contact_duration", "s"},
                  {"dissipated_energy", "J"},    {"outgoing_speed", "m/s"}};
    j["inputs"] = {{"mass", {{"value", mass}, {"unit", "kg"}}},
                   {"velocity", {{"value", velocity}, {"unit", "m/s"}}},
                   {"pin-E", {{"value", materials.pin_youngs_modulus}, {"unit", "Pa"}}},
                   {"pin-nu", {{"value", materials.pin_poisson_ratio}, {"unit", "1"}}},
                   {"bush-E", {{"value", materials.bush_youngs_modulus}, {"unit", "Pa"}}},
                   {"bush-nu", {{"value", materials.bush_poisson_ratio}, {"unit", "1"}}},
                   {"pin-radius", {{"value", geometry.pin_radius}, {"unit", "m"}}},
                   {"bush-radius", {{"value", geometry.bush_radius}, {"unit", "m"}}},
                   {"length", {{"value", geometry.length}, {"unit", "m"}}}};
    nlohmann::json params = nlohmann::json::array();
    for (const auto& p : resolved.parameters) {
      params.push_back(
          {{"name", p.name}, {"value", Number(p.value)}, {"unit", p.unit}, {"source", p.source}});
    }
    j["parameters"] = params;
    if (!warning.empty()) j["warnings"] = {warning};
    WriteFileAtomic(opt.json_file, j.dump(2) + "\n");
  }
  if (!opt.plot_file.empty()) {
    char title[200];
    std::snprintf(title, sizeof title, "%s: m = %.4g kg, v0 = %.4g m/s, achieved e = %.4f",
                  opt.law.c_str(), mass, velocity, r.achieved_restitution);
    WritePlot(opt.plot_file, r, title);
  }
  return 0;
}

}  // namespace

void RegisterContact(CLI::App& app, Handler* handler) {
  auto opt = std::make_shared<ContactOptions>();
  CLI::App* cmd = app.add_subcommand(
      "contact", "single impact of a mass on a rigid wall through a normal contact law");
  std::string law_help = "normal contact law:";
  for (const auto& n : contact::NormalLawNames()) law_help += " " + n;
  cmd->add_option("--law", opt->law, law_help)->required();
  cmd->add_option("--mass", opt->mass, "impacting mass, e.g. \"2.71 kg\"")->required();
  cmd->add_option("--velocity", opt->velocity, "approach speed, e.g. \"0.5 m/s\"")->required();
  for (const LawFlag& f : kLawFlags) {
    const std::string key = f.key;
    cmd->add_option_function<std::string>(
        "--" + key, [opt, key](const std::string& v) { opt->law_params.emplace_back(key, v); },
        f.help);
  }
  cmd->add_option("--pin-E", opt->pin_E, "pin Young's modulus (default steel, 200 GPa)");
  cmd->add_option("--pin-nu", opt->pin_nu, "pin Poisson ratio (default steel, 0.29)");
  cmd->add_option("--bush-E", opt->bush_E, "bush Young's modulus (default steel, 200 GPa)");
  cmd->add_option("--bush-nu", opt->bush_nu, "bush Poisson ratio (default steel, 0.29)");
  cmd->add_option("--pin-radius", opt->pin_radius, "pin radius")->capture_default_str();
  cmd->add_option("--bush-radius", opt->bush_radius, "bush (bore) radius")->capture_default_str();
  cmd->add_option("--length", opt->length, "bearing length of the line contact (assumed default)")
      ->capture_default_str();
  cmd->add_option("--json", opt->json_file, "write results and resolved parameters as JSON");
  cmd->add_option("--plot", opt->plot_file, "write the force-penetration loop as PNG");
  cmd->callback([opt, handler] { *handler = [opt] { return RunContact(*opt); }; });
}

}  // namespace flexrod::app
