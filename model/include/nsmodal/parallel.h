#pragma once
// Runs body(i) for i in [0, count) on `threads` worker threads (0: all cores),
// calling progress(done, count) from the calling thread about ten times a second.
// The first exception thrown by body stops the remaining work and is rethrown
// on the calling thread; a stop request (stop.h) is polled before each item
// and ends the work the same way (Stopped).
#include <algorithm>
#include <atomic>
#include <chrono>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

#include "nsmodal/stop.h"

namespace nsmodal {

inline void ParallelFor(long count, int threads, const std::function<void(long)>& body,
                        const std::function<void(long, long)>& progress = {}) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  // No more threads than items; and if the system refuses a thread, the ones
  // already started (and this one) do the work.
  threads = static_cast<int>(std::min<long>(threads, std::max(1L, count)));
  std::atomic<long> next{0};
  std::atomic<long> done{0};
  std::exception_ptr error;
  std::mutex error_mutex;
  auto fail = [&] {
    std::lock_guard<std::mutex> lock(error_mutex);
    if (!error) error = std::current_exception();
    next = count;  // stop handing out work
  };
  // The calling thread works too, and between its own items reports
  // progress at most every 100 ms. (It used to only report while the pool
  // worked, sleeping 100 ms at a time: one core in `threads` idle, and up to
  // 100 ms lost at the end of every call, which a streamed sweep makes once a
  // block.) A progress callback that throws (a Python callable that raised)
  // ends the work as a body that throws does: the pool is joined before the
  // exception goes on (a running thread's destructor would terminate).
  auto last = std::chrono::steady_clock::now();
  auto worker = [&](bool reports) {
    for (long i = next++; i < count; i = next++) {
      try {
        ThrowIfStopRequested();
        body(i);
      } catch (...) {
        fail();
      }
      ++done;
      if (reports && progress && std::chrono::steady_clock::now() - last >= std::chrono::milliseconds(100)) {
        last = std::chrono::steady_clock::now();
        try {
          progress(done.load(), count);
        } catch (...) {
          fail();
        }
      }
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) {
    try {
      pool.emplace_back(worker, false);
    } catch (const std::exception&) {  // no thread (a system error) or no memory for it
      break;
    }
  }
  if (progress) {
    try {
      progress(0, count);
    } catch (...) {
      fail();
    }
  }
  worker(true);
  for (auto& t : pool) t.join();
  if (error) std::rethrow_exception(error);
  if (progress) progress(count, count);
}

}  // namespace nsmodal
