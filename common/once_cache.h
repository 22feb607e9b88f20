// common/once_cache.h — values computed once per key and shared between callers (threads of
// a sweep, runs of a study): the reduced rods of a sweep (sweep/sweep.h) and the ideal-joint
// twins of clearance runs (run/run.h). What does not live here: what a key means.
// SPDX-License-Identifier: GPL-3.0-or-later
#pragma once

#include <cstddef>
#include <exception>
#include <future>
#include <map>
#include <mutex>
#include <string>
#include <utility>

namespace flexrod {

/// The first caller of a key computes its value (outside the lock, so other keys are computed
/// meanwhile), callers asking for the key meanwhile wait for it, later callers share it. A
/// computation that throws rethrows its exception to every caller of that key. With a
/// capacity, only the `capacity` most recently requested keys are kept (an evicted value lives
/// on in the callers that hold it; asking for its key again computes it again). Thread-safe.
template <typename T>
class OnceCache {
 public:
  /// capacity: keys kept, 0 = all.
  explicit OnceCache(std::size_t capacity = 0) : capacity_(capacity) {}

  /// The value of `key`, from compute() (a callable returning T) if no caller asked before.
  template <typename Compute>
  T Get(const std::string& key, Compute&& compute) {
    std::promise<T> promise;
    std::shared_future<T> future;
    bool mine = false;
    {
      std::lock_guard<std::mutex> lock(mutex_);
      auto it = entries_.find(key);
      if (it == entries_.end()) {
        future = promise.get_future().share();
        it = entries_.emplace(key, Entry{future, 0}).first;
        mine = true;
        ++computed_;
      } else {
        future = it->second.future;
      }
      it->second.last_use = ++clock_;
      if (capacity_ > 0 && entries_.size() > capacity_) {
        auto oldest = entries_.begin();
        for (auto e = entries_.begin(); e != entries_.end(); ++e) {
          if (e->second.last_use < oldest->second.last_use) oldest = e;
        }
        entries_.erase(oldest);  // never `key`: it was used last
      }
    }
    if (mine) {
      try {
        promise.set_value(std::forward<Compute>(compute)());
      } catch (...) {
        promise.set_exception(std::current_exception());
      }
    }
    return future.get();
  }

  /// Values computed so far (one per first request of a key, evicted keys counted again).
  std::size_t num_computed() const {
    std::lock_guard<std::mutex> lock(mutex_);
    return computed_;
  }

 private:
  struct Entry {
    std::shared_future<T> future;
    unsigned long last_use;
  };
  std::size_t capacity_;
  mutable std::mutex mutex_;
  std::map<std::string, Entry> entries_;
  unsigned long clock_{0};
  std::size_t computed_{0};
};

}  // namespace flexrod
