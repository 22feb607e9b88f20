// Tests of signals/timeseries.h: channel bookkeeping, errors naming the offending key, and the
// CSV round trip (bit-identical values, units in the header, atomic write).
// SPDX-License-Identifier: GPL-3.0-or-later
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "common/error.h"
#include "signals/timeseries.h"
#include "tests/test_util.h"

namespace flexrod::study {
namespace {

namespace fs = std::filesystem;

/// A file in this test process's scratch directory.
fs::path TempPath(const std::string& name) {
  static const fs::path dir = flexrod::test::ScratchDir("signals_timeseries");
  return dir / name;
}

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

std::string FirstLine(const fs::path& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  return line;
}

bool BitIdentical(double a, double b) { return std::memcmp(&a, &b, sizeof(double)) == 0; }

TEST(TimeSeries, SampleTimeIsStartPlusIndexOverRate) {
  TimeSeries ts(100000.0, 2.5);
  ts.AddChannel("x", "m", std::vector<double>(7, 0.0));
  EXPECT_EQ(ts.num_samples(), 7u);
  EXPECT_DOUBLE_EQ(ts.time(0), 2.5);
  EXPECT_DOUBLE_EQ(ts.time(300000), 2.5 + 3.0);
  EXPECT_DOUBLE_EQ(ts.sample_period(), 1e-5);
}

TEST(TimeSeries, UnknownChannelThrowsInputErrorNamingIt) {
  TimeSeries ts(1000.0, 0.0);
  ts.AddChannel("slider_acceleration", "m/s^2", {1.0, 2.0});
  try {
    ts.values("slider_accel");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), "channel");
    EXPECT_EQ(e.value(), "slider_accel");
    EXPECT_NE(std::string(e.what()).find("slider_acceleration"), std::string::npos)
        << "the message should list the available channels: " << e.what();
  }
}

TEST(TimeSeries, ChannelsMustHaveOneLengthAndDistinctValidNames) {
  TimeSeries ts(1000.0, 0.0);
  ts.AddChannel("a", "m", {1.0, 2.0, 3.0});
  EXPECT_THROW(ts.AddChannel("b", "m", {1.0, 2.0}), InputError);          // length
  EXPECT_THROW(ts.AddChannel("a", "m", {1.0, 2.0, 3.0}), InputError);     // duplicate
  EXPECT_THROW(ts.AddChannel("time", "s", {1.0, 2.0, 3.0}), InputError);  // reserved
  EXPECT_THROW(ts.AddChannel("c,d", "m", {1.0, 2.0, 3.0}), InputError);   // breaks the CSV
  EXPECT_THROW(ts.AddChannel("e [m]", "m", {1.0, 2.0, 3.0}), InputError);
  EXPECT_THROW(ts.AddChannel("f", "m]", {1.0, 2.0, 3.0}), InputError);
  EXPECT_THROW(TimeSeries(0.0, 0.0), InputError);
  EXPECT_THROW(TimeSeries(-5.0, 0.0), InputError);
  ts.AddChannel("zeros", "N");
  EXPECT_EQ(ts.values("zeros").size(), 3u);
  ts.mutable_values("zeros")[1] = 4.0;
  EXPECT_EQ(ts.values("zeros")[1], 4.0);
  EXPECT_EQ(ts.num_channels(), 2u);
}

TEST(TimeSeries, SliceKeepsValuesAndShiftsStartTime) {
  TimeSeries ts(10.0, 1.0);
  ts.AddChannel("x", "m", {0.0, 1.0, 2.0, 3.0, 4.0});
  const TimeSeries s = ts.Slice({2, 4});
  EXPECT_EQ(s.num_samples(), 2u);
  EXPECT_DOUBLE_EQ(s.start_time(), 1.2);
  EXPECT_EQ(s.values("x")[0], 2.0);
  EXPECT_EQ(s.values("x")[1], 3.0);
  EXPECT_THROW(ts.Slice({3, 6}), InputError);
  EXPECT_THROW(ts.Slice({3, 3}), InputError);
}

TEST(TimeSeriesCsv, RoundTripIsBitIdenticalAndKeepsUnits) {
  const double pi = std::numbers::pi;
  TimeSeries ts(100000.0, 0.125);
  ts.AddChannel("slider_acceleration", "m/s^2",
                {pi, -1.0 / 3.0, 1e-300, 6.02214076e23, -0.0,
                 std::numeric_limits<double>::denorm_min(), 123456789.0});
  ts.AddChannel("crank_angle", "rad", {0.0, 0.1, 0.2, 0.3, 0.4, 0.5, 0.6});
  const fs::path path = TempPath("roundtrip.csv");
  WriteCsv(ts, path);
  EXPECT_EQ(FirstLine(path), "time [s],slider_acceleration [m/s^2],crank_angle [rad]");
  EXPECT_FALSE(fs::exists(path.string() + ".tmp")) << "the temporary file must be renamed";

  const TimeSeries back = ReadCsv(path);
  ASSERT_EQ(back.num_channels(), 2u);
  ASSERT_EQ(back.num_samples(), 7u);
  // Rate recovered from the time column: exact to round-off of (n-1)/(t_last - t_first).
  EXPECT_NEAR(back.sample_rate(), 100000.0, 1e-12 * 100000.0);
  EXPECT_EQ(back.start_time(), 0.125);
  for (std::size_t c = 0; c < 2; ++c) {
    EXPECT_EQ(back.channels()[c].name, ts.channels()[c].name);
    EXPECT_EQ(back.channels()[c].unit, ts.channels()[c].unit);
    for (std::size_t i = 0; i < 7; ++i) {
      EXPECT_TRUE(BitIdentical(back.channels()[c].values[i], ts.channels()[c].values[i]))
          << "channel " << c << " sample " << i;
    }
  }
}

TEST(TimeSeriesCsv, LargeRecordRoundTripRecoversRate) {
  // 3 s at the rig's 100 kHz, started after 1.7 s of settling: the rate must survive the
  // print/parse of 300000 times.
  TimeSeries ts(100000.0, 1.7);
  std::vector<double> x(300000);
  for (std::size_t i = 0; i < x.size(); ++i) x[i] = std::sin(0.001 * static_cast<double>(i));
  ts.AddChannel("x", "m", x);
  const fs::path path = TempPath("large.csv");
  WriteCsv(ts, path);
  const TimeSeries back = ReadCsv(path);
  EXPECT_NEAR(back.sample_rate(), 100000.0, 1e-9);
  EXPECT_EQ(back.values("x")[299999], x[299999]);
  EXPECT_NEAR(back.time(299999), ts.time(299999), 1e-12);
}

TEST(TimeSeriesCsv, ReaderRejectsMalformedFilesNamingFileAndLine) {
  const fs::path path = TempPath("bad.csv");
  WriteText(path, "time [s],x [m]\n0,1\n0.1,2\n0.25,3\n");  // non-uniform time
  EXPECT_THROW(ReadCsv(path), InputError);

  WriteText(path, "time [s],x\n0,1\n0.1,2\n");  // header without unit
  try {
    ReadCsv(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), path.string() + ":1");
    EXPECT_EQ(e.value(), "x");
  }

  WriteText(path, "time [s],x [m]\n0,1\n0.1,abc\n");  // not a number, line 3
  try {
    ReadCsv(path);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.key(), path.string() + ":3");
    EXPECT_EQ(e.value(), "abc");
  }

  WriteText(path, "t [s],x [m]\n0,1\n0.1,2\n");  // first column is not time
  EXPECT_THROW(ReadCsv(path), InputError);
  WriteText(path, "time [s],x [m]\n0,1\n0.1\n");  // short row
  EXPECT_THROW(ReadCsv(path), InputError);
  EXPECT_THROW(ReadCsv(TempPath("does_not_exist.csv")), InputError);
}

TEST(TimeSeriesCsv, ReaderAcceptsCrlfAndBlankLines) {
  const fs::path path = TempPath("crlf.csv");
  WriteText(path, "time [s], x [m] ,y [N]\r\n0,1,2\r\n\r\n0.5,3,4\r\n1.0,+5,6e0\r\n");
  const TimeSeries ts = ReadCsv(path);
  EXPECT_DOUBLE_EQ(ts.sample_rate(), 2.0);
  EXPECT_EQ(ts.channel("x").unit, "m");
  EXPECT_EQ(ts.values("x")[2], 5.0);
  EXPECT_EQ(ts.values("y")[2], 6.0);
}

}  // namespace
}  // namespace flexrod::study
