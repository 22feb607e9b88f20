// python/flexrod_module.cc — the compiled part of the Python package `flexrod` (module
// flexrod._flexrod): thin bindings of the library functions the CLI calls (LoadRunInput +
// RunSimulation + WriteRun, AnalyseModes, SimulateContactImpact, RunSweep, ReadStore,
// the key schema). It returns plain dicts of numpy arrays, numbers and strings; the Python
// layer (python/flexrod/__init__.py) turns them into Run objects and raises NumericalError.
// Runs and sweeps compute on a worker thread with the GIL released; the calling thread checks
// for signals every kSignalPoll and, on Ctrl-C, sets the stop flag the integrator polls
// (multibody::SimulationOptions::stop), waits for the worker and raises KeyboardInterrupt.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gsl/gsl_errno.h>
#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <future>
#include <memory>
#include <optional>
#include <string>
#include <thread>
#include <type_traits>
#include <utility>
#include <vector>

#include "common/error.h"
#include "common/files.h"
#include "common/units.h"
#include "input/config.h"
#include "input/presets.h"
#include "io/run_writer.h"
#include "mechanisms/impact_log.h"
#include "mechanisms/modal_analysis.h"
#include "run/contact_impact.h"
#include "run/ensemble.h"
#include "run/reduction_study.h"
#include "run/run.h"
#include "sweep/sweep.h"
#include "sweep/sweep_store.h"

namespace py = pybind11;

namespace flexrod::python {
namespace {

/// How often the waiting thread takes the GIL to look for Ctrl-C.
constexpr std::chrono::milliseconds kSignalPoll{20};

/// Runs work(&stop) on a worker thread with the GIL released. The calling thread checks for
/// signals every kSignalPoll with the GIL held; when a signal handler raises (Ctrl-C:
/// KeyboardInterrupt), it sets stop, waits for the worker to return and raises that exception.
template <class Work>
auto Interruptible(Work&& work) {
  using Result = std::invoke_result_t<Work, const std::atomic<bool>*>;
  std::atomic<bool> stop{false};
  std::packaged_task<Result()> task([&] { return work(&stop); });
  std::future<Result> result = task.get_future();
  bool interrupted = false;
  {
    py::gil_scoped_release release;
    std::thread worker(std::move(task));
    while (result.wait_for(kSignalPoll) != std::future_status::ready) {
      py::gil_scoped_acquire acquire;
      if (PyErr_CheckSignals() != 0) {  // the handler's exception is now set
        interrupted = true;
        stop = true;
        break;
      }
    }
    worker.join();
  }
  if (interrupted) throw py::error_already_set();
  return result.get();
}

/// A numpy float64 array that owns `values` (moved, not copied).
py::array_t<double> ToArray(std::vector<double>&& values) {
  auto* owned = new std::vector<double>(std::move(values));
  py::capsule free_when_done(owned,
                             [](void* p) { delete reinterpret_cast<std::vector<double>*>(p); });
  return py::array_t<double>({owned->size()}, {sizeof(double)}, owned->data(), free_when_done);
}

py::object FromJson(const nlohmann::json& j) {
  return py::module_::import("json").attr("loads")(j.dump());
}

/// "time" (sample i at start_time + i / sample_rate, as the CSV writes it) and every channel,
/// into `channels` and `units`.
void AddSeries(const study::TimeSeries& series, py::dict* channels, py::dict* units) {
  std::vector<double> time(series.num_samples());
  for (std::size_t i = 0; i < time.size(); ++i) time[i] = series.time(i);
  (*channels)["time"] = ToArray(std::move(time));
  (*units)["time"] = "s";
  for (const study::Channel& c : series.channels()) {
    (*channels)[py::str(c.name)] = ToArray(std::vector<double>(c.values));
    (*units)[py::str(c.name)] = c.unit;
  }
}

py::dict StatusDict(const multibody::SimulationStatus& st) {
  py::dict d;
  d["outcome"] = multibody::ToString(st.outcome);
  d["time"] = st.t_reached;
  d["message"] = st.message;
  d["hint"] = st.hint;
  d["summary"] = st.Summary();
  py::dict state;
  state["norm_coordinates"] = st.norm_coordinates;
  state["norm_velocities"] = st.norm_velocities;
  state["norm_multipliers"] = st.norm_multipliers;
  state["worst_residual_variable"] = st.worst_residual_variable;
  state["worst_residual"] = st.worst_residual;
  state["worst_error_variable"] = st.worst_error_variable;
  state["worst_weighted_error"] = st.worst_weighted_error;
  d["state"] = state;
  d["wall_seconds"] = st.wall_seconds;
  return d;
}

/// One run, as `flexrod run INPUT --set ... [--out DIR] [--check] [--vtk DIR]` computes it
/// (without the plots): its ensemble (run/ensemble.h), member 0's channels. {"ok", "status",
/// "channels", "units", "summary", "impacts", "impact_units", "ideal": {"channels", "units",
/// "summary"} or None}.
py::dict RunInput(const std::string& input, const std::vector<std::string>& sets,
                  const std::optional<std::string>& out, bool check,
                  const std::optional<std::string>& vtk) {
  const Config cfg = LoadRunInput(input, sets);
  // Output locations and the check's tolerances before the run, not after it.
  if (out) CheckCanCreateDirectory("out", *out);
  if (vtk) CheckCanCreateDirectory("vtk", *vtk);
  const std::optional<Config> check_cfg =
      check ? std::optional<Config>(TightenedForCheck(cfg)) : std::nullopt;
  RunResult run = Interruptible([&](const std::atomic<bool>* stop) {
    RunOutputOptions outputs;
    outputs.stop = stop;
    outputs.record_vtk = vtk.has_value();
    RunResult r = RunEnsemble(cfg, outputs);
    if (check_cfg && r.ok()) AddAccuracyCheck(*check_cfg, &r, stop);
    if (stop->load()) throw Interrupted("run interrupted");
    return r;
  });
  if (out || vtk) WriteRun({out.value_or(""), "", vtk.value_or("")}, cfg, run);
  py::dict d, channels, units, impacts, impact_units;
  d["ok"] = run.ok();
  d["status"] = StatusDict(run.status);
  AddSeries(run.channels, &channels, &units);
  d["channels"] = channels;
  d["units"] = units;
  d["summary"] = FromJson(run.summary);
  for (study::Channel& c : study::ImpactColumns(run.impacts)) {
    impacts[c.name.c_str()] = ToArray(std::move(c.values));
    impact_units[c.name.c_str()] = c.unit;
  }
  d["impacts"] = impacts;
  d["impact_units"] = impact_units;
  d["ideal"] = py::none();
  if (run.ideal) {
    py::dict ideal, ideal_channels, ideal_units;
    AddSeries(*run.ideal, &ideal_channels, &ideal_units);
    ideal["channels"] = ideal_channels;
    ideal["units"] = ideal_units;
    ideal["summary"] = FromJson(run.summary["ideal"]);
    d["ideal"] = ideal;
  }
  return d;
}

py::list Keys() {
  py::list keys;
  for (const ParamDef& p : Schema()) {
    py::dict k;
    k["key"] = p.key;
    k["default"] = p.default_text;
    k["unit"] = p.kind == ParamKind::kQuantity ? SiUnit(p.dim) : "";
    k["rule"] = p.doc;
    if (!p.choices.empty()) k["choices"] = p.choices;
    keys.append(k);
  }
  return keys;
}

/// `flexrod modes` with flags given as (name without "--", text) in order: ModesJson.
py::object Modes(const std::string& config_file,
                 const std::vector<std::pair<std::string, std::string>>& flags) {
  Config cfg;
  if (!config_file.empty()) cfg.LoadTomlFile(config_file);
  for (const auto& [name, text] : flags) {
    const ModesFlag* flag = nullptr;
    for (const ModesFlag& f : ModesFlags()) {
      if ("--" + name == f.name) flag = &f;
    }
    if (flag == nullptr) {
      std::string list;
      for (const ModesFlag& f : ModesFlags()) {
        if (!list.empty()) list += ", ";
        list += f.name + 2;  // without the dashes
      }
      throw InputError(name, text, "unknown flag of modes(); must be one of: " + list);
    }
    cfg.Set(flag->key, text);
  }
  const ModalAnalysis analysis = [&] {
    py::gil_scoped_release release;
    return AnalyseModes(cfg);
  }();
  py::dict d = FromJson(ModesJson(cfg, analysis));
  d["warning"] = analysis.warning;
  return d;
}

/// `flexrod contact`: ContactJson, plus the hysteresis loop as arrays under "loop".
py::object Contact(const std::string& law, const std::string& mass, const std::string& velocity,
                   const std::vector<std::pair<std::string, std::string>>& params) {
  ContactRequest request;
  request.law = law;
  request.mass = mass;
  request.velocity = velocity;
  const std::pair<const char*, std::string ContactRequest::*> kGeometry[] = {
      {"pin_E", &ContactRequest::pin_E},           {"pin_nu", &ContactRequest::pin_nu},
      {"bush_E", &ContactRequest::bush_E},         {"bush_nu", &ContactRequest::bush_nu},
      {"pin_radius", &ContactRequest::pin_radius}, {"bush_radius", &ContactRequest::bush_radius},
      {"length", &ContactRequest::length}};
  for (const auto& [name, text] : params) {
    bool geometry = false;
    for (const auto& [field, member] : kGeometry) {
      if (name == field) {
        request.*member = text;
        geometry = true;
      }
    }
    if (geometry) continue;
    std::string key = name;
    std::replace(key.begin(), key.end(), '_', '-');
    request.law_params.emplace_back(key, text);
  }
  const ContactImpact impact = [&] {
    py::gil_scoped_release release;
    return SimulateContactImpact(request);
  }();
  py::dict d = FromJson(ContactJson(impact));
  const std::vector<contact::LoopSample>& loop = impact.result.loop;
  std::vector<double> time, penetration, rate, force;
  for (const contact::LoopSample& s : loop) {
    time.push_back(s.time);
    penetration.push_back(s.penetration);
    rate.push_back(s.rate);
    force.push_back(s.force);
  }
  py::dict arrays;
  arrays["time"] = ToArray(std::move(time));
  arrays["penetration"] = ToArray(std::move(penetration));
  arrays["rate"] = ToArray(std::move(rate));
  arrays["force"] = ToArray(std::move(force));
  d["loop"] = arrays;
  d["loop_units"] = py::dict(py::arg("time") = "s", py::arg("penetration") = "m",
                             py::arg("rate") = "m/s", py::arg("force") = "N");
  return d;
}

/// `flexrod sweep MATRIX --set ... --jobs N --out OUT` on threads (no MPI); returns OUT.
std::string Sweep(const std::string& matrix_name, const std::vector<std::string>& sets,
                  std::optional<int> jobs, const std::string& out) {
  study::CheckStorePath("out", out);
  if (jobs && *jobs < 1)
    throw InputError("jobs", std::to_string(*jobs), "must be >= 1 (None: all cores)");
  const study::SweepMatrix matrix = study::LoadSweepMatrix(matrix_name, sets);
  study::SweepOptions options;
  options.jobs = jobs ? *jobs : static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  return Interruptible([&](const std::atomic<bool>* stop) {
    options.stop = stop;
    return study::RunSweep(matrix, out, options).store_path;
  });
}

/// The runs of a store: {"id", "label", "status", "message", "fingerprint", "inputs" (every
/// resolved key: SI float, int, bool or text), "input_toml", "summary" (the run's summary
/// JSON), "figures" (the store's summary scalars) + "figure_units", "channels" (with "time")
/// + "units", "channel_rate" [Hz], "wall_time" [s]}.
py::list OpenStore(const std::string& path) {
  const study::SweepStore store = [&] {
    py::gil_scoped_release release;
    return study::ReadStore(path, true);
  }();
  py::list runs;
  for (const study::StoredRun& r : store.runs) {
    py::dict d, inputs, figures, figure_units, channels, units;
    d["id"] = r.id;
    d["label"] = r.label;
    d["status"] = r.status;
    d["message"] = r.message;
    d["fingerprint"] = r.fingerprint;
    const Config cfg = r.Input();
    for (const Config::Resolved& k : cfg.Resolve()) {
      const ParamDef* p = FindParam(k.key);
      if (p != nullptr && p->kind == ParamKind::kQuantity) {
        inputs[py::str(k.key)] = cfg.Quantity(k.key);
      } else if (p != nullptr && p->kind == ParamKind::kInteger) {
        inputs[py::str(k.key)] = cfg.Integer(k.key);
      } else if (p != nullptr && p->kind == ParamKind::kBool) {
        inputs[py::str(k.key)] = cfg.Bool(k.key);
      } else {
        inputs[py::str(k.key)] = k.value;
      }
    }
    d["inputs"] = inputs;
    d["input_toml"] = r.input_toml;
    d["summary"] = r.summary_json.empty()
                       ? py::object(py::dict())
                       : py::module_::import("json").attr("loads")(r.summary_json);
    for (const study::StoredScalar& s : r.summary) {
      figures[py::str(s.name)] = s.value;
      figure_units[py::str(s.name)] = s.unit;
    }
    d["figures"] = figures;
    d["figure_units"] = figure_units;
    std::size_t n = 0;
    for (const study::StoredSeries& c : r.channels) n = std::max(n, c.values.size());
    std::vector<double> time(n);
    for (std::size_t i = 0; i < n; ++i)
      time[i] = r.channel_start + static_cast<double>(i) / r.channel_rate;
    channels["time"] = ToArray(std::move(time));
    units["time"] = "s";
    for (const study::StoredSeries& c : r.channels) {
      channels[py::str(c.name)] = ToArray(std::vector<double>(c.values));
      units[py::str(c.name)] = c.unit;
    }
    d["channels"] = channels;
    d["units"] = units;
    d["channel_rate"] = r.channel_rate;
    d["wall_time"] = r.wall_time;
    runs.append(d);
  }
  return runs;
}

/// The variants of the modal reduction study: [{"name", "sets": ["key=value", ...], "modes"}].
py::list ReductionVariantList() {
  py::list out;
  for (const ReductionVariant& v : ReductionVariants()) {
    py::dict d;
    d["name"] = v.name;
    d["sets"] = v.sets;
    d["modes"] = v.modes;
    out.append(d);
  }
  return out;
}

/// The reduction study's figures of a run: [(name with unit, value)], NaN where undefined.
std::vector<std::pair<std::string, double>> ReductionFigureList(const std::string& summary_json,
                                                                double first_impact_time) {
  const ReductionFigures f = FiguresOf(nlohmann::json::parse(summary_json), first_impact_time);
  std::vector<std::pair<std::string, double>> out;
  for (int i = 0; i < ReductionFigures::kCount; ++i)
    out.emplace_back(ReductionFigures::Name(i), f.value[i]);
  return out;
}

/// The Python exception class `name` of the package, called with `args`, raised.
template <class... Args>
void RaisePython(const char* name, Args&&... args) {
  const py::object cls = py::module_::import("flexrod").attr(name);
  const py::object instance = cls(std::forward<Args>(args)...);
  PyErr_SetObject(cls.ptr(), instance.ptr());
}

}  // namespace
}  // namespace flexrod::python

PYBIND11_MODULE(_flexrod, m) {
  using namespace flexrod::python;
  m.doc() = "Compiled core of the flexrod package; use the functions of `flexrod`.";
  gsl_set_error_handler_off();  // as the CLI: every GSL status is checked where it is returned
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const flexrod::InputError& e) {
      RaisePython("InputError", e.key(), e.value(), e.rule());
    } catch (const flexrod::NumericalError& e) {
      RaisePython("NumericalError", std::string(e.what()));
    } catch (const flexrod::IoError& e) {
      RaisePython("IoError", std::string(e.what()));
    } catch (const flexrod::Interrupted& e) {
      PyErr_SetString(PyExc_KeyboardInterrupt, e.what());
    }
  });
  m.def("run", &RunInput, py::arg("input"), py::arg("sets"), py::arg("out"), py::arg("check"),
        py::arg("vtk"));
  m.def("keys", &Keys);
  m.def("modes", &Modes, py::arg("config"), py::arg("flags"));
  m.def("contact", &Contact, py::arg("law"), py::arg("mass"), py::arg("velocity"),
        py::arg("params"));
  m.def("sweep", &Sweep, py::arg("matrix"), py::arg("sets"), py::arg("jobs"), py::arg("out"));
  m.def("open_store", &OpenStore, py::arg("path"));
  m.def("reduction_variants", &ReductionVariantList);
  m.def("reduction_figures", &ReductionFigureList, py::arg("summary_json"),
        py::arg("first_impact_time"));
}
