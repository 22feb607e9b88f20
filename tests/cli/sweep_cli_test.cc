// tests/cli/sweep_cli_test.cc — `flexrod sweep` and `flexrod compare` end to end on the
// 4-run examples/sweep-small.toml: identical stores with 1 thread, 2 threads and 2 MPI ranks;
// a sweep killed with SIGKILL after its first finished run resumes without recomputing it and
// ends with the store of an uninterrupted sweep; a failed run is recorded and the sweep goes
// on; bad matrices exit with code 2 and write nothing; the Python reader finds a unit on every
// dataset and the stored input reruns the run exactly; compare writes its tables.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <fcntl.h>
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <nlohmann/json.hpp>
#include <string>
#include <thread>

#include "sweep/sweep_store.h"
#include "tests/test_util.h"

namespace {

namespace fs = std::filesystem;
using flexrod::study::ReadStore;
using flexrod::study::SameResults;
using flexrod::study::SweepStore;

using flexrod::test::CommandResult;
using flexrod::test::Flexrod;
using flexrod::test::Shell;

/// This test process's scratch directory.
fs::path Dir() {
  static const fs::path dir = flexrod::test::ScratchDir("sweep_cli");
  return dir;
}

std::string Small() { return std::string(FLEXROD_SOURCE_DIR) + "/examples/sweep-small.toml"; }

void ExpectSameStores(const std::string& a, const std::string& b) {
  const SweepStore x = ReadStore(a), y = ReadStore(b);
  ASSERT_EQ(x.runs.size(), y.runs.size());
  for (std::size_t i = 0; i < x.runs.size(); ++i) {
    std::string why;
    EXPECT_TRUE(SameResults(x.runs[i], y.runs[i], &why))
        << a << " vs " << b << ", run " << i << ": " << why;
  }
}

/// The reference store: sweep-small on one thread. ctest runs every test in its own process,
/// so the first process to compute it publishes it under a name keyed by the binary and the
/// matrix (rename: complete or absent), and later processes copy it.
std::string ReferenceStore(CommandResult* run = nullptr) {
  auto stamp = [](const fs::path& p) {
    struct stat st {};
    stat(p.c_str(), &st);
    return std::to_string(st.st_mtim.tv_sec) + std::to_string(st.st_mtim.tv_nsec) + "_" +
           std::to_string(st.st_size);
  };
  const fs::path shared =
      fs::temp_directory_path() /
      ("flexrod_sweep_cli_ref_" + stamp(FLEXROD_BINARY) + "_" + stamp(Small()) + ".h5");
  // A copy of its own: another build's tests may remove the shared one as stale meanwhile.
  const std::string local = (Dir() / "ref.h5").string();
  std::error_code copied;
  if (!run) fs::copy_file(shared, local, fs::copy_options::overwrite_existing, copied);
  if (!run && !copied && fs::exists(local)) return local;
  const CommandResult r =
      Flexrod("sweep " + Small() + " --jobs 1 " + (run ? "" : "--no-plot ") + "--out " + local);
  if (run) *run = r;
  if (r.exit_code != 0) return local;
  // Tests run in parallel processes: another one may publish the same reference at the same
  // time (either copy will do), and its copy in flight (shared.<pid>) is not stale.
  const fs::path tmp = shared.string() + "." + std::to_string(getpid());
  std::error_code ec;
  fs::copy_file(local, tmp, fs::copy_options::overwrite_existing, ec);
  if (!ec) fs::rename(tmp, shared, ec);
  if (ec) fs::remove(tmp, ec);
  // References of older binaries are stale: remove them.
  const std::string current = shared.filename().string();
  for (const auto& e : fs::directory_iterator(fs::temp_directory_path())) {
    const std::string name = e.path().filename().string();
    if (name.rfind("flexrod_sweep_cli_ref_", 0) == 0 && name.rfind(current, 0) != 0)
      fs::remove(e.path(), ec);
  }
  return local;
}

class SweepCli : public ::testing::Test {
 protected:
  static void TearDownTestSuite() { fs::remove_all(Dir()); }
};

TEST_F(SweepCli, SmallSweepCompletesWithTheLoadAmplificationOfEveryRun) {
  CommandResult run;
  const std::string reference = ReferenceStore(&run);
  ASSERT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("4 runs; 0 already finished; 4 to run on 1 thread"), std::string::npos)
      << run.output;
  EXPECT_NE(run.output.find("sweep: run 3 done"), std::string::npos);  // log lines off a terminal
  const SweepStore s = ReadStore(reference);
  ASSERT_EQ(s.runs.size(), 4u);
  EXPECT_EQ(s.num_failed, 0);
  for (const auto& run : s.runs) {
    EXPECT_TRUE(run.ok()) << run.message;
    // The clearance joint amplifies the ideal joint's peaks (amplification > 1 in at least one
    // direction: the impacts add to the kinematic acceleration).
    const double up = run.Summary("amplification_positive"),
                 down = run.Summary("amplification_negative");
    EXPECT_TRUE(std::isfinite(up) && std::isfinite(down)) << run.label;
    EXPECT_GT(std::max(up, down), 1.0) << run.label;
    EXPECT_DOUBLE_EQ(run.decimation, 2.0);  // 10 kHz record, 5 kHz store
  }
  EXPECT_TRUE(fs::exists(Dir() / "ref.summary.csv"));
  EXPECT_TRUE(fs::exists(Dir() / "ref.amplification.png"));
  EXPECT_FALSE(fs::exists(reference + ".parts"));
}

TEST_F(SweepCli, StoresAreIdenticalWithOneThreadTwoThreadsAndTwoMpiRanks) {
  const std::string reference = ReferenceStore();
  ASSERT_TRUE(fs::exists(reference)) << "the reference sweep failed";
  const std::string two = (Dir() / "two.h5").string();
  const CommandResult r2 = Flexrod("sweep " + Small() + " --jobs 2 --no-plot --out " + two);
  ASSERT_EQ(r2.exit_code, 0) << r2.output;
  ExpectSameStores(reference, two);
  ASSERT_TRUE(fs::exists("/usr/bin/mpirun")) << "Open MPI (Debian openmpi-bin) is needed";
  const std::string mpi = (Dir() / "mpi.h5").string();
  // -x ASAN_OPTIONS: in a sanitizer build, Open MPI's own allocations in MPI_Init (libmpi,
  // libopen-pal and its plugins) are reported as leaks at exit; the ranks' leak check is off,
  // the rest of the sanitizer stays on (and the thread runs above keep the leak check).
  const CommandResult rm =
      Shell("mpirun --allow-run-as-root --oversubscribe -x ASAN_OPTIONS=detect_leaks=0 -np 2 " +
            std::string(FLEXROD_BINARY) + " sweep " + Small() + " --no-plot --out " + mpi);
  ASSERT_EQ(rm.exit_code, 0) << rm.output;
  EXPECT_NE(rm.output.find("2 MPI ranks"), std::string::npos) << rm.output;
  ExpectSameStores(reference, mpi);
}

// An error that is not a failed run (here a full disk at the second part rank 0 commits, its
// own or a worker's, by fault injection) aborts every rank: a non-zero exit naming the error, no
// store, the finished part kept, and the rerun resumes from it to the same store as an undisturbed
// sweep.
TEST_F(SweepCli, AnErrorOnOneMpiRankAbortsEveryRankAndTheRerunResumes) {
  const std::string reference = ReferenceStore();
  ASSERT_TRUE(fs::exists(reference)) << "the reference sweep failed";
  ASSERT_TRUE(fs::exists("/usr/bin/mpirun")) << "Open MPI (Debian openmpi-bin) is needed";
  const std::string store = (Dir() / "mpi_abort.h5").string();
  const fs::path parts = store + ".parts";
  const std::string mpirun =
      "mpirun --allow-run-as-root --oversubscribe -x ASAN_OPTIONS=detect_leaks=0 ";
  const std::string sweep =
      std::string(FLEXROD_BINARY) + " sweep " + Small() + " --jobs 1 --no-plot --out " + store;
  // Rank 0 alone fails (a worker commits its parts to a scratch file before sending them).
  const CommandResult r =
      Shell(mpirun + "-np 1 env FLEXROD_FAIL_WRITE=2 " + sweep + " : -np 1 " + sweep);
  EXPECT_NE(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("flexrod: sweep aborted: No space left on device: " + parts.string()),
            std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(store));
  int kept = 0;
  for (const auto& e : fs::directory_iterator(parts)) kept += e.path().extension() == ".h5";
  EXPECT_EQ(kept, 1);
  // A worker's error aborts every rank too, naming the worker.
  const CommandResult w =
      Shell(mpirun + "-np 1 " + sweep + " : -np 1 env FLEXROD_FAIL_WRITE=1 " + sweep);
  EXPECT_NE(w.exit_code, 0) << w.output;
  EXPECT_NE(w.output.find("flexrod: sweep aborted: rank 1: No space left on device"),
            std::string::npos)
      << w.output;
  EXPECT_FALSE(fs::exists(store));
  const CommandResult again = Shell(mpirun + "-np 2 " + sweep);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  // The part of the first attempt is kept; the second attempt may have added rank 0's own.
  EXPECT_NE(again.output.find(" already finished; "), std::string::npos) << again.output;
  EXPECT_EQ(again.output.find("0 already finished"), std::string::npos) << again.output;
  ExpectSameStores(reference, store);
}

TEST_F(SweepCli, KilledSweepResumesWithoutRecomputingFinishedRuns) {
  const std::string reference = ReferenceStore();
  ASSERT_TRUE(fs::exists(reference)) << "the reference sweep failed";
  const std::string store = (Dir() / "killed.h5").string();
  const fs::path parts = store + ".parts";
  const fs::path log = Dir() / "killed.log";
  const pid_t pid = fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    const int fd = ::open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    dup2(fd, 1);
    dup2(fd, 2);
    execl(FLEXROD_BINARY, FLEXROD_BINARY, "sweep", Small().c_str(), "--jobs", "1", "--keep-parts",
          "--no-plot", "--out", store.c_str(), static_cast<char*>(nullptr));
    _exit(127);
  }
  // SIGKILL as soon as the first run is committed (a finished part, not a temporary).
  std::map<std::string, struct stat> finished;
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(60);
  while (finished.empty() && std::chrono::steady_clock::now() < deadline) {
    if (fs::is_directory(parts)) {
      for (const auto& e : fs::directory_iterator(parts)) {
        if (e.path().extension() == ".h5") {
          struct stat st {};
          if (stat(e.path().c_str(), &st) == 0) finished[e.path().string()] = st;
        }
      }
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
  }
  kill(pid, SIGKILL);
  int status = 0;
  waitpid(pid, &status, 0);
  ASSERT_FALSE(finished.empty()) << "no part appeared";
  ASSERT_TRUE(WIFSIGNALED(status)) << "the sweep ended before it could be killed";
  EXPECT_FALSE(fs::exists(store)) << "killed before assembly: no store yet";
  // Every part there now is complete: re-list (a second run may have finished meanwhile).
  finished.clear();
  for (const auto& e : fs::directory_iterator(parts)) {
    struct stat st {};
    if (e.path().extension() == ".h5" && stat(e.path().c_str(), &st) == 0)
      finished[e.path().string()] = st;
  }
  ASSERT_LT(finished.size(), 4u);
  const CommandResult again =
      Flexrod("sweep " + Small() + " --jobs 1 --keep-parts --no-plot --out " + store);
  ASSERT_EQ(again.exit_code, 0) << again.output;
  const std::string expected = "4 runs; " + std::to_string(finished.size()) +
                               " already finished; " + std::to_string(4 - finished.size()) +
                               " to run";
  EXPECT_NE(again.output.find(expected), std::string::npos) << again.output;
  for (const auto& [path, before] : finished) {
    struct stat after {};
    ASSERT_EQ(stat(path.c_str(), &after), 0) << path;
    EXPECT_EQ(before.st_ino, after.st_ino) << path << " was rewritten";
    EXPECT_EQ(before.st_mtim.tv_sec, after.st_mtim.tv_sec) << path;
    EXPECT_EQ(before.st_mtim.tv_nsec, after.st_mtim.tv_nsec) << path;
  }
  ExpectSameStores(reference, store);
}

// A full disk (fault injection: FLEXROD_FAIL_WRITE=N fails the N-th file committed, with
// ENOSPC) at a part and then at the store: exit 3 naming the file, no store under its name, every
// finished part kept, and the rerun resumes from them to the same store as an undisturbed sweep.
TEST_F(SweepCli, FullDiskAtAPartOrTheStoreLosesNoFinishedRunAndResumes) {
  const std::string reference = ReferenceStore();
  ASSERT_TRUE(fs::exists(reference)) << "the reference sweep failed";
  const std::string store = (Dir() / "full.h5").string();
  const fs::path parts = store + ".parts";
  auto count_parts = [&] {
    int n = 0;
    for (const auto& e : fs::directory_iterator(parts)) n += e.path().extension() == ".h5";
    return n;
  };
  const std::string sweep = "sweep " + Small() + " --jobs 1 --no-plot --out " + store;
  // The second part fails: the first is kept.
  CommandResult r = Shell("FLEXROD_FAIL_WRITE=2 " + std::string(FLEXROD_BINARY) + " " + sweep);
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("No space left on device: " + parts.string()), std::string::npos)
      << r.output;
  EXPECT_FALSE(fs::exists(store));
  EXPECT_EQ(count_parts(), 1);
  // Room for the three remaining parts but not for the store.
  r = Shell("FLEXROD_FAIL_WRITE=4 " + std::string(FLEXROD_BINARY) + " " + sweep);
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_NE(r.output.find("1 already finished; 3 to run"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("No space left on device: " + store), std::string::npos) << r.output;
  EXPECT_FALSE(fs::exists(store));
  EXPECT_FALSE(fs::exists(store + ".tmp"));
  EXPECT_EQ(count_parts(), 4);
  // Room again: nothing is recomputed.
  r = Flexrod(sweep);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("4 already finished; 0 to run"), std::string::npos) << r.output;
  ExpectSameStores(reference, store);
}

TEST_F(SweepCli, FailedRunIsRecordedAndTheSweepGoesOn) {
  const fs::path matrix = Dir() / "failing.toml";
  std::ofstream(matrix)
      << "[sweep]\nbase = \"rigid-rig\"\n[set]\nsim.settle = \"0.1 s\"\nsim.capture = \"0.2 s\"\n"
         "sim.sample_rate = \"10 kHz\"\n[axes]\n"
         "\"sim.max_steps\" = [10, 0]\n";  // run 0 fails: 10 steps do not reach its end
  const std::string store = (Dir() / "failing.h5").string();
  const CommandResult r =
      Flexrod("sweep " + matrix.string() + " --jobs 1 --no-plot --out " + store);
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("run 0 FAILED"), std::string::npos) << r.output;
  EXPECT_NE(r.output.find("sweep: run 1 done"), std::string::npos) << r.output;
  const SweepStore s = ReadStore(store);
  EXPECT_EQ(s.num_failed, 1);
  EXPECT_FALSE(s.runs[0].ok());
  EXPECT_FALSE(s.runs[0].message.empty());
  EXPECT_TRUE(s.runs[1].ok());
}

TEST_F(SweepCli, BadMatrixExitsWithCode2AndWritesNothing) {
  struct Case {
    std::string text, expect;
  };
  const std::vector<Case> cases = {
      {"[sweep]\nbase = \"rigid-rig\"\n[axes]\n\"rod.colour\" = [\"red\"]\n", "rod.colour"},
      {"[sweep]\nbase = \"rigid-rig\"\n[axes]\n\"drive.speed\" = []\n", "at least one value"},
      {"[sweep]\nbase = \"rigid-rig\"\n[axes\n", "malformed TOML"},
      {"[sweep]\nbase = \"rigid-rig\"\n[axes]\n\"rod.material\" = [\"steel\", \"wood\"]\n",
       "rod.material = wood"},
      {"[sweep]\nbase = \"rigid-rig\"\n[store]\nchannels = \"slider_jerk\"\n",
       "store.channels = slider_jerk"},
      // Run keys of every run, checked before any run (they used to fail every run, exit 0).
      {"[sweep]\nbase = \"rigid-rig\"\n[set]\n\"sim.capture\" = \"0 s\"\n", "sim.capture = 0"},
      {"[sweep]\nbase = \"rigid-rig\"\n[axes]\n\"sim.settle\" = [\"0.1 s\", \"-1 s\"]\n",
       "sim.settle = -1"},
      {"[sweep]\nbase = \"flexible-rig\"\n[set]\n\"output.midspan\" = \"0.3 m\"\n",
       "output.midspan = 0.3 m"},
      // The name is the default store's file name: it must not leave the output folder.
      {"[sweep]\nname = \"../x\"\nbase = \"rigid-rig\"\n", "sweep.name = \"../x\""},
      {"[sweep]\nname = \"\"\nbase = \"rigid-rig\"\n", "sweep.name = \"\""},
  };
  for (std::size_t i = 0; i < cases.size(); ++i) {
    const fs::path matrix = Dir() / ("bad" + std::to_string(i) + ".toml");
    std::ofstream(matrix) << cases[i].text;
    const std::string store = (Dir() / ("bad" + std::to_string(i) + ".h5")).string();
    const CommandResult r = Flexrod("sweep " + matrix.string() + " --no-plot --out " + store);
    EXPECT_EQ(r.exit_code, 2) << cases[i].text << r.output;
    EXPECT_NE(r.output.find(cases[i].expect), std::string::npos) << r.output;
    EXPECT_FALSE(fs::exists(store));
    EXPECT_FALSE(fs::exists(store + ".parts")) << cases[i].text;
  }
  EXPECT_EQ(Flexrod("sweep " + Small() + " --out " + (Dir() / "x.txt").string()).exit_code, 2);
  EXPECT_EQ(Flexrod("sweep no-such-matrix.toml").exit_code, 2);
  EXPECT_EQ(Flexrod("sweep " + Small() + " --jobs -1").exit_code, 2);
}

TEST_F(SweepCli, DefaultMatrixListsTheTable2Runs) {
  const CommandResult r = Flexrod("sweep --list");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_NE(r.output.find("table2: 189 runs"), std::string::npos);
  EXPECT_NE(r.output.find("  188  rod.material=steel, rod.height=25.4 mm, joint.clearance=1.0 mm, "
                          "drive.speed=200 rpm"),
            std::string::npos)
      << r.output;
}

TEST_F(SweepCli, ReaderFindsAUnitOnEveryDatasetAndTheStoredInputRerunsTheRun) {
  const std::string reference = ReferenceStore();
  ASSERT_TRUE(fs::exists(reference)) << "the reference sweep failed";
  const std::string reader = std::string(FLEXROD_PYTHON) + " " + FLEXROD_SOURCE_DIR +
                             "/examples/read_store.py " + reference;
  const CommandResult units = Shell(reader + " --check-units");
  ASSERT_EQ(units.exit_code, 0) << units.output;
  EXPECT_NE(units.output.find(" 0 without a unit"), std::string::npos) << units.output;
  const CommandResult listing = Shell(reader);
  ASSERT_EQ(listing.exit_code, 0) << listing.output;
  EXPECT_NE(listing.output.find("rod.height=19.05 mm, drive.speed=250 rpm"), std::string::npos)
      << listing.output;
  // Run 2 again from its stored input: the same peak, bit for bit (runs are deterministic).
  const fs::path input = Dir() / "run2.toml";
  const CommandResult stored_input = Shell(reader + " --input 2");
  ASSERT_EQ(stored_input.exit_code, 0) << stored_input.output;
  EXPECT_NE(stored_input.output.find("\"joint.type\" = \"clearance\""), std::string::npos)
      << stored_input.output;
  std::ofstream(input) << stored_input.output;
  const CommandResult rerun =
      Flexrod("run " + input.string() + " --no-plot --out " + (Dir() / "run2").string());
  ASSERT_EQ(rerun.exit_code, 0) << rerun.output;
  std::ifstream in(Dir() / "run2" / "summary.json");
  const nlohmann::json summary = nlohmann::json::parse(in);
  const SweepStore s = ReadStore(reference);
  EXPECT_EQ(summary["slider_acceleration"]["peak_positive"].get<double>(),
            s.runs[2].Summary("peak_positive"));
  EXPECT_EQ(summary["slider_acceleration"]["peak_negative"].get<double>(),
            s.runs[2].Summary("peak_negative"));
}

TEST_F(SweepCli, CompareWritesTheTablesOfEveryComparisonAndItsPlots) {
  const std::string reference = ReferenceStore();
  ASSERT_TRUE(fs::exists(reference)) << "the reference sweep failed";
  const fs::path out = Dir() / "compare";
  const CommandResult r = Flexrod("compare " + reference + " --group I --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(out / "comparisons.md"));
  for (int n = 1; n <= 12; ++n) {
    const std::string stem =
        (out / ((n < 10 ? "comparison_0" : "comparison_") + std::to_string(n))).string();
    EXPECT_TRUE(fs::exists(stem + ".md") && fs::exists(stem + ".csv") &&
                fs::exists(stem + "_points.csv"))
        << stem;
  }
  EXPECT_FALSE(fs::exists(out / "comparison_13.md"));  // group II not asked for
  // Comparison 3 (steel 12.7 / 19.05 / 25.4, 0.5 mm, negative): sweep-small has two of its rods.
  std::ifstream csv(out / "comparison_03.csv");
  std::string text((std::istreambuf_iterator<char>(csv)), std::istreambuf_iterator<char>());
  EXPECT_NE(text.find("steel 12.7 mm,2,0,"), std::string::npos) << text;
  EXPECT_NE(text.find("steel 19.05 mm,2,0,"), std::string::npos) << text;
  EXPECT_NE(text.find("-,steel 25.4 mm,0,0,0"), std::string::npos) << text;
  EXPECT_NE(r.output.find("comparison  3 (group I): Thesis trend"), std::string::npos);
  EXPECT_TRUE(fs::exists(out / "comparison_03_scatter.png"));
  EXPECT_TRUE(fs::exists(out / "comparison_03_plan.png"));
  // Bad options: exit 2, nothing written.
  EXPECT_EQ(
      Flexrod("compare " + reference + " --group IV --out " + (Dir() / "c2").string()).exit_code,
      2);
  EXPECT_EQ(Flexrod("compare " + reference + " --comparison 26 --out " + (Dir() / "c2").string())
                .exit_code,
            2);
  EXPECT_EQ(
      Flexrod("compare " + (Dir() / "missing.h5").string() + " --out " + (Dir() / "c2").string())
          .exit_code,
      2);
  // A damaged store (its second half cut off) and a foreign HDF5 file (a run's run.h5) are bad
  // input naming the file, not numerical failures.
  const fs::path cut = Dir() / "cut.h5";
  fs::copy_file(reference, cut, fs::copy_options::overwrite_existing);
  fs::resize_file(cut, fs::file_size(cut) / 2);
  CommandResult damaged = Flexrod("compare " + cut.string() + " --out " + (Dir() / "c2").string());
  EXPECT_EQ(damaged.exit_code, 2) << damaged.output;
  EXPECT_NE(damaged.output.find("store = " + cut.string()), std::string::npos) << damaged.output;
  const fs::path run = Dir() / "run";
  ASSERT_EQ(Flexrod("run rigid-rig --no-plot --set sim.settle=0s --set sim.capture=0.01s --out " +
                    run.string())
                .exit_code,
            0);
  const CommandResult foreign =
      Flexrod("compare " + (run / "run.h5").string() + " --out " + (Dir() / "c2").string());
  EXPECT_EQ(foreign.exit_code, 2) << foreign.output;
  EXPECT_NE(foreign.output.find("is not a flexrod sweep store"), std::string::npos)
      << foreign.output;
  EXPECT_FALSE(fs::exists(Dir() / "c2"));
}

}  // namespace
