// tests/run/twin_cache_test.cc — sharing computed values between runs: OnceCache (one
// computation per key, also under concurrent requests; eviction; failures rethrown) and the
// ideal-joint twins of clearance runs (TwinCache). The twin's key leaves out the joint.* keys;
// the test proves that is safe by computing the twin afresh for runs that differ in every kind
// of joint key and comparing the channels bit for bit, and proves reuse changes nothing by
// comparing the load amplification of a run with a reused twin to one with its own.
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <atomic>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "common/once_cache.h"
#include "input/presets.h"
#include "run/run.h"

namespace flexrod {
namespace {

TEST(OnceCache, ComputesEachKeyOnceAndSharesIt) {
  OnceCache<int> cache;
  int calls = 0;
  EXPECT_EQ(cache.Get("a", [&] { return ++calls * 10; }), 10);
  EXPECT_EQ(cache.Get("a", [&] { return ++calls * 10; }), 10);
  EXPECT_EQ(cache.Get("b", [&] { return ++calls * 10; }), 20);
  EXPECT_EQ(calls, 2);
  EXPECT_EQ(cache.num_computed(), 2u);
}

TEST(OnceCache, ConcurrentRequestsForOneKeyComputeOnce) {
  OnceCache<int> cache;
  std::atomic<int> calls{0};
  std::vector<std::thread> threads;
  std::vector<int> got(8, 0);
  for (int i = 0; i < 8; ++i) {
    threads.emplace_back([&, i] {
      got[i] = cache.Get("k", [&] {
        std::this_thread::sleep_for(std::chrono::milliseconds(20));  // others arrive meanwhile
        return ++calls;
      });
    });
  }
  for (std::thread& t : threads) t.join();
  EXPECT_EQ(calls.load(), 1);
  for (int v : got) EXPECT_EQ(v, 1);
}

TEST(OnceCache, KeepsTheMostRecentlyUsedKeysUpToItsCapacity) {
  OnceCache<int> cache(2);
  int calls = 0;
  auto f = [&] { return ++calls; };
  cache.Get("a", f);
  cache.Get("b", f);
  cache.Get("a", f);  // a is now more recent than b
  cache.Get("c", f);  // evicts b
  EXPECT_EQ(calls, 3);
  cache.Get("a", f);
  EXPECT_EQ(calls, 3);
  cache.Get("b", f);  // computed again
  EXPECT_EQ(calls, 4);
}

TEST(OnceCache, RethrowsAFailedComputationToEveryCaller) {
  OnceCache<int> cache;
  int calls = 0;
  auto fail = [&]() -> int {
    ++calls;
    throw std::runtime_error("no");
  };
  EXPECT_THROW(cache.Get("x", fail), std::runtime_error);
  EXPECT_THROW(cache.Get("x", fail), std::runtime_error);
  EXPECT_EQ(calls, 1);
}

// A preset with a clearance joint, 0.1 s capture at 20 kHz from rest: short, with impacts.
Config Clearance(const char* preset = "rigid-rig") {
  Config cfg;
  cfg.LoadToml(FindPreset(preset)->toml, preset);
  cfg.Set("joint.type", "clearance");
  cfg.Set("sim.settle", "0 s");
  cfg.Set("sim.capture", "0.1 s");
  cfg.Set("sim.sample_rate", "20 kHz");
  return cfg;
}

void ExpectSameChannels(const study::TimeSeries& a, const study::TimeSeries& b) {
  ASSERT_EQ(a.num_channels(), b.num_channels());
  ASSERT_EQ(a.num_samples(), b.num_samples());
  EXPECT_EQ(a.start_time(), b.start_time());
  for (std::size_t c = 0; c < a.channels().size(); ++c) {
    EXPECT_EQ(a.channels()[c].name, b.channels()[c].name);
    EXPECT_EQ(a.channels()[c].values, b.channels()[c].values)
        << a.channels()[c].name;  // bit for bit
  }
}

class TwinKeyTest : public testing::TestWithParam<const char*> {};

TEST_P(TwinKeyTest, TheTwinDoesNotDependOnAnyJointKey) {
  const Config base = Clearance(GetParam());
  const RunResult ref = RunSimulation(base);
  ASSERT_TRUE(ref.ok()) << ref.status.Summary();
  ASSERT_NE(ref.ideal, nullptr);
  // Each kind of joint key: geometry, law and its parameters, friction, materials.
  const std::vector<std::vector<std::string>> variants = {
      {"joint.clearance=0.5 mm", "joint.bush_radius=12 mm", "joint.length=20 mm"},
      {"joint.law=flores", "joint.restitution=0.5", "joint.friction_law=none"},
      {"joint.law=kelvin-voigt", "joint.damping=50 N s/m", "joint.effective_mass=2 kg"},
      {"joint.pin_material=brass", "joint.bush_material=aluminium", "joint.friction=0.4"},
  };
  for (const auto& sets : variants) {
    Config cfg = base;
    for (const std::string& s : sets) cfg.SetAssignment(s);
    EXPECT_EQ(TwinKey(cfg), TwinKey(base)) << sets[0];
    const RunResult r = RunSimulation(cfg);
    ASSERT_TRUE(r.ok()) << sets[0] << ": " << r.status.Summary();
    ASSERT_NE(r.ideal, nullptr);
    ExpectSameChannels(*r.ideal, *ref.ideal);
  }
  Config faster = base;
  faster.Set("drive.speed", "101 rpm");
  EXPECT_NE(TwinKey(faster), TwinKey(base));
}

INSTANTIATE_TEST_SUITE_P(Rigs, TwinKeyTest, testing::Values("rigid-rig", "flexible-rig"),
                         [](const testing::TestParamInfo<const char*>& p) {
                           return std::string(p.param) == "rigid-rig" ? "Rigid" : "Flexible";
                         });

TEST(TwinCache, AReusedTwinGivesTheSameAmplificationAsAFreshOne) {
  Config a = Clearance(), b = Clearance();
  b.Set("joint.clearance", "0.5 mm");
  TwinCache twins;
  RunOutputOptions shared;
  shared.twins = &twins;
  const RunResult ra = RunSimulation(a, nullptr, false, shared);
  const RunResult rb = RunSimulation(b, nullptr, false, shared);
  const RunResult fresh = RunSimulation(b);
  ASSERT_TRUE(ra.ok() && rb.ok() && fresh.ok());
  EXPECT_EQ(twins.num_computed(), 1);
  EXPECT_FALSE(ra.summary["ideal"]["reused"].get<bool>());
  EXPECT_TRUE(rb.summary["ideal"]["reused"].get<bool>());
  EXPECT_FALSE(fresh.summary["ideal"]["reused"].get<bool>());
  EXPECT_EQ(rb.ideal, ra.ideal);  // the same record, not a copy
  ExpectSameChannels(*rb.ideal, *fresh.ideal);
  EXPECT_EQ(rb.summary["load_amplification"], fresh.summary["load_amplification"]);
  EXPECT_GT(rb.summary["load_amplification"]["slider_acceleration_positive"].get<double>(), 1.0);
}

}  // namespace
}  // namespace flexrod
