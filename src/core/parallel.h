// Splitting loops over threads. Work items must be independent: results are
// then the same whatever the thread count.
#pragma once

#include <functional>
#include <span>

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

// The same, the items taken in the order `order` lists them (a permutation of
// [0, order.size())): the longest first, say. The first exception by item, not
// by position in `order`, is rethrown.
void parallel_for_each(std::span<const int> order, int threads,
                       const std::function<void(int i)>& body);

// Calls work(i, lane) for every i in [0, count) on `lanes` threads (lane in
// [0, lanes)), each thread taking the next unclaimed item, and commit(i) for
// i = 0, 1, ... in that order, one at a time, each as soon as work(0..i) have
// returned. After an exception no item is claimed; the one of the lowest item
// is rethrown once the threads finish, and neither that item nor any later one
// is committed.
void ordered_parallel_for(int count, int lanes, const std::function<void(int i, int lane)>& work,
                          const std::function<void(int i)>& commit);

}  // namespace fss
