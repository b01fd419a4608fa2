// Splitting loops over threads. Work items must be independent: results are
// then the same whatever the thread count.
#pragma once

#include <functional>

namespace fss {

// 0 means all hardware threads (at least 1).
int resolve_thread_count(int threads);

// Calls body(begin, end) on contiguous blocks covering [0, count), on up to
// `threads` threads (see resolve_thread_count). The first exception thrown by
// a block is rethrown in the caller after all threads have finished. Blocks
// whose thread cannot be started run on the calling thread.
void parallel_for(int count, int threads, const std::function<void(int begin, int end)>& body);

// Calls body(i) for every i in [0, count), each thread taking the next
// unclaimed item: for items of unequal cost (files of different sizes),
// where fixed blocks would leave a thread idle. Same exceptions rule as
// parallel_for (the first thrown, by item order, is rethrown).
void parallel_for_each(int count, int threads, const std::function<void(int i)>& body);

}  // namespace fss
