// `flexrod contact`: one impact of a mass against a rigid wall through a chosen normal contact
// law (run/contact_impact.h, contact/impact.h), with the law's parameters derived from pin and
// bush materials and geometry unless overridden. Prints and optionally writes (JSON) the achieved
// restitution, peak force, peak penetration and contact duration with the resolved parameters;
// --plot draws the force–penetration loop with app/plot_contact.py (python3 + matplotlib, Agg
// backend). SPDX-License-Identifier: GPL-3.0-or-later
#include <sys/wait.h>
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "app/commands.h"
#include "common/error.h"
#include "common/files.h"
#include "contact/impact.h"
#include "run/contact_impact.h"

namespace flexrod::app {
namespace {

constexpr const char* kPython = "/usr/bin/python3";

struct ContactOptions {
  ContactRequest request;
  std::string json_file, plot_file;
};

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
  if (!opt.plot_file.empty()) {  // checked before any work
    const std::string ext = std::filesystem::path(opt.plot_file).extension().string();
    if (ext != ".png") throw InputError("plot", opt.plot_file, "the plot file must end in .png");
    CheckCanWriteFile("--plot", opt.plot_file);
  }
  if (!opt.json_file.empty()) CheckCanWriteFile("--json", opt.json_file);
  const ContactImpact c = SimulateContactImpact(opt.request);
  const contact::ImpactResult& r = c.result;
  const double mass = c.mass, velocity = c.velocity;

  std::printf("law: %s\n", c.law.c_str());
  std::printf("mass %.6g kg, approach velocity %.6g m/s\n", mass, velocity);
  std::printf("%-22s %.8g\n", "achieved restitution", r.achieved_restitution);
  std::printf("%-22s %.8g N\n", "peak force", r.peak_force);
  std::printf("%-22s %.8g m\n", "peak penetration", r.peak_penetration);
  std::printf("%-22s %.8g s\n", "contact duration", r.contact_duration);
  std::printf("%-22s %.8g J\n", "dissipated energy", r.dissipated_energy);
  std::printf("resolved parameters:\n");
  for (const auto& p : c.parameters) {
    std::printf("  %-30s %.10g %s (%s)\n", p.name.c_str(), p.value, p.unit.c_str(),
                p.source.c_str());
  }
  if (!c.warning.empty()) std::fprintf(stderr, "flexrod: warning: %s\n", c.warning.c_str());
  if (!opt.json_file.empty()) WriteFileAtomic(opt.json_file, ContactJson(c).dump(2) + "\n");
  if (!opt.plot_file.empty()) {
    char title[200];
    std::snprintf(title, sizeof title, "%s: m = %.4g kg, v0 = %.4g m/s, achieved e = %.4f",
                  c.law.c_str(), mass, velocity, r.achieved_restitution);
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
  cmd->add_option("--law", opt->request.law, law_help)->required();
  cmd->add_option("--mass", opt->request.mass, "impacting mass, e.g. \"2.71 kg\"")->required();
  cmd->add_option("--velocity", opt->request.velocity, "approach speed, e.g. \"0.5 m/s\"")
      ->required();
  for (const ContactLawFlag& f : ContactLawFlags()) {
    const std::string key = f.key;
    cmd->add_option_function<std::string>(
        "--" + key,
        [opt, key](const std::string& v) { opt->request.law_params.emplace_back(key, v); }, f.help);
  }
  cmd->add_option("--pin-E", opt->request.pin_E, "pin Young's modulus (default steel, 200 GPa)");
  cmd->add_option("--pin-nu", opt->request.pin_nu, "pin Poisson ratio (default steel, 0.29)");
  cmd->add_option("--bush-E", opt->request.bush_E, "bush Young's modulus (default steel, 200 GPa)");
  cmd->add_option("--bush-nu", opt->request.bush_nu, "bush Poisson ratio (default steel, 0.29)");
  cmd->add_option("--pin-radius", opt->request.pin_radius, "pin radius")->capture_default_str();
  cmd->add_option("--bush-radius", opt->request.bush_radius, "bush (bore) radius")
      ->capture_default_str();
  cmd->add_option("--length", opt->request.length,
                  "bearing length of the line contact (assumed default)")
      ->capture_default_str();
  cmd->add_option("--json", opt->json_file, "write results and resolved parameters as JSON");
  cmd->add_option("--plot", opt->plot_file, "write the force-penetration loop as PNG");
  cmd->callback([opt, handler] { *handler = [opt] { return RunContact(*opt); }; });
}

}  // namespace flexrod::app
