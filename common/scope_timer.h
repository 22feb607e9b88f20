// common/scope_timer.h — opt-in wall-time accounting of a scope.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <chrono>

namespace flexrod {

/// Adds the wall time of its scope to *seconds [s]; does nothing (reads no clock) when seconds
/// is null. Timing is opt-in: two clock reads per call cost a few percent of a run whose
/// callbacks take microseconds.
class ScopeTimer {
 public:
  explicit ScopeTimer(double* seconds) : seconds_(seconds) {
    if (seconds_) start_ = std::chrono::steady_clock::now();
  }
  ~ScopeTimer() {
    if (seconds_)
      *seconds_ += std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  }
  ScopeTimer(const ScopeTimer&) = delete;
  ScopeTimer& operator=(const ScopeTimer&) = delete;

 private:
  double* seconds_;
  std::chrono::steady_clock::time_point start_;
};

}  // namespace flexrod
