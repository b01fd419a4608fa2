#include "core/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <thread>
#include <vector>

namespace fss {

int resolve_thread_count(int threads) {
  if (threads > 0) return threads;
  const unsigned hardware = std::thread::hardware_concurrency();
  return hardware == 0 ? 1 : static_cast<int>(hardware);
}

void parallel_for(int count, int threads, const std::function<void(int begin, int end)>& body) {
  if (count <= 0) return;
  const int workers = std::min(resolve_thread_count(threads), count);
  if (workers == 1) {
    body(0, count);
    return;
  }
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(workers));
  auto run_block = [&](int w) {
    const int begin = static_cast<int>(static_cast<long long>(count) * w / workers);
    const int end = static_cast<int>(static_cast<long long>(count) * (w + 1) / workers);
    try {
      body(begin, end);
    } catch (...) {
      errors[w] = std::current_exception();
    }
  };
  // A thread that cannot be started (the system's thread or memory limit) is
  // no error: the calling thread runs its block. The blocks, and so the
  // results, are the same whichever thread runs them.
  std::vector<std::thread> pool;
  int started = 1;
  try {
    pool.reserve(static_cast<std::size_t>(workers - 1));
    for (; started < workers; ++started) pool.emplace_back(run_block, started);
  } catch (const std::exception&) {
  }
  run_block(0);
  for (int w = started; w < workers; ++w) run_block(w);
  for (auto& thread : pool) thread.join();
  for (const auto& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

void parallel_for_each(int count, int threads, const std::function<void(int i)>& body) {
  if (count <= 0) return;
  const int workers = std::min(resolve_thread_count(threads), count);
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(count));
  std::atomic<int> next{0};
  parallel_for(workers, workers, [&](int, int) {
    for (int i = next++; i < count; i = next++) {
      try {
        body(i);
      } catch (...) {
        errors[i] = std::current_exception();
      }
    }
  });
  for (const auto& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

}  // namespace fss
