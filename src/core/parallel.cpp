#include "core/parallel.h"

#include <algorithm>
#include <atomic>
#include <exception>
#include <mutex>
#include <numeric>
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
  std::vector<int> order(static_cast<std::size_t>(count));
  std::iota(order.begin(), order.end(), 0);
  parallel_for_each(order, threads, body);
}

void parallel_for_each(std::span<const int> order, int threads,
                       const std::function<void(int i)>& body) {
  const int count = static_cast<int>(order.size());
  if (count <= 0) return;
  const int workers = std::min(resolve_thread_count(threads), count);
  std::vector<std::exception_ptr> errors(static_cast<std::size_t>(count));
  std::atomic<int> next{0};
  parallel_for(workers, workers, [&](int, int) {
    for (int position = next++; position < count; position = next++) {
      const int i = order[static_cast<std::size_t>(position)];
      try {
        body(i);
      } catch (...) {
        errors[static_cast<std::size_t>(i)] = std::current_exception();
      }
    }
  });
  for (const auto& error : errors) {
    if (error) std::rethrow_exception(error);
  }
}

namespace {

// What ordered_parallel_for's threads share: which items are done, the next
// to commit and the first failure, all under `mutex`.
struct OrderedState {
  explicit OrderedState(int count) : done(static_cast<std::size_t>(count), 0), failed_at(count) {}
  std::mutex mutex;
  std::vector<char> done;
  int next_commit = 0;
  int failed_at;  // the lowest item that threw; count when none
  std::exception_ptr error;
  std::atomic<int> next{0};
  std::atomic<bool> stop{false};

  void fail(int i, std::exception_ptr e) {
    if (i < failed_at) {
      failed_at = i;
      error = std::move(e);
    }
    stop = true;
  }
  // Commits the items done in a row from next_commit, up to the first failure.
  void commit_ready(const std::function<void(int i)>& commit) {
    while (next_commit < failed_at && done[static_cast<std::size_t>(next_commit)]) {
      try {
        commit(next_commit);
      } catch (...) {
        fail(next_commit, std::current_exception());
        return;
      }
      ++next_commit;
    }
  }
};

}  // namespace

void ordered_parallel_for(int count, int lanes, const std::function<void(int i, int lane)>& work,
                          const std::function<void(int i)>& commit) {
  if (count <= 0) return;
  OrderedState state(count);
  const int workers = std::clamp(lanes, 1, count);
  parallel_for(workers, workers, [&](int lane, int) {
    for (int i = state.next++; i < count && !state.stop; i = state.next++) {
      std::exception_ptr error;
      try {
        work(i, lane);
      } catch (...) {
        error = std::current_exception();
      }
      const std::lock_guard<std::mutex> lock(state.mutex);
      if (error) {
        state.fail(i, error);
      } else {
        state.done[static_cast<std::size_t>(i)] = 1;
        state.commit_ready(commit);
      }
    }
  });
  if (state.error) std::rethrow_exception(state.error);
}

}  // namespace fss
