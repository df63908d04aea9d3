// Work sharing for the render passes.
//
// parallel_chunks: chunks are handed out one at a time from a shared counter,
// so a thread that drew cheap chunks takes more of them (static splits left a
// thread idle at the end of every pass). Callers keep results per chunk, never
// per thread, so the image does not depend on which thread ran what. The
// calling thread does not work; it sleeps until the workers finish, waking
// every `interval` seconds to call `poll` so Python can show progress and
// cancel.
//
// parallel_for / parallel_each: the short steps between passes (merging,
// committing sums), not cancellable.
#pragma once

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <mutex>
#include <thread>
#include <vector>

namespace ppm {

// The machine's threads, asked once: hardware_concurrency reads /sys on Linux, 10 us a call, and a
// dynamic scene builds thousands of small trees.
inline int hardware_threads() {
  static const int threads = std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  return threads;
}

// Returns false if cancelled (by `poll` returning false or the flag being set
// already). Exceptions from workers are rethrown on the calling thread.
inline bool parallel_chunks(int threads, size_t chunks, const std::function<void(int, size_t)>& work,
                            std::atomic<bool>& cancel, const std::function<bool()>& poll, double interval) {
  threads = std::max(1, std::min<int>(threads, static_cast<int>(std::min<size_t>(chunks, 1u << 16))));
  std::atomic<size_t> next{0};
  std::exception_ptr error;
  std::mutex mutex;  // guards error, running and the wake-up
  std::condition_variable finished;
  int running = threads;
  std::vector<std::thread> pool;
  pool.reserve(threads);
  for (int t = 0; t < threads; ++t) {
    pool.emplace_back([&, t]() {
      try {
        for (size_t c; !cancel.load(std::memory_order_relaxed) && (c = next.fetch_add(1)) < chunks;) work(t, c);
      } catch (...) {
        std::lock_guard<std::mutex> lock(mutex);
        if (!error) error = std::current_exception();
        cancel = true;
      }
      std::lock_guard<std::mutex> lock(mutex);
      if (--running == 0) finished.notify_one();
    });
  }
  // Polls four times per interval: `poll` keeps its own clock (Renderer::run calls back once per
  // interval), and a phase that starts just before its time is then not a whole interval late.
  const auto wait = std::chrono::duration<double>(poll ? std::max(interval / 4.0, 1e-3) : 3600.0);
  for (;;) {
    {
      std::unique_lock<std::mutex> lock(mutex);
      if (finished.wait_for(lock, wait, [&] { return running == 0; })) break;
    }
    if (!poll) continue;
    bool keep_going = true;
    try {
      keep_going = poll();
    } catch (...) {
      std::lock_guard<std::mutex> lock(mutex);
      if (!error) error = std::current_exception();
      keep_going = false;
    }
    if (!keep_going) cancel = true;
  }
  for (auto& th : pool) th.join();
  if (error) std::rethrow_exception(error);
  return !cancel.load();
}

// Runs fn on a worker thread while the calling thread polls every `interval`:
// a step that is not cut into chunks (building an index) still lets a cancel
// be noticed on time. fn runs to its end; returns false if poll asked to cancel.
inline bool run_polled(const std::function<void()>& fn, std::atomic<bool>& cancel, const std::function<bool()>& poll,
                       double interval) {
  return parallel_chunks(1, 1, [&](int, size_t) { fn(); }, cancel, poll, interval);
}

// fn(k) for every k in [0, count), handed out one at a time as in
// parallel_chunks, for uneven items (copying chunks of varying size); not cancellable.
inline void parallel_each(int threads, size_t count, const std::function<void(size_t)>& fn) {
  std::atomic<bool> never{false};
  parallel_chunks(threads, count, [&](int, size_t k) { fn(k); }, never, nullptr, 0.0);
}

// fn(begin, end) over [0, n) in at most `threads` contiguous ranges; small n
// runs on the calling thread. Exceptions are rethrown on the calling thread.
inline void parallel_for(int threads, size_t n, const std::function<void(size_t, size_t)>& fn) {
  constexpr size_t kMinPerThread = 16384;
  const size_t parts = std::max<size_t>(1, std::min<size_t>(threads, n / kMinPerThread));
  if (parts == 1) {
    fn(0, n);
    return;
  }
  parallel_each(static_cast<int>(parts), parts, [&](size_t p) { fn(n * p / parts, n * (p + 1) / parts); });
}

}  // namespace ppm
