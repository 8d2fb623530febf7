#pragma once
// Runs body(i) for i in [0, count) on `threads` worker threads (0: all cores),
// calling progress(done, count) from the calling thread about ten times a second.
#include <atomic>
#include <chrono>
#include <functional>
#include <thread>
#include <vector>

namespace nsmodal {

inline void ParallelFor(long count, int threads, const std::function<void(long)>& body,
                        const std::function<void(long, long)>& progress = {}) {
  if (threads <= 0) threads = static_cast<int>(std::max(1u, std::thread::hardware_concurrency()));
  std::atomic<long> next{0};
  std::atomic<long> done{0};
  auto worker = [&] {
    for (long i = next++; i < count; i = next++) {
      body(i);
      ++done;
    }
  };
  std::vector<std::thread> pool;
  for (int t = 1; t < threads; ++t) pool.emplace_back(worker);
  if (progress) {
    // The calling thread reports while the pool works, then joins in.
    while (done.load() < count && !pool.empty()) {
      progress(done.load(), count);
      std::this_thread::sleep_for(std::chrono::milliseconds(100));
      if (next.load() >= count) break;
    }
  }
  worker();
  for (auto& t : pool) t.join();
  if (progress) progress(count, count);
}

}  // namespace nsmodal
