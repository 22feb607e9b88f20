// SPDX-License-Identifier: GPL-3.0-or-later
// `flexrod sweep [matrix.toml] [--jobs N] [--out FILE.h5] [--set key=value ...]`: a test matrix
// on the cores of this machine, or across machines under mpirun (app/sweep_mpi.cc).
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <memory>
#include <thread>

#include "app/commands.h"
#include "app/plotting.h"
#include "app/sweep_app.h"
#include "common/error.h"
#include "sweep/sweep_compare.h"

namespace flexrod::app {
namespace {

std::string Duration(double seconds) {
  if (!std::isfinite(seconds) || seconds < 0.0) return "--";
  const long s = std::lround(seconds);
  char buf[32];
  if (s >= 3600) {
    std::snprintf(buf, sizeof buf, "%ldh%02ldm", s / 3600, (s / 60) % 60);
  } else if (s >= 60) {
    std::snprintf(buf, sizeof buf, "%ldm%02lds", s / 60, s % 60);
  } else {
    std::snprintf(buf, sizeof buf, "%lds", s);
  }
  return buf;
}

int DefaultJobs() { return std::max(1u, std::thread::hardware_concurrency()); }

int Sweep(const SweepRequest& request) {
  if (request.jobs < 0)
    throw InputError("--jobs", std::to_string(request.jobs), "must be >= 1 (0: all cores)");
  if (LaunchedUnderMpi() && !request.list) return RunSweepMpi(request);
  const study::SweepMatrix matrix = LoadRequestMatrix(request);
  if (request.list) {
    const char* rank = std::getenv("OMPI_COMM_WORLD_RANK");
    if (rank && std::string(rank) != "0") return 0;  // under mpirun: rank 0 prints
    std::printf("%s: %zu runs (base %s)\n", matrix.name.c_str(), matrix.num_runs(),
                matrix.base.c_str());
    for (const study::SweepRun& r : matrix.runs) std::printf("%5d  %s\n", r.id, r.Label().c_str());
    return 0;
  }
  const int jobs = request.jobs > 0 ? request.jobs : DefaultJobs();
  const std::string store = StorePath(request, matrix);
  ProgressDisplay display(matrix.name, std::to_string(jobs) + (jobs == 1 ? " thread" : " threads"));
  study::SweepOptions options;
  options.jobs = jobs;
  options.keep_parts = request.keep_parts;
  options.on_event = [&display](const study::SweepEvent& e) { display(e); };
  const study::SweepSession::Outcome outcome = study::RunSweep(matrix, store, options);
  display.Finish(outcome);
  AfterSweep(request, store);
  return 0;
}

}  // namespace

study::SweepMatrix LoadRequestMatrix(const SweepRequest& request) {
  return study::LoadSweepMatrix(request.matrix, request.sets);
}

std::string StorePath(const SweepRequest& request, const study::SweepMatrix& matrix) {
  if (!request.out.empty()) {
    study::CheckStorePath("--out", request.out);
    return request.out;
  }
  return "out/" + matrix.name + ".h5";
}

ProgressDisplay::ProgressDisplay(std::string name, std::string workers)
    : name_(std::move(name)),
      workers_(std::move(workers)),
      tty_(isatty(STDERR_FILENO) != 0),
      start_(std::chrono::steady_clock::now()) {}

void ProgressDisplay::operator()(const study::SweepEvent& e) {
  last_ = e;
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  const double eta = e.done > 0 ? elapsed / e.done * (e.to_run - e.done) : NAN;
  if (e.kind == study::SweepEvent::Kind::kStart) {
    std::fprintf(stderr, "sweep %s: %d runs; %d already finished; %d to run on %s\n", name_.c_str(),
                 e.total, e.already_done, e.to_run, workers_.c_str());
  } else if (!e.ok) {
    std::fprintf(stderr, "%ssweep: run %d FAILED (%s): %s\n", tty_ ? "\r\033[K" : "", e.id,
                 e.label.c_str(), e.message.c_str());
  } else if (!tty_) {
    std::fprintf(stderr, "sweep: run %d done in %.2f s [%d/%d, %d failed, ETA %s]: %s\n", e.id,
                 e.run_seconds, e.done, e.to_run, e.failed, Duration(eta).c_str(), e.label.c_str());
  }
  if (tty_ && e.to_run > 0) {
    constexpr int kWidth = 28;
    const int filled = e.to_run > 0 ? kWidth * e.done / e.to_run : kWidth;
    std::string bar(static_cast<std::size_t>(filled), '#');
    bar.resize(kWidth, '.');
    std::fprintf(stderr, "\r\033[K[%s] %d/%d runs | %d failed | %d resumed | %s elapsed | ETA %s",
                 bar.c_str(), e.done, e.to_run, e.failed, e.already_done, Duration(elapsed).c_str(),
                 Duration(eta).c_str());
  }
  std::fflush(stderr);
}

void ProgressDisplay::Finish(const study::SweepSession::Outcome& outcome) {
  const double elapsed =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (tty_ && last_.to_run > 0) std::fprintf(stderr, "\n");
  std::fprintf(stderr, "sweep %s: %d runs (%d computed now, %d failed) -> %s in %s\n",
               name_.c_str(), outcome.num_runs, last_.done, outcome.num_failed,
               outcome.store_path.c_str(), Duration(elapsed).c_str());
}

void AfterSweep(const SweepRequest& request, const std::string& store_path) {
  std::string stem = store_path;
  if (stem.size() > 3 && stem.substr(stem.size() - 3) == ".h5") stem.resize(stem.size() - 3);
  const study::SweepStore store = study::ReadStore(store_path, false);
  study::WriteSweepSummaryCsv(store, stem + ".summary.csv");
  std::fprintf(stderr, "sweep: summary table %s.summary.csv\n", stem.c_str());
  if (!request.no_plot) {
    if (RunPlotScript({"sweep", stem + ".summary.csv", stem + ".amplification.png"})) {
      std::fprintf(stderr, "sweep: plot %s.amplification.png\n", stem.c_str());
    }
  }
}

bool LaunchedUnderMpi() { return std::getenv("OMPI_COMM_WORLD_SIZE") != nullptr; }

void RegisterSweep(CLI::App& app, Handler* handler) {
  auto req = std::make_shared<SweepRequest>();
  CLI::App* cmd = app.add_subcommand(
      "sweep",
      "run a test matrix (default: the thesis's Table 2, 189 runs) into one HDF5 store; resumable; "
      "parallel on all cores, and across machines under mpirun");
  cmd->add_option("matrix", req->matrix,
                  "matrix file or built-in matrix (sweep-table2, sweep-small)")
      ->capture_default_str();
  cmd->add_option("--jobs,-j", req->jobs,
                  "worker threads (per MPI rank); 0 = all cores (per rank: cores / local ranks)")
      ->capture_default_str();
  cmd->add_option("--out", req->out, "store file FILE.h5 (default out/<matrix name>.h5)");
  cmd->add_option("--set", req->sets,
                  "override a base key or a store option: --set sim.capture=\"1 s\", "
                  "--set store.rate=\"20 kHz\"")
      ->take_all();
  cmd->add_flag("--keep-parts", req->keep_parts,
                "keep FILE.h5.parts/ (one file per run) after assembly");
  cmd->add_flag("--list", req->list, "print the runs of the matrix and exit");
  cmd->add_flag("--no-plot", req->no_plot, "skip the amplification plot");
  cmd->callback([req, handler] { *handler = [req] { return Sweep(*req); }; });
}

}  // namespace flexrod::app
