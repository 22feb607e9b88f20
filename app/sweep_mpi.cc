// SPDX-License-Identifier: GPL-3.0-or-later
// `mpirun -np N flexrod sweep ...`: rank 0 validates the matrix, owns the store (parts, lock,
// assembly) and hands out run ids on request; every rank (rank 0 included) computes runs on its
// own threads with its own reduced-rod cache and sends each finished run to rank 0 as the bytes
// of its part file. Only each rank's main thread calls MPI (MPI_THREAD_FUNNELED). MPI is
// initialised only here, so the plain binary never needs it.
// The C API only: Open MPI's deprecated C++ bindings are not linked (MPI::MPI_C).
#define OMPI_SKIP_MPICXX 1
#define MPICH_SKIP_MPICXX 1
#include <mpi.h>
#include <unistd.h>

#include <atomic>
#include <condition_variable>
#include <cstdio>
#include <cstring>
#include <deque>
#include <exception>
#include <filesystem>
#include <memory>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

#include "app/sweep_app.h"
#include "common/error.h"

namespace flexrod::app {
namespace {

namespace fs = std::filesystem;

constexpr int kTagRequest = 1;  // worker -> 0: give me a run id
constexpr int kTagAssign = 2;   // 0 -> worker: a run id, or -1: no more
constexpr int kTagResult = 3;   // worker -> 0: int id + part file bytes

void Check(int rc, const char* call) {
  if (rc != MPI_SUCCESS)
    throw NumericalError(std::string("MPI call ") + call + " failed with code " +
                         std::to_string(rc));
}

/// MPI for the lifetime of the sweep.
class MpiSession {
 public:
  MpiSession() {
    int provided = 0;
    Check(MPI_Init_thread(nullptr, nullptr, MPI_THREAD_FUNNELED, &provided), "MPI_Init_thread");
    Check(MPI_Comm_rank(MPI_COMM_WORLD, &rank_), "MPI_Comm_rank");
    Check(MPI_Comm_size(MPI_COMM_WORLD, &size_), "MPI_Comm_size");
  }
  ~MpiSession() { MPI_Finalize(); }
  MpiSession(const MpiSession&) = delete;
  MpiSession& operator=(const MpiSession&) = delete;
  int rank() const { return rank_; }
  int size() const { return size_; }

 private:
  int rank_{0}, size_{1};
};

[[noreturn]] void Abort(const std::string& what) {
  std::fprintf(stderr, "flexrod: sweep aborted: %s\n", what.c_str());
  std::fflush(stderr);
  MPI_Abort(MPI_COMM_WORLD, 1);
  std::_Exit(1);
}

void BroadcastString(std::string* s) {
  long long n = static_cast<long long>(s->size());
  Check(MPI_Bcast(&n, 1, MPI_LONG_LONG, 0, MPI_COMM_WORLD), "MPI_Bcast");
  s->resize(static_cast<std::size_t>(n));
  Check(MPI_Bcast(s->data(), static_cast<int>(n), MPI_CHAR, 0, MPI_COMM_WORLD), "MPI_Bcast");
}

int JobsPerRank(const SweepRequest& request) {
  if (request.jobs > 0) return request.jobs;
  int local = 1;
  if (const char* env = std::getenv("OMPI_COMM_WORLD_LOCAL_SIZE"))
    local = std::max(1, std::atoi(env));
  return std::max(1, static_cast<int>(std::thread::hardware_concurrency()) / local);
}

/// Rethrows `error` and aborts every rank with `prefix` and its message.
[[noreturn]] void AbortOn(const std::exception_ptr& error, const std::string& prefix) {
  try {
    std::rethrow_exception(error);
  } catch (const std::exception& e) {
    Abort(prefix + e.what());
  }
}

/// Rank 0's run ids still to hand out and the sweep's progress, shared by its own threads and
/// its MPI loop; every member takes the lock.
class RunLedger {
 public:
  /// Shows the starting state: `order` are the runs still to compute.
  RunLedger(const study::SweepMatrix& matrix, const std::vector<int>& order,
            ProgressDisplay* display)
      : matrix_(matrix), display_(display), queue_(order.begin(), order.end()) {
    state_.total = static_cast<int>(matrix.num_runs());
    state_.to_run = static_cast<int>(queue_.size());
    state_.already_done = state_.total - state_.to_run;
    (*display_)(state_);
  }

  /// The next run id, nullopt when every run has been handed out.
  std::optional<int> Pop() {
    std::lock_guard<std::mutex> lock(mutex_);
    if (queue_.empty()) return std::nullopt;
    const int id = queue_.front();
    queue_.pop_front();
    return id;
  }

  /// Counts a finished run (computed here or received) and shows it.
  void Record(const study::StoredRun& run) {
    std::lock_guard<std::mutex> lock(mutex_);
    state_.kind = study::SweepEvent::Kind::kRunDone;
    ++state_.done;
    state_.failed += run.ok() ? 0 : 1;
    state_.id = run.id;
    state_.ok = run.ok();
    state_.label = matrix_.runs[static_cast<std::size_t>(run.id)].Label();
    state_.message = run.message;
    state_.run_seconds = run.wall_time;
    (*display_)(state_);
  }

  /// Whether every run to compute has been recorded.
  bool AllDone() {
    std::lock_guard<std::mutex> lock(mutex_);
    return state_.done >= state_.to_run;
  }

 private:
  const study::SweepMatrix& matrix_;
  ProgressDisplay* display_;
  std::mutex mutex_;
  std::deque<int> queue_;
  study::SweepEvent state_;
};

/// Rank 0: answers one probed message of a worker rank. A request gets the next run id, or −1
/// when none is left (that worker then stops asking: *workers_active drops); a result's part
/// bytes are saved to the store and recorded.
void AnswerWorker(const MPI_Status& status, RunLedger* ledger, study::SweepSession* session,
                  int* workers_active) {
  if (status.MPI_TAG == kTagRequest) {
    int unused = 0;
    Check(MPI_Recv(&unused, 1, MPI_INT, status.MPI_SOURCE, kTagRequest, MPI_COMM_WORLD,
                   MPI_STATUS_IGNORE),
          "MPI_Recv");
    const int id = ledger->Pop().value_or(-1);
    Check(MPI_Send(&id, 1, MPI_INT, status.MPI_SOURCE, kTagAssign, MPI_COMM_WORLD), "MPI_Send");
    if (id < 0) --*workers_active;
  } else if (status.MPI_TAG == kTagResult) {
    int count = 0;
    Check(MPI_Get_count(&status, MPI_BYTE, &count), "MPI_Get_count");
    std::string buffer(static_cast<std::size_t>(count), '\0');
    Check(MPI_Recv(buffer.data(), count, MPI_BYTE, status.MPI_SOURCE, kTagResult, MPI_COMM_WORLD,
                   MPI_STATUS_IGNORE),
          "MPI_Recv");
    int id = 0;
    std::memcpy(&id, buffer.data(), sizeof id);
    study::StoredRun run = session->SaveBytes(id, buffer.substr(sizeof id));
    run.id = id;
    ledger->Record(run);
  } else {
    Abort("unexpected MPI message tag " + std::to_string(status.MPI_TAG));
  }
}

/// Rank 0: serve run ids and collect results while its own threads compute.
study::SweepSession::Outcome Serve(const MpiSession& mpi, const SweepRequest& request,
                                   const study::SweepMatrix& matrix, study::RodCache* rods,
                                   study::SweepSession* session) {
  const int jobs = JobsPerRank(request);
  ProgressDisplay display(matrix.name, std::to_string(mpi.size()) + " MPI ranks x " +
                                           std::to_string(jobs) +
                                           (jobs == 1 ? " thread" : " threads"));
  // Runs handed out at about the same time (to every worker of every rank) have different twins.
  RunLedger ledger(matrix, study::TwinOrder(matrix, session->pending(), mpi.size() * jobs),
                   &display);
  TwinCache twins(static_cast<std::size_t>(jobs));
  std::exception_ptr local_error;
  std::atomic<bool> local_failed{false};
  std::thread local([&] {
    try {
      study::RunOnThreads(
          jobs, [&] { return ledger.Pop(); },
          [&](int id) {
            const study::StoredRun run = study::ComputeSweepRun(matrix, id, rods, &twins);
            session->Save(run);
            ledger.Record(run);
          });
    } catch (...) {
      local_error = std::current_exception();
      local_failed = true;
    }
  });
  int workers_active = mpi.size() - 1;
  // An error on this thread (a part that cannot be saved, an MPI failure) aborts every rank, the
  // local compute thread included: unwinding past that thread would terminate this rank alone.
  try {
    while (workers_active > 0 || !ledger.AllDone()) {
      if (local_failed) {
        local.join();
        AbortOn(local_error, "");
      }
      int flag = 0;
      MPI_Status status;
      Check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
      if (!flag) {
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
        continue;
      }
      AnswerWorker(status, &ledger, session, &workers_active);
    }
  } catch (const std::exception& e) {
    Abort(e.what());
  }
  local.join();
  if (local_error) AbortOn(local_error, "");
  const study::SweepSession::Outcome outcome = session->Assemble(request.keep_parts);
  display.Finish(outcome);
  return outcome;
}

/// What a worker rank's compute threads and its main thread share, under `mutex`: the run ids
/// rank 0 assigned, the finished runs' messages still to send, and the threads' states.
struct RankExchange {
  std::mutex mutex;
  std::condition_variable cv;
  int waiting{0};                                  // threads waiting for an id
  int active{0};                                   // threads not yet ended
  bool exhausted{false};                           // rank 0 has no run left
  std::deque<int> ids;                             // assigned, not yet taken by a thread
  std::deque<std::pair<int, std::string>> outbox;  // (id, message) to send to rank 0
  std::exception_ptr error;                        // the first a thread threw
};

/// The message of a finished run for rank 0: the int id, then the bytes of its part file
/// (written to and removed from `scratch`).
std::string PartMessage(int id, const study::StoredRun& run, const fs::path& scratch) {
  const std::string path = (scratch / (std::to_string(id) + ".h5")).string();
  study::WritePartFile(path, run);
  std::string message(sizeof id, '\0');
  std::memcpy(message.data(), &id, sizeof id);
  message += study::ReadFileBytes(path);
  fs::remove(path);
  return message;
}

/// A compute thread of a worker rank: takes assigned ids until rank 0 has none left, computes
/// each run and posts its message; an exception is kept for the main thread.
void ComputeAssignedRuns(const study::SweepMatrix& matrix, study::RodCache* rods, TwinCache* twins,
                         const fs::path& scratch, RankExchange* x) {
  try {
    for (;;) {
      int id = -1;
      {
        std::unique_lock<std::mutex> lock(x->mutex);
        ++x->waiting;
        x->cv.notify_all();
        x->cv.wait(lock, [&] { return !x->ids.empty() || x->exhausted; });
        --x->waiting;
        if (x->ids.empty()) break;
        id = x->ids.front();
        x->ids.pop_front();
      }
      const study::StoredRun run = study::ComputeSweepRun(matrix, id, rods, twins);
      std::string message = PartMessage(id, run, scratch);
      std::lock_guard<std::mutex> lock(x->mutex);
      x->outbox.emplace_back(id, std::move(message));
      x->cv.notify_all();
    }
  } catch (...) {
    std::lock_guard<std::mutex> lock(x->mutex);
    if (!x->error) x->error = std::current_exception();
  }
  std::lock_guard<std::mutex> lock(x->mutex);
  --x->active;
  x->cv.notify_all();
}

/// The main thread of a worker rank, the only one that calls MPI: sends the finished runs to
/// rank 0 and asks it for an id whenever more threads wait than ids are queued, until every
/// compute thread has ended. A thread's exception aborts every rank.
void RelayToRoot(const MpiSession& mpi, RankExchange* x) {
  for (;;) {
    std::unique_lock<std::mutex> lock(x->mutex);
    x->cv.wait(lock, [&] {
      return x->error || !x->outbox.empty() ||
             (!x->exhausted && x->waiting > static_cast<int>(x->ids.size())) || x->active == 0;
    });
    if (x->error) AbortOn(x->error, "rank " + std::to_string(mpi.rank()) + ": ");
    if (!x->outbox.empty()) {
      const std::pair<int, std::string> item = std::move(x->outbox.front());
      x->outbox.pop_front();
      lock.unlock();
      Check(MPI_Send(item.second.data(), static_cast<int>(item.second.size()), MPI_BYTE, 0,
                     kTagResult, MPI_COMM_WORLD),
            "MPI_Send");
      continue;
    }
    if (!x->exhausted && x->waiting > static_cast<int>(x->ids.size())) {
      lock.unlock();
      int id = -1, unused = 0;
      Check(MPI_Send(&unused, 1, MPI_INT, 0, kTagRequest, MPI_COMM_WORLD), "MPI_Send");
      Check(MPI_Recv(&id, 1, MPI_INT, 0, kTagAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
            "MPI_Recv");
      lock.lock();
      if (id < 0) {
        x->exhausted = true;
      } else {
        x->ids.push_back(id);
      }
      x->cv.notify_all();
      continue;
    }
    if (x->active == 0) break;
  }
}

/// Rank > 0: threads compute, the main thread asks rank 0 for ids and sends the parts back.
void Work(const MpiSession& mpi, const SweepRequest& request, const study::SweepMatrix& matrix) {
  const int jobs = JobsPerRank(request);
  study::RodCache rods;
  TwinCache twins(static_cast<std::size_t>(jobs));
  const fs::path scratch =
      fs::temp_directory_path() /
      ("flexrod-sweep-rank" + std::to_string(mpi.rank()) + "-" + std::to_string(::getpid()));
  fs::create_directories(scratch);
  RankExchange exchange;
  exchange.active = jobs;
  std::vector<std::thread> threads;
  for (int j = 0; j < jobs; ++j) {
    threads.emplace_back([&] { ComputeAssignedRuns(matrix, &rods, &twins, scratch, &exchange); });
  }
  try {  // as in Serve: never unwind past the compute threads
    RelayToRoot(mpi, &exchange);
  } catch (const std::exception& e) {
    Abort("rank " + std::to_string(mpi.rank()) + ": " + e.what());
  }
  for (std::thread& t : threads) t.join();
  std::error_code ec;
  fs::remove_all(scratch, ec);
}

}  // namespace

int RunSweepMpi(const SweepRequest& request) {
  std::string store_path;
  int code = 0;
  {
    MpiSession mpi;
    // Rank 0 validates everything before anyone computes; bad input stops every rank.
    std::unique_ptr<study::SweepMatrix> matrix;
    std::unique_ptr<study::RodCache> rods;
    std::unique_ptr<study::SweepSession> session;
    std::string error;
    if (mpi.rank() == 0) {
      try {
        matrix = std::make_unique<study::SweepMatrix>(LoadRequestMatrix(request));
        store_path = StorePath(request, *matrix);
        rods = std::make_unique<study::RodCache>();
        study::ValidateSweep(*matrix, rods.get());
        session = std::make_unique<study::SweepSession>(*matrix, store_path);
      } catch (const InputError& e) {
        code = 2;
        error = "flexrod: error: " + std::string(e.what());
      } catch (const std::exception& e) {
        code = 1;
        error = "flexrod: " + std::string(e.what());
      }
    }
    Check(MPI_Bcast(&code, 1, MPI_INT, 0, MPI_COMM_WORLD), "MPI_Bcast");
    if (code != 0) {
      if (mpi.rank() == 0) std::fprintf(stderr, "%s\n", error.c_str());
      return code;
    }
    std::string json = mpi.rank() == 0 ? study::SweepMatrixToJson(*matrix).dump() : std::string();
    BroadcastString(&json);
    try {
      if (mpi.rank() == 0) {
        Serve(mpi, request, *matrix, rods.get(), session.get());
      } else {
        Work(mpi, request, study::SweepMatrixFromJson(nlohmann::json::parse(json)));
      }
    } catch (const std::exception& e) {
      Abort(e.what());
    }
    session.reset();  // releases the store lock before MPI is finalised
  }
  if (!store_path.empty()) AfterSweep(request, store_path);
  return code;
}

}  // namespace flexrod::app
