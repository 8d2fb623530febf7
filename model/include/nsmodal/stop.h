#pragma once
// A request to stop long work, polled: the one process-wide state of nsmodal.
//
// A signal is process-wide by nature, so its request is too: the command
// line's SIGINT and SIGTERM handlers (and Python's Ctrl-C) call RequestStop,
// which is async-signal-safe (a lock-free atomic store). Long work polls
// ThrowIfStopRequested() between units of work (ParallelFor between items,
// every event loop at each step, the charts between figures); it throws Stopped,
// so the work unwinds: result files not yet committed are removed by their
// destructors and an OutputDir removes the results its run had committed
// (output.h). The face that installed the handlers catches Stopped and exits
// 128 + signal (130 for SIGINT, 143 for SIGTERM).
//
// Polling costs one relaxed atomic load. A poll never blocks and never throws
// unless a stop was requested.
#include <atomic>
#include <csignal>
#include <stdexcept>
#include <string>

namespace nsmodal {

class Stopped : public std::runtime_error {
 public:
  explicit Stopped(int signal)
      : std::runtime_error(std::string("interrupted by ") +
                           (signal == SIGINT ? "SIGINT" : signal == SIGTERM ? "SIGTERM" : "a stop request")),
        signal_(signal) {}
  int signal() const { return signal_; }

 private:
  int signal_;
};

namespace internal {
inline std::atomic<int> stop_signal{0};
// Tests and the fault fuzzer: a stop requested by the k-th poll from now
// (0: disarmed), to stop work at a chosen point without a timer.
inline std::atomic<long> stop_countdown{0};
inline std::atomic<int> stop_countdown_signal{0};
static_assert(std::atomic<int>::is_always_lock_free, "RequestStop must be async-signal-safe");
}  // namespace internal

// Async-signal-safe. `signal`: the signal number (any positive value for a
// request that is not a signal).
inline void RequestStop(int signal) noexcept { internal::stop_signal.store(signal, std::memory_order_relaxed); }
// The requested signal, 0 when none.
inline int StopRequested() noexcept { return internal::stop_signal.load(std::memory_order_relaxed); }
// Forget a request (a face that handled it and goes on, as Python does).
inline void ClearStopRequest() noexcept {
  internal::stop_signal.store(0, std::memory_order_relaxed);
  internal::stop_countdown.store(0, std::memory_order_relaxed);
}
// Requests a stop (`signal`) at the k-th poll from now (k >= 1).
inline void RequestStopAtPoll(long k, int signal) noexcept {
  internal::stop_signal.store(0, std::memory_order_relaxed);
  internal::stop_countdown_signal.store(signal, std::memory_order_relaxed);
  internal::stop_countdown.store(k, std::memory_order_relaxed);
}

inline void ThrowIfStopRequested() {
  if (internal::stop_countdown.load(std::memory_order_relaxed) > 0 &&
      internal::stop_countdown.fetch_sub(1, std::memory_order_relaxed) == 1) {
    RequestStop(internal::stop_countdown_signal.load(std::memory_order_relaxed));
  }
  if (const int s = StopRequested()) throw Stopped(s);
}

}  // namespace nsmodal
