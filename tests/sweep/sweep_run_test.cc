// Tests of sweep/sweep.h on small real sweeps of the rigid rig (fast) and the flexible rig's
// reduced rods: one reduced rod per distinct rod whatever the threads, results independent of
// the number of threads, a failed run recorded while the sweep goes on, an interrupted sweep
// resumed without recomputing its finished runs and ending with the same store, the store
// lock, and bad input refused before anything is written.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>
#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <thread>

#include "common/error.h"
#include "sweep/sweep.h"
#include "tests/test_util.h"

namespace flexrod::study {
namespace {

namespace fs = std::filesystem;
using flexrod::test::ScratchDir;

// The rigid rig (RIG.md §1) at 101 and 177 rpm with two slider masses: 4 short runs.
const char* kRigidMatrix = R"(
[sweep]
name = "rigid-test"
base = "rigid-rig"
[set]
joint.type = "ideal"
sim.settle = "0.1 s"
sim.capture = "0.4 s"
sim.sample_rate = "10 kHz"
[axes]
"drive.speed" = ["101 rpm", "177 rpm"]
"slider.mass" = ["1.02 kg", "1.5 kg"]
)";

SweepMatrix Matrix(const char* text, const std::vector<std::string>& sets = {}) {
  return ParseSweepMatrix(text, "test.toml", ".", sets);
}

void ExpectSameStores(const std::string& a, const std::string& b) {
  const SweepStore x = ReadStore(a), y = ReadStore(b);
  ASSERT_EQ(x.runs.size(), y.runs.size());
  for (std::size_t i = 0; i < x.runs.size(); ++i) {
    std::string why;
    EXPECT_TRUE(SameResults(x.runs[i], y.runs[i], &why)) << "run " << i << ": " << why;
    EXPECT_EQ(x.runs[i].id, static_cast<int>(i));
    EXPECT_EQ(y.runs[i].id, static_cast<int>(i));
  }
}

TEST(SweepRun, RunsSharingAnIdealTwinAreComputedNextToEachOther) {
  // Table 2's shape: clearance in the outer combinations, so 0.5 and 1.0 mm at one height and
  // speed (the same twin) are far apart in run-id order.
  const SweepMatrix m = Matrix(R"(
[sweep]
base = "rigid-rig"
[set]
"joint.type" = "clearance"
[axes]
"rod.rigid_mass" = ["0.5 kg", "0.6 kg"]
[[combinations]]
"joint.clearance" = "0.5 mm"
"drive.speed" = ["100 rpm", "150 rpm"]
[[combinations]]
"joint.clearance" = "1.0 mm"
"drive.speed" = ["100 rpm", "150 rpm"]
)");
  ASSERT_EQ(m.num_runs(), 8u);
  // ids 0-3: 0.5 mm (mass 0.5: 100, 150; mass 0.6: 100, 150); ids 4-7: the same at 1.0 mm.
  const std::vector<int> all = {0, 1, 2, 3, 4, 5, 6, 7};
  EXPECT_EQ(TwinOrder(m, all, 1), (std::vector<int>{0, 4, 1, 5, 2, 6, 3, 7}));
  // Two threads: the two runs computed at once have different twins; each pair within a block.
  EXPECT_EQ(TwinOrder(m, all, 2), (std::vector<int>{0, 1, 4, 5, 2, 3, 6, 7}));
  EXPECT_EQ(TwinOrder(m, all, 3), (std::vector<int>{0, 1, 2, 4, 5, 6, 3, 7}));
  EXPECT_EQ(TwinOrder(m, {1, 5, 6}, 1), (std::vector<int>{1, 5, 6}));
  for (int id : {0, 1, 2, 3}) EXPECT_EQ(TwinKey(m.ConfigFor(id)), TwinKey(m.ConfigFor(id + 4)));
}

TEST(SweepRun, EachDistinctRodIsReducedOnceAndShared) {
  const SweepMatrix m = Matrix(R"(
[sweep]
base = "flexible-rig"
[set]
"rod.elements" = 10
"reduction.modes" = 2
[axes]
"rod.height" = ["12.7 mm", "19.05 mm"]
"drive.speed" = ["100 rpm", "150 rpm", "200 rpm"]
)");
  RodCache cache;
  std::vector<std::shared_ptr<const fem::ReducedRod>> rods(m.num_runs());
  std::vector<std::thread> threads;
  for (std::size_t i = 0; i < m.num_runs(); ++i) {
    threads.emplace_back([&, i] { rods[i] = cache.Get(m.ConfigFor(static_cast<int>(i))); });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(cache.num_built(), 2);
  for (std::size_t i = 0; i < m.num_runs(); ++i) {
    ASSERT_NE(rods[i], nullptr);
    EXPECT_EQ(rods[i].get(), rods[i / 3 * 3].get()) << i;  // same height: the same object
  }
  EXPECT_NE(rods[0].get(), rods[3].get());
  // A rigid rod has no reduced rod.
  EXPECT_EQ(cache.Get(Matrix(kRigidMatrix).ConfigFor(0)), nullptr);
}

TEST(SweepRun, StoreDoesNotDependOnTheNumberOfThreads) {
  const fs::path dir = ScratchDir("sweep_run_threads");
  const SweepMatrix m = Matrix(kRigidMatrix);
  SweepOptions one, two;
  one.jobs = 1;
  two.jobs = 2;
  const auto a = RunSweep(m, (dir / "one.h5").string(), one);
  const auto b = RunSweep(m, (dir / "two.h5").string(), two);
  EXPECT_EQ(a.num_runs, 4);
  EXPECT_EQ(a.num_failed, 0);
  EXPECT_EQ(b.num_failed, 0);
  ExpectSameStores((dir / "one.h5").string(), (dir / "two.h5").string());
  // The parts are gone after assembly (keep_parts = false).
  EXPECT_FALSE(fs::exists(dir / "one.h5.parts"));
  // With ideal joints and a rigid rod at constant speed the slider acceleration is pure
  // kinematics; the capture starts at θ = 0 (index), where |a| = r ω² (1 + r/L) exactly
  // (r = 50 mm, L = 300 mm, no offsets: RIG.md §1). Tolerance: the integrator's 1e-6 and the
  // sampling of the peak, 1e-4 relative.
  const SweepStore s = ReadStore((dir / "one.h5").string());
  for (int id : {0, 2}) {
    const Config cfg = s.runs[id].Input();
    const double omega = cfg.Quantity("drive.speed"), r = 0.05, length = 0.3;
    EXPECT_NEAR(s.runs[id].Summary("peak_negative"), r * omega * omega * (1.0 + r / length),
                1e-4 * r * omega * omega)
        << id;
    EXPECT_GT(s.runs[id].amplitude.size(), 10u);
    EXPECT_EQ(s.runs[id].channels.size(), 2u);
  }
  fs::remove_all(dir);
}

TEST(SweepRun, AFailedRunIsRecordedAndTheSweepGoesOn) {
  const fs::path dir = ScratchDir("sweep_run_failed");
  // A budget of 10 steps does not reach the end of the run: it fails, keeping what it computed.
  const SweepMatrix m = Matrix(R"(
[sweep]
base = "rigid-rig"
[set]
sim.settle = "0.1 s"
sim.capture = "0.2 s"
sim.sample_rate = "10 kHz"
[axes]
"sim.max_steps" = [0, 10, 100000]
)");
  SweepOptions options;
  options.jobs = 2;
  int failures_seen = 0;
  options.on_event = [&](const SweepEvent& e) {
    if (e.kind == SweepEvent::Kind::kRunDone && !e.ok) ++failures_seen;
  };
  const auto outcome = RunSweep(m, (dir / "f.h5").string(), options);
  EXPECT_EQ(outcome.num_runs, 3);
  EXPECT_EQ(outcome.num_failed, 1);
  EXPECT_EQ(failures_seen, 1);
  const SweepStore s = ReadStore((dir / "f.h5").string());
  EXPECT_EQ(s.num_failed, 1);
  EXPECT_TRUE(s.runs[0].ok());
  EXPECT_FALSE(s.runs[1].ok());
  EXPECT_FALSE(s.runs[1].message.empty());
  EXPECT_TRUE(s.runs[2].ok());
  fs::remove_all(dir);
}

TEST(SweepRun, ResumedSweepSkipsFinishedRunsAndEndsWithTheSameStore) {
  const fs::path dir = ScratchDir("sweep_run_resume");
  const SweepMatrix m = Matrix(kRigidMatrix);
  const std::string store = (dir / "r.h5").string();
  struct stat before {};
  {
    // An interrupted sweep: runs 0 and 2 finished, then the process died (the session ends
    // without assembling; nothing else was written).
    RodCache rods;
    SweepSession session(m, store);
    ASSERT_EQ(session.pending().size(), 4u);
    session.Save(ComputeSweepRun(m, 0, &rods, nullptr));
    session.Save(ComputeSweepRun(m, 2, &rods, nullptr));
    std::ofstream(session.PartPath(3) + ".tmp") << "half-written";  // a kill during a write
    ASSERT_EQ(stat(session.PartPath(0).c_str(), &before), 0);
  }
  SweepOptions options;
  options.jobs = 2;
  options.keep_parts = true;
  SweepEvent start;
  int computed = 0;
  std::vector<int> computed_ids;
  options.on_event = [&](const SweepEvent& e) {
    if (e.kind == SweepEvent::Kind::kStart) start = e;
    if (e.kind == SweepEvent::Kind::kRunDone) {
      ++computed;
      computed_ids.push_back(e.id);
    }
  };
  RunSweep(m, store, options);
  EXPECT_EQ(start.already_done, 2);
  EXPECT_EQ(start.to_run, 2);
  EXPECT_EQ(computed, 2);
  std::sort(computed_ids.begin(), computed_ids.end());
  EXPECT_EQ(computed_ids, (std::vector<int>{1, 3}));
  // The finished part was not rewritten: same inode, same modification time.
  const std::string part0 = store + ".parts/" + RunFingerprint(m.ConfigFor(0), m.store) + ".h5";
  struct stat after {};
  ASSERT_EQ(stat(part0.c_str(), &after), 0);
  EXPECT_EQ(before.st_ino, after.st_ino);
  EXPECT_EQ(before.st_mtim.tv_sec, after.st_mtim.tv_sec);
  EXPECT_EQ(before.st_mtim.tv_nsec, after.st_mtim.tv_nsec);
  EXPECT_FALSE(fs::exists(part0 + ".tmp"));
  // Identical to an uninterrupted sweep.
  SweepOptions plain;
  RunSweep(m, (dir / "plain.h5").string(), plain);
  ExpectSameStores(store, (dir / "plain.h5").string());
  // Run again with the store complete and the parts removed: nothing is recomputed.
  fs::remove_all(store + ".parts");
  computed = 0;
  RunSweep(m, store, options);
  EXPECT_EQ(start.already_done, 4);
  EXPECT_EQ(computed, 0);
  ExpectSameStores(store, (dir / "plain.h5").string());
  fs::remove_all(dir);
}

TEST(SweepRun, ASecondSweepOnTheSameStoreIsRefused) {
  const fs::path dir = ScratchDir("sweep_run_lock");
  const SweepMatrix m = Matrix(kRigidMatrix);
  SweepSession first(m, (dir / "x.h5").string());
  try {
    SweepSession second(m, (dir / "x.h5").string());
    ADD_FAILURE() << "second session opened";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "--out");
    EXPECT_NE(e.rule().find("another flexrod sweep"), std::string::npos);
  }
  fs::remove_all(dir);
}

TEST(SweepRun, AFileThatIsNotAStoreIsNeverOverwritten) {
  const fs::path dir = ScratchDir("sweep_run_notastore");
  std::ofstream(dir / "notes.h5") << "my notes";
  try {
    SweepSession session(Matrix(kRigidMatrix), (dir / "notes.h5").string());
    ADD_FAILURE() << "session opened";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "--out");
  }
  EXPECT_FALSE(fs::exists(dir / "notes.h5.parts"));
  fs::remove_all(dir);
}

TEST(SweepRun, UnknownStoreChannelIsRefusedBeforeAnythingIsWritten) {
  const fs::path dir = ScratchDir("sweep_run_badchannel");
  const SweepMatrix m = Matrix(kRigidMatrix, {"store.channels=crank_angle,slider_jerk"});
  try {
    RunSweep(m, (dir / "b.h5").string(), SweepOptions{});
    ADD_FAILURE() << "no InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "store.channels");
    EXPECT_EQ(e.value(), "slider_jerk");
    EXPECT_NE(e.rule().find("slider_acceleration"), std::string::npos);  // lists what exists
  }
  EXPECT_TRUE(fs::is_empty(dir));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace flexrod::study
