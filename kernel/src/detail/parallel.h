#pragma once
// Work shared by the kernel's sources over a few threads (no pool: each call starts and joins its own).

#include <algorithm>
#include <atomic>
#include <cstddef>
#include <system_error>
#include <thread>
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

} // namespace st::detail
