/// What the OpenMP loops share: when a loop is worth a parallel region, and the first error
/// of a parallel loop by index (an exception may not leave an OpenMP region, so each
/// iteration's is kept and the lowest index's rethrown after the loop: the one the serial loop
/// would have stopped at, whatever the thread count).
#pragma once
#include <exception>
#include <utility>

namespace mfv {

/// Below this many points or particles a parallel region costs more than it saves (and on a
/// loaded machine much more: waiting threads spin while their partner is descheduled).
constexpr int kParallelMinimum = 4096;

/// Whether a loop of `n` iterations on `threads` threads runs in parallel.
inline bool run_parallel(int threads, long n) { return threads > 1 && n > kParallelMinimum; }

class FirstError {
 public:
  /// Keeps the error of iteration `index` when no lower iteration has failed.
  void keep(long index, std::exception_ptr e) {
#pragma omp critical(mfv_first_error)
    if (index_ < 0 || index < index_) {
      index_ = index;
      error_ = std::move(e);
    }
  }
  void rethrow() const {
    if (error_) std::rethrow_exception(error_);
  }

 private:
  long index_ = -1;
  std::exception_ptr error_;
};

}  // namespace mfv
