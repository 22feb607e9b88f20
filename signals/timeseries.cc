// SPDX-License-Identifier: GPL-3.0-or-later
#include "signals/timeseries.h"

#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <sstream>
#include <system_error>
#include <utility>

#include "common/error.h"
#include "common/files.h"

namespace flexrod::study {
namespace {

constexpr std::string_view kTimeHeader = "time [s]";
constexpr std::string_view kForbidden = ",[]\"\n\r";
// A foreign CSV may print times with fewer digits: accept this fraction of a sample period.
constexpr double kTimeTolerance = 1e-3;

void ValidateName(const std::string& name) {
  if (name.empty()) throw InputError("channel", "\"\"", "channel name must not be empty");
  if (name.find_first_of(kForbidden) != std::string::npos) {
    throw InputError("channel", name, "channel name must not contain , [ ] \" or a newline");
  }
  if (name.front() == ' ' || name.back() == ' ') {
    throw InputError("channel", name, "channel name must not start or end with a space");
  }
  if (name == "time") {
    throw InputError("channel", name, "\"time\" is reserved for the record's time column");
  }
}

void ValidateUnit(const std::string& name, const std::string& unit) {
  if (unit.find_first_of(kForbidden) != std::string::npos) {
    throw InputError("channel " + name + " unit", unit,
                     "unit must not contain , [ ] \" or a newline");
  }
}

void AppendNumber(double v, std::string* out) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof(buf), v);  // shortest round-trip form
  FLEXROD_ASSERT(ec == std::errc());
  out->append(buf, end);
}

std::string_view Trim(std::string_view s) {
  while (!s.empty() && (s.front() == ' ' || s.front() == '\t')) s.remove_prefix(1);
  while (!s.empty() && (s.back() == ' ' || s.back() == '\t' || s.back() == '\r')) {
    s.remove_suffix(1);
  }
  return s;
}

// Splits one CSV line at commas (no quoting: names and numbers never contain commas).
void SplitCells(std::string_view line, std::vector<std::string_view>* cells) {
  cells->clear();
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = line.find(',', start);
    if (comma == std::string_view::npos) {
      cells->push_back(Trim(line.substr(start)));
      return;
    }
    cells->push_back(Trim(line.substr(start, comma - start)));
    start = comma + 1;
  }
}

double ParseNumber(std::string_view cell, const std::string& where) {
  double v = 0.0;
  const char* first = cell.data();
  const char* last = cell.data() + cell.size();
  if (!cell.empty() && *first == '+') ++first;  // from_chars rejects a leading '+'
  const auto [ptr, ec] = std::from_chars(first, last, v);
  if (ec != std::errc() || ptr != last || cell.empty()) {
    throw InputError(where, std::string(cell), "not a number");
  }
  return v;
}

// "name [unit]" → (name, unit).
std::pair<std::string, std::string> ParseHeaderCell(std::string_view cell,
                                                    const std::string& where) {
  const std::size_t open = cell.find('[');
  if (cell.empty() || cell.back() != ']' || open == std::string_view::npos || open == 0) {
    throw InputError(where, std::string(cell), "header cell must read \"name [unit]\"");
  }
  std::string name(Trim(cell.substr(0, open)));
  std::string unit(Trim(cell.substr(open + 1, cell.size() - open - 2)));
  return {std::move(name), std::move(unit)};
}

}  // namespace

TimeSeries::TimeSeries(double sample_rate, double start_time)
    : sample_rate_(sample_rate), start_time_(start_time) {
  Require(std::isfinite(sample_rate) && sample_rate > 0.0, "sample_rate", sample_rate,
          "must be finite and > 0 [Hz]");
  Require(std::isfinite(start_time), "start_time", start_time, "must be finite [s]");
}

void TimeSeries::AddChannel(std::string name, std::string unit, std::vector<double> values) {
  ValidateName(name);
  ValidateUnit(name, unit);
  if (HasChannel(name)) throw InputError("channel", name, "a channel of that name exists");
  if (!channels_.empty() && values.size() != num_samples_) {
    throw InputError("channel " + name + " length", std::to_string(values.size()),
                     "must equal the record's " + std::to_string(num_samples_) + " samples");
  }
  if (channels_.empty()) num_samples_ = values.size();
  channels_.push_back(Channel{std::move(name), std::move(unit), std::move(values)});
}

void TimeSeries::AddChannel(std::string name, std::string unit) {
  AddChannel(std::move(name), std::move(unit), std::vector<double>(num_samples_, 0.0));
}

std::size_t TimeSeries::IndexOf(std::string_view name) const {
  for (std::size_t c = 0; c < channels_.size(); ++c) {
    if (channels_[c].name == name) return c;
  }
  return channels_.size();
}

bool TimeSeries::HasChannel(std::string_view name) const {
  return IndexOf(name) < channels_.size();
}

const Channel& TimeSeries::channel(std::string_view name) const {
  const std::size_t c = IndexOf(name);
  if (c == channels_.size()) {
    std::string available;
    for (const Channel& ch : channels_) available += (available.empty() ? "" : ", ") + ch.name;
    throw InputError("channel", std::string(name),
                     "unknown channel; available: " + (available.empty() ? "none" : available));
  }
  return channels_[c];
}

std::span<double> TimeSeries::mutable_values(std::string_view name) {
  const Channel& ch = channel(name);  // throws on an unknown name
  return channels_[static_cast<std::size_t>(&ch - channels_.data())].values;
}

TimeSeries TimeSeries::Slice(SampleRange range) const {
  ValidateRange("slice", range, num_samples_);
  TimeSeries out(sample_rate_, time(range.begin));
  for (const Channel& ch : channels_) {
    out.AddChannel(ch.name, ch.unit,
                   std::vector<double>(ch.values.begin() + static_cast<std::ptrdiff_t>(range.begin),
                                       ch.values.begin() + static_cast<std::ptrdiff_t>(range.end)));
  }
  return out;
}

void ValidateRange(const std::string& key, SampleRange range, std::size_t num_samples) {
  if (range.empty() || range.end > num_samples) {
    throw InputError(key,
                     "[" + std::to_string(range.begin) + ", " + std::to_string(range.end) + ")",
                     "sample range must be non-empty and inside the record's " +
                         std::to_string(num_samples) + " samples");
  }
}

void WriteCsv(const TimeSeries& series, const std::filesystem::path& path) {
  const std::filesystem::path tmp = path.string() + ".tmp";
  std::FILE* file = std::fopen(tmp.c_str(), "wb");
  if (file == nullptr) throw IoError(std::string(std::strerror(errno)) + ": " + tmp.string());
  std::string row(kTimeHeader);
  for (const Channel& ch : series.channels()) row += "," + ch.name + " [" + ch.unit + "]";
  row += '\n';
  bool ok = std::fwrite(row.data(), 1, row.size(), file) == row.size();
  for (std::size_t i = 0; ok && i < series.num_samples(); ++i) {
    row.clear();  // keeps its capacity: no allocation per row after the first few
    AppendNumber(series.time(i), &row);
    for (const Channel& ch : series.channels()) {
      row += ',';
      AppendNumber(ch.values[i], &row);
    }
    row += '\n';
    ok = std::fwrite(row.data(), 1, row.size(), file) == row.size();
  }
  const int write_errno = errno;
  const bool closed = std::fclose(file) == 0;  // flushes: a full disk may show only here
  if (!ok || !closed) {
    const int e = !ok ? write_errno : errno;
    std::error_code ignored;
    std::filesystem::remove(tmp, ignored);
    throw IoError(std::string(std::strerror(e)) + ": " + path.string());
  }
  CommitFile(tmp.string(), path.string());
}

TimeSeries ReadCsv(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError("csv", path.string(), "cannot open for reading");
  std::ostringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  const std::string file = path.string();

  std::vector<std::string_view> cells;
  std::vector<std::string> names, units;
  std::vector<double> times;
  std::vector<std::vector<double>> columns;
  std::size_t line_number = 0;
  bool have_header = false;
  for (std::size_t start = 0; start < text.size();) {
    std::size_t stop = text.find('\n', start);
    if (stop == std::string::npos) stop = text.size();
    const std::string_view line = Trim(std::string_view(text).substr(start, stop - start));
    start = stop + 1;
    ++line_number;
    if (line.empty()) continue;
    const std::string where = file + ":" + std::to_string(line_number);
    SplitCells(line, &cells);
    if (!have_header) {
      if (cells.front() != kTimeHeader) {
        throw InputError(where, std::string(cells.front()), "first column must be \"time [s]\"");
      }
      for (std::size_t c = 1; c < cells.size(); ++c) {
        auto [name, unit] = ParseHeaderCell(cells[c], where);
        names.push_back(std::move(name));
        units.push_back(std::move(unit));
      }
      columns.resize(names.size());
      have_header = true;
      continue;
    }
    if (cells.size() != names.size() + 1) {
      throw InputError(where, std::to_string(cells.size()) + " cells",
                       "every row needs " + std::to_string(names.size() + 1) + " cells");
    }
    times.push_back(ParseNumber(cells[0], where));
    for (std::size_t c = 0; c < names.size(); ++c) {
      columns[c].push_back(ParseNumber(cells[c + 1], where));
    }
  }
  if (!have_header) throw InputError("csv", file, "empty file: no header");
  if (times.size() < 2) {
    throw InputError("csv", file, "needs at least 2 rows to recover the sample rate");
  }
  const std::size_t n = times.size();
  const double span = times.back() - times.front();
  if (!(span > 0.0) || !std::isfinite(span)) {
    throw InputError(file + ": time", FormatValue(span), "times must increase");
  }
  const double rate = static_cast<double>(n - 1) / span;
  TimeSeries series(rate, times.front());
  for (std::size_t i = 0; i < n; ++i) {
    if (std::abs(times[i] - series.time(i)) > kTimeTolerance / rate) {
      throw InputError(
          file + ": time of data row " + std::to_string(i + 1), FormatValue(times[i]),
          "times must be uniformly spaced (expected " + FormatValue(series.time(i)) + ")");
    }
  }
  for (std::size_t c = 0; c < names.size(); ++c) {
    series.AddChannel(std::move(names[c]), std::move(units[c]), std::move(columns[c]));
  }
  return series;
}

}  // namespace flexrod::study
