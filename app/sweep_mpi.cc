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

/// Rank 0: serve run ids and collect results while its own threads compute.
study::SweepSession::Outcome Serve(const MpiSession& mpi, const SweepRequest& request,
                                   const study::SweepMatrix& matrix, study::RodCache* rods,
                                   study::SweepSession* session) {
  const int jobs = JobsPerRank(request);
  ProgressDisplay display(matrix.name, std::to_string(mpi.size()) + " MPI ranks x " +
                                           std::to_string(jobs) +
                                           (jobs == 1 ? " thread" : " threads"));
  std::mutex mutex;
  // Runs handed out at about the same time (to every worker of every rank) have different twins.
  const std::vector<int> order = study::TwinOrder(matrix, session->pending(), mpi.size() * jobs);
  std::deque<int> queue(order.begin(), order.end());
  study::SweepEvent state;
  state.total = static_cast<int>(matrix.num_runs());
  state.to_run = static_cast<int>(queue.size());
  state.already_done = state.total - state.to_run;
  display(state);
  auto record = [&](const study::StoredRun& run) {
    std::lock_guard<std::mutex> lock(mutex);
    state.kind = study::SweepEvent::Kind::kRunDone;
    ++state.done;
    state.failed += run.ok() ? 0 : 1;
    state.id = run.id;
    state.ok = run.ok();
    state.label = matrix.runs[static_cast<std::size_t>(run.id)].Label();
    state.message = run.message;
    state.run_seconds = run.wall_time;
    display(state);
  };
  auto pop = [&]() -> std::optional<int> {
    std::lock_guard<std::mutex> lock(mutex);
    if (queue.empty()) return std::nullopt;
    const int id = queue.front();
    queue.pop_front();
    return id;
  };
  TwinCache twins(static_cast<std::size_t>(jobs));
  std::exception_ptr local_error;
  std::atomic<bool> local_failed{false};
  std::thread local([&] {
    try {
      study::RunOnThreads(jobs, pop, [&](int id) {
        const study::StoredRun run = study::ComputeSweepRun(matrix, id, rods, &twins);
        session->Save(run);
        record(run);
      });
    } catch (...) {
      local_error = std::current_exception();
      local_failed = true;
    }
  });
  int workers_active = mpi.size() - 1;
  auto done = [&] {
    std::lock_guard<std::mutex> lock(mutex);
    return state.done >= state.to_run;
  };
  while (workers_active > 0 || !done()) {
    if (local_failed) {
      local.join();
      try {
        std::rethrow_exception(local_error);
      } catch (const std::exception& e) {
        Abort(e.what());
      }
    }
    int flag = 0;
    MPI_Status status;
    Check(MPI_Iprobe(MPI_ANY_SOURCE, MPI_ANY_TAG, MPI_COMM_WORLD, &flag, &status), "MPI_Iprobe");
    if (!flag) {
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
      continue;
    }
    if (status.MPI_TAG == kTagRequest) {
      int unused = 0;
      Check(MPI_Recv(&unused, 1, MPI_INT, status.MPI_SOURCE, kTagRequest, MPI_COMM_WORLD,
                     MPI_STATUS_IGNORE),
            "MPI_Recv");
      const int id = pop().value_or(-1);
      Check(MPI_Send(&id, 1, MPI_INT, status.MPI_SOURCE, kTagAssign, MPI_COMM_WORLD), "MPI_Send");
      if (id < 0) --workers_active;
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
      record(run);
    } else {
      Abort("unexpected MPI message tag " + std::to_string(status.MPI_TAG));
    }
  }
  local.join();
  if (local_error) {
    try {
      std::rethrow_exception(local_error);
    } catch (const std::exception& e) {
      Abort(e.what());
    }
  }
  const study::SweepSession::Outcome outcome = session->Assemble(request.keep_parts);
  display.Finish(outcome);
  return outcome;
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
  std::mutex mutex;
  std::condition_variable cv;
  int waiting = 0, active = jobs;
  bool exhausted = false;
  std::deque<int> ids;
  std::deque<std::pair<int, std::string>> outbox;
  std::exception_ptr error;
  std::vector<std::thread> threads;
  for (int j = 0; j < jobs; ++j) {
    threads.emplace_back([&] {
      try {
        for (;;) {
          int id = -1;
          {
            std::unique_lock<std::mutex> lock(mutex);
            ++waiting;
            cv.notify_all();
            cv.wait(lock, [&] { return !ids.empty() || exhausted; });
            --waiting;
            if (ids.empty()) break;
            id = ids.front();
            ids.pop_front();
          }
          const study::StoredRun run = study::ComputeSweepRun(matrix, id, &rods, &twins);
          const std::string path = (scratch / (std::to_string(id) + ".h5")).string();
          study::WritePartFile(path, run);
          std::string message(sizeof id, '\0');
          std::memcpy(message.data(), &id, sizeof id);
          message += study::ReadFileBytes(path);
          fs::remove(path);
          std::lock_guard<std::mutex> lock(mutex);
          outbox.emplace_back(id, std::move(message));
          cv.notify_all();
        }
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
      }
      std::lock_guard<std::mutex> lock(mutex);
      --active;
      cv.notify_all();
    });
  }
  for (;;) {
    std::unique_lock<std::mutex> lock(mutex);
    cv.wait(lock, [&] {
      return error || !outbox.empty() || (!exhausted && waiting > static_cast<int>(ids.size())) ||
             active == 0;
    });
    if (error) {
      try {
        std::rethrow_exception(error);
      } catch (const std::exception& e) {
        Abort("rank " + std::to_string(mpi.rank()) + ": " + e.what());
      }
    }
    if (!outbox.empty()) {
      const std::pair<int, std::string> item = std::move(outbox.front());
      outbox.pop_front();
      lock.unlock();
      Check(MPI_Send(item.second.data(), static_cast<int>(item.second.size()), MPI_BYTE, 0,
                     kTagResult, MPI_COMM_WORLD),
            "MPI_Send");
      continue;
    }
    if (!exhausted && waiting > static_cast<int>(ids.size())) {
      lock.unlock();
      int id = -1, unused = 0;
      Check(MPI_Send(&unused, 1, MPI_INT, 0, kTagRequest, MPI_COMM_WORLD), "MPI_Send");
      Check(MPI_Recv(&id, 1, MPI_INT, 0, kTagAssign, MPI_COMM_WORLD, MPI_STATUS_IGNORE),
            "MPI_Recv");
      lock.lock();
      if (id < 0) {
        exhausted = true;
      } else {
        ids.push_back(id);
      }
      cv.notify_all();
      continue;
    }
    if (active == 0) break;
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
