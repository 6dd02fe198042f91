// Splits [0, n) into contiguous chunks run on up to `threads` std::threads. Chunk
// boundaries depend only on n and the chunk count, and callers write results to
// per-item slots, so results never depend on the thread count.
#pragma once

#include <algorithm>
#include <cstddef>
#include <system_error>
#include <thread>
#include <vector>

namespace coral_introspection {
namespace coral {

// Calls f(begin, end) for every chunk; the calling thread runs the first one. A thread that
// cannot be started (resource limits) runs its chunk on the caller: never throws for that.
template <class F>
void parallelChunks(std::size_t n, int threads, F&& f) {
  const std::size_t k = std::max<std::size_t>(1, std::min<std::size_t>(threads, n));
  if (k == 1) {
    if (n > 0) f(std::size_t{0}, n);
    return;
  }
  std::vector<std::thread> pool;
  std::vector<std::size_t> inline_chunks;
  for (std::size_t c = 1; c < k; ++c) {
    const std::size_t b = n * c / k, e = n * (c + 1) / k;
    try {
      pool.emplace_back([&f, b, e] { f(b, e); });
    } catch (const std::system_error&) {
      inline_chunks.push_back(c);
    }
  }
  f(std::size_t{0}, n / k);
  for (std::size_t c : inline_chunks) f(n * c / k, n * (c + 1) / k);
  for (std::thread& t : pool) t.join();
}

}  // namespace coral
}  // namespace coral_introspection
