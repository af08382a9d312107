/// Work a process owes when SIGINT, SIGTERM or SIGHUP kills it: an external solver's process
/// group to kill (it runs in a group of its own, so the signal that kills mfv does not reach
/// it, and it would run on, orphaned) and its case directory to remove. The signal thread
/// (reports/atomic.cpp, install_staging_cleanup) runs the registered work, the latest first,
/// before the process dies of the signal. A process-wide registry is unavoidable here: a
/// signal names no object. Header-only, so that every layer may register work.
#pragma once
#include <cstddef>
#include <functional>
#include <map>
#include <mutex>

namespace mfv {

class SignalCleanups {
 public:
  static SignalCleanups& get() {
    static SignalCleanups r;
    return r;
  }
  std::size_t add(std::function<void()> work) {
    std::lock_guard<std::mutex> hold(mutex_);
    work_.emplace(++next_, std::move(work));
    return next_;
  }
  void remove(std::size_t id) {
    std::lock_guard<std::mutex> hold(mutex_);
    work_.erase(id);
  }
  /// Runs every registered work, the latest first, once; the registry stays locked after it
  /// (the process is about to die: nothing registers or unregisters in between).
  void run_all_and_hold() {
    mutex_.lock();
    for (auto it = work_.rbegin(); it != work_.rend(); ++it) {
      try {
        it->second();
      } catch (...) {  // a signal's clean-up does what it can
      }
    }
    work_.clear();
  }

 private:
  std::mutex mutex_;
  std::map<std::size_t, std::function<void()>> work_;
  std::size_t next_ = 0;
};

/// Registers `work` for the signal thread while in scope.
class OnSignal {
 public:
  explicit OnSignal(std::function<void()> work) : id_(SignalCleanups::get().add(std::move(work))) {}
  ~OnSignal() { SignalCleanups::get().remove(id_); }
  OnSignal(const OnSignal&) = delete;
  OnSignal& operator=(const OnSignal&) = delete;

 private:
  std::size_t id_;
};

}  // namespace mfv
