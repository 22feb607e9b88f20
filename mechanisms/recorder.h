// mechanisms/recorder.h — the channel recorder a run fills in its capture window, with each
// channel's running statistics. Mechanism recipes (mechanisms/mechanism_recipe.h) add their
// channels to it; run/run.cc records and finishes it. SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <algorithm>
#include <functional>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"
#include "multibody/simulate.h"
#include "signals/timeseries.h"

namespace flexrod {

/// Extremes and sum of squares of one channel's samples, gathered as they are recorded (the
/// summary then needs no second pass over a record of tens of MB).
struct ChannelStats {
  double min{std::numeric_limits<double>::infinity()};     ///< [channel unit]
  double max{-std::numeric_limits<double>::infinity()};    ///< [channel unit]
  double sum_squares{0.0};                                 ///< Σ x² [channel unit²]
  double peak_abs() const { return std::max(max, -min); }  ///< max |x| [channel unit]
};

/// Channel recorder, filled in the capture window. Channels come in groups: a group's function
/// writes the values of all its channels for one sample, so what they share (a joint reaction,
/// the contact response, the energies) is computed once, with one call per group.
///
/// Samples are gathered row by row in a small block and moved into their channels a block at a
/// time, with each channel's running statistics: writing every channel's vector and statistics
/// once per sample cost about 650 instructions a sample on the rigid rig (each push_back's
/// reallocation path forces the loop to reload everything), the block move about 300.
class Recorder {
 public:
  struct Spec {
    std::string name;
    std::string unit;
  };
  using Fn = std::function<void(const multibody::SampleView&, double* values)>;
  void Add(std::vector<Spec> channels, Fn fn) {
    FLEXROD_ASSERT(size_ == 0);
    groups_.push_back({names_.size(), std::move(fn)});
    for (Spec& c : channels) {
      names_.push_back(std::move(c.name));
      units_.push_back(std::move(c.unit));
    }
    values_.resize(names_.size());
    stats_.resize(names_.size());
    kept_.resize(names_.size(), true);
    block_.resize(kBlockRows * names_.size());
  }
  /// Keeps the samples of the channels `keep` accepts only; the others still get their
  /// statistics (stats()) but no record (Finish leaves them out). The first channel is kept if
  /// `keep` accepts none: a TimeSeries counts its samples by its channels. Before the first
  /// sample.
  void KeepOnly(const std::function<bool(const std::string&)>& keep) {
    FLEXROD_ASSERT(size_ == 0);
    for (size_t c = 0; c < names_.size(); ++c) kept_[c] = keep(names_[c]);
    if (!kept_.empty() && std::find(kept_.begin(), kept_.end(), true) == kept_.end())
      kept_[0] = true;
  }
  void Record(const multibody::SampleView& s) {
    if (size_ == 0) first_t_ = s.t();
    double* row = block_.data() + filled_ * names_.size();
    for (const Group& g : groups_) g.fn(s, row + g.first);
    ++size_;
    if (++filled_ == kBlockRows) Flush();
  }
  size_t size() const { return size_; }
  /// Every channel, kept or not (and stats() in this order).
  const std::vector<std::string>& names() const { return names_; }
  const std::vector<std::string>& units() const { return units_; }
  /// Per channel, kept or not, in the order of names(); complete once Finish has been called.
  const std::vector<ChannelStats>& stats() const { return stats_; }
  void Reserve(size_t n) {
    for (size_t c = 0; c < values_.size(); ++c) {
      if (kept_[c]) values_[c].reserve(n);
    }
  }
  study::TimeSeries Finish(double rate) {
    Flush();
    study::TimeSeries ts(rate, size_ ? first_t_ : 0.0);
    for (size_t i = 0; i < names_.size(); ++i) {
      if (kept_[i]) ts.AddChannel(names_[i], units_[i], std::move(values_[i]));
    }
    return ts;
  }

 private:
  static constexpr size_t kBlockRows = 256;  // 256 samples × ~20 channels: 40 kB, in L2
  struct Group {
    size_t first;  // index of its first channel
    Fn fn;
  };
  // Moves the block's rows into the channels, channel by channel, updating their statistics.
  void Flush() {
    const size_t nc = names_.size(), rows = filled_;
    for (size_t c = 0; c < nc; ++c) {
      const double* __restrict src = block_.data() + c;
      ChannelStats st = stats_[c];
      for (size_t r = 0; r < rows; ++r) {
        const double v = src[r * nc];
        st.min = std::min(st.min, v);
        st.max = std::max(st.max, v);
        st.sum_squares += v * v;
      }
      stats_[c] = st;
      if (!kept_[c]) continue;
      std::vector<double>& col = values_[c];
      const size_t old = col.size();
      col.resize(old + rows);
      double* __restrict dst = col.data() + old;
      for (size_t r = 0; r < rows; ++r) dst[r] = src[r * nc];
    }
    filled_ = 0;
  }
  std::vector<std::string> names_, units_;
  std::vector<Group> groups_;
  std::vector<std::vector<double>> values_;
  std::vector<ChannelStats> stats_;
  std::vector<bool> kept_;     // per channel: its samples are recorded (KeepOnly)
  std::vector<double> block_;  // kBlockRows samples of every channel, row by row
  size_t filled_{0};           // rows of block_ not yet in values_
  size_t size_{0};
  double first_t_{0.0};
};

}  // namespace flexrod
