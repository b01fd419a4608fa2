// Tests of parallel_for and ordered_parallel_for (parallel.h): coverage of the
// range, commit order, exceptions, and a system that refuses new threads.
#include "core/parallel.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstdlib>
#include <mutex>
#include <stdexcept>
#include <string>
#include <thread>
#include <vector>

#include "support/test_util.h"

namespace fss {
namespace {

TEST(ParallelFor, EveryIndexExactlyOnceInContiguousBlocks) {
  for (const int threads : {0, 1, 2, 3, 7, 64}) {
    for (const int count : {0, 1, 2, 5, 63, 64, 1000}) {
      std::vector<int> hits(static_cast<std::size_t>(count), 0);
      std::mutex mutex;
      std::vector<std::pair<int, int>> blocks;
      parallel_for(count, threads, [&](int begin, int end) {
        for (int i = begin; i < end; ++i) ++hits[i];
        const std::lock_guard<std::mutex> lock(mutex);
        blocks.emplace_back(begin, end);
      });
      for (int i = 0; i < count; ++i) {
        EXPECT_EQ(hits[i], 1) << "index " << i << ", count " << count << ", threads " << threads;
      }
      for (const auto& [begin, end] : blocks) EXPECT_LE(begin, end);
    }
  }
}

TEST(ParallelFor, RethrowsTheExceptionOfABlock) {
  EXPECT_THROW(parallel_for(100, 4,
                            [](int begin, int end) {
                              if (begin <= 60 && 60 < end) throw std::runtime_error("block");
                            }),
               std::runtime_error);
}

TEST(ParallelForEach, EveryIndexExactlyOnce) {
  for (const int threads : {0, 1, 2, 3, 64}) {
    for (const int count : {0, 1, 2, 9, 1000}) {
      std::vector<std::atomic<int>> hits(static_cast<std::size_t>(count));
      parallel_for_each(count, threads, [&](int i) { ++hits[i]; });
      for (int i = 0; i < count; ++i) {
        EXPECT_EQ(hits[i], 1) << "index " << i << ", count " << count << ", threads " << threads;
      }
    }
  }
}

TEST(ParallelForEach, RethrowsTheFirstExceptionByIndex) {
  try {
    parallel_for_each(50, 3, [](int i) {
      if (i == 7 || i == 40) throw std::runtime_error("item " + std::to_string(i));
    });
    ADD_FAILURE() << "no exception";
  } catch (const std::runtime_error& e) {
    EXPECT_STREQ(e.what(), "item 7");
  }
}

TEST(ParallelForEach, TakesTheItemsInTheOrderGiven) {
  const std::vector<int> order = {3, 0, 4, 1, 2};
  std::vector<int> taken;
  parallel_for_each(order, 1, [&](int i) { taken.push_back(i); });
  EXPECT_EQ(taken, order);
  for (const int threads : {2, 3, 64}) {
    std::vector<std::atomic<int>> hits(order.size());
    parallel_for_each(order, threads, [&](int i) { ++hits[static_cast<std::size_t>(i)]; });
    for (const auto& hit : hits) EXPECT_EQ(hit, 1) << threads << " threads";
  }
}

TEST(ParallelForEach, InAnyOrderRethrowsTheFirstExceptionByItem) {
  std::vector<int> order(50);  // 49, 48, ..., 0: item 40 is taken before item 7
  for (int position = 0; position < 50; ++position) order[position] = 49 - position;
  for (const int threads : {1, 3}) {
    try {
      parallel_for_each(order, threads, [](int i) {
        if (i == 7 || i == 40) throw std::runtime_error("item " + std::to_string(i));
      });
      ADD_FAILURE() << "no exception";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 7");
    }
  }
}

TEST(ParallelForDeathTest, RunsEveryBlockWhenThreadsCannotStart) {
  if (test::kAddressSanitizer) GTEST_SKIP() << "RLIMIT_AS cannot be used under AddressSanitizer";
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  // With room for a few 8 MiB thread stacks only, most of the 64 threads
  // cannot start; their blocks must still run (before the fix, the exception
  // of std::thread left joinable threads behind: std::terminate).
  EXPECT_EXIT(
      {
        constexpr int kCount = 64;
        std::vector<std::atomic<int>> hits(kCount);
        test::limit_address_space(std::size_t{40} << 20);
        parallel_for(kCount, kCount, [&](int begin, int end) {
          for (int i = begin; i < end; ++i) hits[i].fetch_add(1);
        });
        for (const auto& hit : hits) {
          if (hit.load() != 1) std::_Exit(3);
        }
        std::_Exit(0);
      },
      ::testing::ExitedWithCode(0), "");
}

// Every item is worked once, on a lane in range, and committed once, in order,
// only after its own work.
TEST(OrderedParallelFor, CommitsEveryItemInOrderAfterItsWork) {
  for (const int lanes : {1, 2, 3, 8}) {
    for (const int count : {0, 1, 2, 7, 200}) {
      std::vector<std::atomic<int>> worked(static_cast<std::size_t>(count));
      std::vector<int> committed;
      ordered_parallel_for(
          count, lanes,
          [&](int i, int lane) {
            EXPECT_GE(lane, 0);
            EXPECT_LT(lane, lanes);
            // Later items often finish first: the commits must still come in order.
            if (i % 3 == 0) std::this_thread::sleep_for(std::chrono::microseconds(200));
            ++worked[i];
          },
          [&](int i) {
            EXPECT_EQ(worked[i].load(), 1) << i;
            committed.push_back(i);
          });
      ASSERT_EQ(static_cast<int>(committed.size()), count) << lanes;
      for (int i = 0; i < count; ++i) EXPECT_EQ(committed[i], i);
    }
  }
}

// The lowest failing item's exception is rethrown; it and every later item
// stay uncommitted, every earlier one is committed.
TEST(OrderedParallelFor, StopsAtTheLowestFailure) {
  for (const int lanes : {1, 2, 4}) {
    std::vector<int> committed;
    std::mutex mutex;
    try {
      ordered_parallel_for(
          100, lanes,
          [&](int i, int) {
            if (i == 40) throw std::runtime_error("item 40");
            if (i == 60) throw std::runtime_error("item 60");
          },
          [&](int i) {
            const std::lock_guard<std::mutex> lock(mutex);
            committed.push_back(i);
          });
      ADD_FAILURE() << "no exception with " << lanes << " lanes";
    } catch (const std::runtime_error& e) {
      EXPECT_STREQ(e.what(), "item 40") << lanes;
    }
    ASSERT_EQ(committed.size(), 40u) << lanes;
    for (int i = 0; i < 40; ++i) EXPECT_EQ(committed[i], i);
  }
}

// A commit that throws stops the run: nothing after it is committed.
TEST(OrderedParallelFor, ACommitThatThrowsStopsTheRun) {
  std::vector<int> committed;
  EXPECT_THROW(ordered_parallel_for(
                   50, 2, [](int, int) {},
                   [&](int i) {
                     if (i == 10) throw std::runtime_error("commit 10");
                     committed.push_back(i);
                   }),
               std::runtime_error);
  EXPECT_EQ(committed.size(), 10u);
}

}  // namespace
}  // namespace fss
