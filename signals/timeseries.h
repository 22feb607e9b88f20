// signals/timeseries.h — a uniformly sampled record with named, unit-carrying channels
// (TimeSeries), half-open sample ranges (SampleRange), and the CSV form of a record
// (header "time [s],name [unit],...", written atomically through FILE.tmp + rename).
// What does not live here: any analysis of the samples (signals/signals.h,
// signals/signals_spectrum.h) and anything that knows about the solver — a TimeSeries is filled
// by whoever samples the integrator, and read by the signal analysis.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <filesystem>
#include <span>
#include <string>
#include <string_view>
#include <vector>

namespace flexrod::study {

/// Half-open range of sample indices [begin, end).
struct SampleRange {
  std::size_t begin{0};
  std::size_t end{0};
  std::size_t size() const { return end > begin ? end - begin : 0; }
  bool empty() const { return end <= begin; }
  bool operator==(const SampleRange&) const = default;
};

/// One named channel of a record.
struct Channel {
  std::string name;            ///< e.g. "slider_acceleration"; no ',', '[', ']', '"', newline
  std::string unit;            ///< e.g. "m/s^2"; SI by convention; no ',', '[', ']', '"', newline
  std::vector<double> values;  ///< one value per sample [unit]
};

/// A record sampled at a uniform rate: sample i is taken at time start_time + i / sample_rate.
/// All channels have the same number of samples (fixed by the first channel added).
/// Lookup by name is a linear scan: records carry tens of channels, not thousands.
class TimeSeries {
 public:
  /// Throws InputError unless sample_rate > 0 and start_time is finite.
  TimeSeries(double sample_rate, double start_time);

  double sample_rate() const { return sample_rate_; }          ///< [Hz]
  double start_time() const { return start_time_; }            ///< time of sample 0 [s]
  double sample_period() const { return 1.0 / sample_rate_; }  ///< [s]
  std::size_t num_samples() const { return num_samples_; }     ///< 0 until a channel is added
  std::size_t num_channels() const { return channels_.size(); }
  /// Time of sample i [s] (i may equal or exceed num_samples()).
  double time(std::size_t i) const { return start_time_ + static_cast<double>(i) / sample_rate_; }
  /// The whole record as a range.
  SampleRange all() const { return {0, num_samples_}; }

  /// Adds a channel. Throws InputError if the name or unit is invalid (see Channel), the name
  /// is "time" or already present, or values.size() differs from num_samples() (when this is
  /// not the first channel).
  void AddChannel(std::string name, std::string unit, std::vector<double> values);
  /// Adds a zero-filled channel of num_samples() samples, to be filled via mutable_values().
  void AddChannel(std::string name, std::string unit);

  bool HasChannel(std::string_view name) const;
  /// Throws InputError("channel", name, "unknown channel; available: ...") if absent.
  const Channel& channel(std::string_view name) const;
  std::span<const double> values(std::string_view name) const { return channel(name).values; }
  /// Writable view of a channel's samples (fixed length: the record's shape cannot change).
  std::span<double> mutable_values(std::string_view name);
  const std::vector<Channel>& channels() const { return channels_; }

  /// Copy of the samples in `range` (start time shifted to the range's first sample).
  /// Throws InputError if the range does not lie inside the record.
  TimeSeries Slice(SampleRange range) const;

 private:
  std::size_t IndexOf(std::string_view name) const;  // num_channels() if absent

  double sample_rate_;
  double start_time_;
  std::size_t num_samples_{0};
  std::vector<Channel> channels_;
};

/// Throws InputError("<key>", "[begin, end)", ...) unless range lies inside [0, num_samples)
/// and is not empty.
void ValidateRange(const std::string& key, SampleRange range, std::size_t num_samples);

/// Writes the record as CSV: a header "time [s],<name> [<unit>],..." then one row per sample,
/// numbers in the shortest form that reads back bit-identically. Writes path + ".tmp" and
/// renames it over `path`, so readers never see a half-written file. Throws IoError naming
/// the file and the system's reason if it cannot be written.
void WriteCsv(const TimeSeries& series, const std::filesystem::path& path);

/// Reads a CSV written by WriteCsv (or any CSV of that shape). The first column must be
/// "time [s]" with uniformly spaced times (within 1e-3 of a sample period); the sample rate is
/// recovered as (n − 1) / (t_last − t_first), exact to round-off, so at least 2 rows are
/// needed. Every other header cell must read "name [unit]". Blank lines are skipped; CRLF is
/// accepted. Throws InputError("<path>:<line>", cell, rule) on the first malformed item.
TimeSeries ReadCsv(const std::filesystem::path& path);

}  // namespace flexrod::study
