#pragma once
// Work shared by the kernel's sources over a few threads (no pool: each call starts and joins its own).

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <exception>
#include <functional>
#include <optional>
#include <system_error>
#include <thread>
#include <utility>
#include <vector>

namespace st::detail {

/// Threads a parallel loop uses: the machine's, at most 8.
inline unsigned thread_count() { return std::clamp(std::thread::hardware_concurrency(), 1u, 8u); }

/// Runs work(worker, begin, end) over [0, n) in chunks of `grain` items (always the same chunks,
/// whatever the number of threads, so results gathered per chunk do not depend on it), handed out in
/// order to up to thread_count() threads; worker < thread_count() names the thread (for scratch).
template <class Work> void parallel_for(std::size_t n, std::size_t grain, const Work& work) {
  const std::size_t chunks = (n + grain - 1) / grain;
  const std::size_t threads = std::min<std::size_t>(thread_count(), chunks);
  std::atomic<std::size_t> next{0};
  auto run = [&](std::size_t worker) {
    for (std::size_t c = next.fetch_add(1); c < chunks; c = next.fetch_add(1))
      work(worker, c * grain, std::min(n, (c + 1) * grain));
  };
  std::vector<std::thread> pool;
  if (threads > 1) pool.reserve(threads - 1);
  for (std::size_t k = 1; k < threads; ++k) {
    try {
      pool.emplace_back(run, k);
    } catch (const std::system_error&) {
      break; // fewer threads: the others take over the chunks
    }
  }
  run(0);
  for (std::thread& t : pool) t.join();
}

/// Work on a thread of its own beside the caller's (at once, on the caller's, when no thread can be
/// started). join() waits for it and rethrows what it threw; the destructor waits too, so the work
/// never outlives what it reads, even when the caller leaves by an exception.
class Background {
public:
  explicit Background(std::function<void()> work) : work_(std::move(work)) {
    try {
      thread_.emplace([this] { run(); });
    } catch (const std::system_error&) {
      run();
    }
  }
  Background(const Background&) = delete;
  Background& operator=(const Background&) = delete;
  ~Background() {
    if (thread_ && thread_->joinable()) thread_->join();
  }
  void join() {
    if (thread_ && thread_->joinable()) thread_->join();
    if (failure_) std::rethrow_exception(std::exchange(failure_, nullptr));
  }

private:
  void run() {
    try {
      work_();
    } catch (...) {
      failure_ = std::current_exception();
    }
  }
  std::function<void()> work_;
  std::exception_ptr failure_;
  std::optional<std::thread> thread_;
};

} // namespace st::detail
