// Static, interleaved work sharing: chunk c runs on thread c % threads, so the
// split (and with it every per-thread sum) is the same on every run. The
// calling thread does not work; it waits and calls `poll` every `interval`
// seconds so Python can show progress and ask to cancel.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace ppm {

// Returns false if cancelled (by `poll` returning false or the flag being set
// already). Exceptions from workers are rethrown on the calling thread.
inline bool parallel_chunks(int threads, size_t chunks, const std::function<void(int, size_t)>& work,
                            std::atomic<bool>& cancel, const std::function<bool()>& poll, double interval) {
  std::atomic<int> running{threads};
  std::exception_ptr error;
  std::mutex error_mutex;
  std::vector<std::thread> pool;
  pool.reserve(threads);
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t]() {
      try {
        for (size_t c = t; c < chunks && !cancel.load(std::memory_order_relaxed); c += threads) work(t, c);
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        cancel = true;
      }
      running.fetch_sub(1);
    });
  }
  auto last = std::chrono::steady_clock::now();
  while (running.load() > 0) {
    std::this_thread::sleep_for(std::chrono::milliseconds(2));
    const auto now = std::chrono::steady_clock::now();
    if (poll && std::chrono::duration<double>(now - last).count() >= interval) {
      last = now;
      bool keep_going = true;
      try {
        keep_going = poll();
      } catch (...) {
        std::lock_guard<std::mutex> lock(error_mutex);
        if (!error) error = std::current_exception();
        keep_going = false;
      }
      if (!keep_going) cancel = true;
    }
  }
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
  return !cancel.load();
}

}  // namespace ppm
