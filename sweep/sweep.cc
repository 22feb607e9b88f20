// SPDX-License-Identifier: GPL-3.0-or-later
// Sweeps: rod cache, validation, one run, threads, the store session.
#include "sweep/sweep.h"

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <filesystem>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include "common/error.h"
#include "common/files.h"
#include "input/output_selection.h"
#include "mechanisms/mechanism_model.h"
#include "run/run.h"

namespace flexrod::study {
namespace {

namespace fs = std::filesystem;

std::string JoinSet(const std::set<std::string>& names) {
  std::string s;
  for (const std::string& n : names) s += (s.empty() ? "" : ", ") + n;
  return s;
}

}  // namespace

// ---- rods ---------------------------------------------------------------------------------

std::shared_ptr<const fem::ReducedRod> RodCache::Get(const Config& cfg) {
  return rods_.Get(RodKey(cfg), [&cfg] { return BuildReducedRod(cfg); });
}

int RodCache::num_built() const { return static_cast<int>(rods_.num_computed()); }

// ---- validation and runs ----------------------------------------------------------------------

void ValidateSweep(const SweepMatrix& matrix, RodCache* rods) {
  std::set<std::string> available;
  bool any_checked = false;
  for (const SweepRun& run : matrix.runs) {
    const Config cfg = matrix.ConfigFor(run.id);
    std::shared_ptr<const fem::ReducedRod> rod;
    try {
      rod = rods->Get(cfg);
    } catch (const NumericalError&) {
      continue;  // recorded as a failure by the runs of this rod
    }
    const MechanismModel mm = BuildMechanism(cfg, rod);
    CheckRunInput(cfg, mm);
    const std::vector<std::string> names = RunChannelNames(cfg, mm);
    (void)ReadOutputSelection(cfg, cfg.Quantity("sim.sample_rate"), &names);
    available.insert(names.begin(), names.end());
    any_checked = true;
  }
  if (!any_checked) return;  // every rod failed numerically: the runs will say why
  for (const auto& [key, names] :
       {std::pair{"store.channels", &matrix.store.channels},
        std::pair{"store.poincare_channels", &matrix.store.poincare_channels}}) {
    for (const std::string& name : *names) {
      if (!available.count(name)) {
        throw InputError(
            key, name, "no run of this matrix has this channel; available: " + JoinSet(available));
      }
    }
  }
}

StoredRun ComputeSweepRun(const SweepMatrix& matrix, int id, RodCache* rods, TwinCache* twins,
                          const std::atomic<bool>* stop) {
  const auto t0 = std::chrono::steady_clock::now();
  const Config cfg = matrix.ConfigFor(id);
  StoredRun out;
  try {
    const std::shared_ptr<const fem::ReducedRod> rod = rods->Get(cfg);
    // An ensemble's members share the twin of the case's member 0.
    const Config twin_cfg = matrix.ConfigFor(matrix.runs[id].case_id);
    RunOutputOptions outputs;
    outputs.twins = twins;
    outputs.twin_input = &twin_cfg;
    outputs.stop = stop;
    const RunResult result = RunSimulation(cfg, rod, false, outputs);
    if (stop != nullptr && stop->load()) throw Interrupted("sweep interrupted");
    out = AnalyseRun(cfg, result, matrix.store);
  } catch (const Interrupted&) {
    throw;
  } catch (const InputError& e) {
    out = FailedRun(cfg, matrix.store, "input-error", e.what());
  } catch (const NumericalError& e) {
    out = FailedRun(cfg, matrix.store, "numerical-error", e.what());
  }  // anything else (a logic error, out of memory) is not a result of the run: it stops the sweep
  out.id = id;
  out.label = matrix.runs[id].Label();
  out.wall_time = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  return out;
}

void RunOnThreads(int jobs, const std::function<std::optional<int>()>& next,
                  const std::function<void(int)>& work) {
  std::mutex mutex;
  std::exception_ptr error;
  std::atomic<bool> stop{false};
  auto worker = [&] {
    for (;;) {
      std::optional<int> id;
      {
        std::lock_guard<std::mutex> lock(mutex);
        if (stop) return;
        id = next();
      }
      if (!id) return;
      try {
        work(*id);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        stop = true;
        return;
      }
    }
  };
  std::vector<std::thread> threads;
  for (int i = 1; i < std::max(jobs, 1); ++i) threads.emplace_back(worker);
  worker();  // the calling thread works too
  for (std::thread& t : threads) t.join();
  if (error) std::rethrow_exception(error);
}

// ---- session ------------------------------------------------------------------------------

SweepSession::SweepSession(const SweepMatrix& matrix, const std::string& store_path)
    : matrix_(matrix), store_path_(store_path), parts_dir_(store_path + ".parts") {
  CheckPathLength("--out", store_path, kCompanionSuffix);
  if (fs::exists(store_path) && !StoreIndex::IsStore(store_path)) {
    throw InputError("--out", store_path,
                     "exists and is not a flexrod sweep store: choose another file");
  }
  const std::string parent = fs::path(store_path).parent_path().string();
  if (!parent.empty()) {
    try {
      EnsureDirectory("--out", parent);
    } catch (const InputError& e) {  // named by the value given, the parent in the rule
      throw InputError("--out", store_path, "its directory " + parent + ": " + e.rule());
    }
  }
  EnsureDirectory("--out", parts_dir_);
  const std::string lock_path = parts_dir_ + "/.lock";
  lock_fd_ = ::open(lock_path.c_str(), O_RDWR | O_CREAT, 0644);
  if (lock_fd_ < 0)
    throw InputError("--out", store_path, "cannot create the lock file " + lock_path);
  if (::flock(lock_fd_, LOCK_EX | LOCK_NB) != 0) {
    ::close(lock_fd_);
    lock_fd_ = -1;
    throw InputError("--out", store_path,
                     "another flexrod sweep is writing this store (" + lock_path + " is locked)");
  }
  // Temporaries of a killed sweep are incomplete by construction: remove them.
  for (const auto& entry : fs::directory_iterator(parts_dir_)) {
    if (entry.path().extension() == ".tmp") fs::remove(entry.path());
  }
  std::error_code ec;
  fs::remove(store_path_ + ".tmp", ec);
  const StoreIndex previous(store_path_);
  for (const SweepRun& run : matrix_.runs) {
    const Config cfg = matrix_.ConfigFor(run.id);
    fingerprints_.push_back(RunFingerprint(cfg, matrix_.store));
    const std::string part = PartPath(run.id);
    bool finished = false;
    if (fs::is_regular_file(part)) {
      try {
        const StoredRun stored = ReadPartFile(part, false);
        finished =
            stored.fingerprint == fingerprints_.back() && stored.input_toml == InputToml(cfg);
      } catch (const IoError&) {  // damaged or incomplete: computed again
        finished = false;
      }
      if (!finished) fs::remove(part);
      from_parts_ += finished ? 1 : 0;
    }
    if (!finished && previous.Has(fingerprints_.back())) {
      finished = true;
      ++from_store_;
    }
    if (!finished) pending_.push_back(run.id);
  }
}

SweepSession::~SweepSession() {
  if (lock_fd_ >= 0) {
    ::flock(lock_fd_, LOCK_UN);
    ::close(lock_fd_);
  }
}

std::string SweepSession::PartPath(int id) const {
  return parts_dir_ + "/" + fingerprints_.at(static_cast<std::size_t>(id)) + ".h5";
}

void SweepSession::Save(const StoredRun& run) { WritePartFile(PartPath(run.id), run); }

StoredRun SweepSession::SaveBytes(int id, const std::string& bytes) {
  const std::string path = PartPath(id);
  WriteFileDurable(path, bytes);
  StoredRun back = ReadPartFile(path, false);
  if (back.fingerprint != fingerprints_.at(static_cast<std::size_t>(id))) {
    fs::remove(path);
    throw IoError("part received for run " + std::to_string(id) + " has another fingerprint");
  }
  return back;
}

SweepSession::Outcome SweepSession::Assemble(bool keep_parts) {
  const StoreIndex previous(store_path_);
  StoreHeader header;
  header.name = matrix_.name;
  header.origin = matrix_.origin;
  header.base = matrix_.base;
  header.matrix_source = matrix_.source;
  header.axis_keys = matrix_.axis_keys;
  header.num_runs = static_cast<int>(matrix_.runs.size());
  Outcome outcome;
  int next_id = 0;
  WriteStore(store_path_, header, [&](StoredRun* run) {
    if (next_id >= header.num_runs) return false;
    const std::string part = PartPath(next_id);
    const std::string& fp = fingerprints_[static_cast<std::size_t>(next_id)];
    if (fs::is_regular_file(part)) {
      *run = ReadPartFile(part, true);
    } else if (previous.Has(fp)) {
      *run = previous.Read(fp);
    } else {
      throw IoError("run " + std::to_string(next_id) + " has no result: neither " + part +
                    " nor in " + store_path_);
    }
    run->id = next_id;
    run->label = matrix_.runs[static_cast<std::size_t>(next_id)].Label();
    outcome.num_failed += run->ok() ? 0 : 1;
    ++next_id;
    return true;
  });
  // WriteStore wrote FILE.h5.tmp and renamed it over FILE.h5: the old store is replaced whole.
  std::error_code ec;
  outcome.num_runs = header.num_runs;
  outcome.store_path = store_path_;
  if (!keep_parts) {
    for (const auto& entry : fs::directory_iterator(parts_dir_)) fs::remove(entry.path(), ec);
    fs::remove(parts_dir_, ec);
  }
  return outcome;
}

std::vector<int> TwinOrder(const SweepMatrix& matrix, const std::vector<int>& ids, int jobs) {
  std::map<std::string, std::size_t> group_of;
  std::vector<std::vector<int>> groups;
  for (int id : ids) {
    const auto [it, added] =
        group_of.emplace(TwinKey(matrix.ConfigFor(matrix.runs[id].case_id)), groups.size());
    if (added) groups.emplace_back();
    groups[it->second].push_back(id);
  }
  const std::size_t block = static_cast<std::size_t>(std::max(jobs, 1));
  std::vector<int> order;
  for (std::size_t first = 0; first < groups.size(); first += block) {
    const std::size_t last = std::min(first + block, groups.size());
    for (std::size_t k = 0; order.size() < ids.size(); ++k) {
      bool any = false;
      for (std::size_t g = first; g < last; ++g) {
        if (k < groups[g].size()) {
          order.push_back(groups[g][k]);
          any = true;
        }
      }
      if (!any) break;
    }
  }
  return order;
}

// ---- local sweep --------------------------------------------------------------------------

void CheckStorePath(const std::string& key, const std::string& path) {
  if (fs::path(path).extension() != ".h5") throw InputError(key, path, "must end in .h5");
}

SweepSession::Outcome RunSweep(const SweepMatrix& matrix, const std::string& store_path,
                               const SweepOptions& options) {
  RodCache rods;
  TwinCache twins(static_cast<std::size_t>(options.jobs));
  ValidateSweep(matrix, &rods);
  SweepSession session(matrix, store_path);
  const std::vector<int> pending = TwinOrder(matrix, session.pending(), options.jobs);
  std::mutex event_mutex;
  SweepEvent state;
  state.total = static_cast<int>(matrix.runs.size());
  state.already_done = state.total - static_cast<int>(pending.size());
  state.to_run = static_cast<int>(pending.size());
  if (options.on_event) options.on_event(state);
  std::size_t cursor = 0;
  RunOnThreads(
      options.jobs,
      [&]() -> std::optional<int> {
        return cursor < pending.size() ? std::optional<int>(pending[cursor++]) : std::nullopt;
      },
      [&](int id) {
        const StoredRun run = ComputeSweepRun(matrix, id, &rods, &twins, options.stop);
        session.Save(run);
        std::lock_guard<std::mutex> lock(event_mutex);
        state.kind = SweepEvent::Kind::kRunDone;
        ++state.done;
        state.failed += run.ok() ? 0 : 1;
        state.id = id;
        state.ok = run.ok();
        state.label = run.label;
        state.message = run.message;
        state.run_seconds = run.wall_time;
        if (options.on_event) options.on_event(state);
      });
  return session.Assemble(options.keep_parts);
}

}  // namespace flexrod::study
