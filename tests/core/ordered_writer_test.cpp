#include "core/ordered_writer.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <random>
#include <stdexcept>
#include <thread>
#include <vector>

namespace acpca {
namespace {

TEST(OrderedWriter, CommitsInSubmissionOrderWhateverOrderJobsFinishIn) {
  for (int threads : {1, 2, 4}) {
    std::vector<int> committed;
    std::atomic<int> inFlight{0}, mostInFlight{0};
    std::mt19937 rng(threads);
    {
      OrderedWriter writer(threads, 5);
      for (int i = 0; i < 200; ++i) {
        const int sleepUs = static_cast<int>(rng() % 300);
        writer.submit([&, i, sleepUs] {
          const int now = ++inFlight;
          for (int seen = mostInFlight;
               now > seen && !mostInFlight.compare_exchange_weak(seen, now);)
            ;
          std::this_thread::sleep_for(std::chrono::microseconds(sleepUs));  // finish out of order
          return OrderedWriter::Commit([&, i] {
            committed.push_back(i);
            --inFlight;
          });
        });
      }
      writer.finish();
      EXPECT_EQ(writer.committed(), 200u);
    }
    ASSERT_EQ(committed.size(), 200u) << threads << " threads";
    for (int i = 0; i < 200; ++i) ASSERT_EQ(committed[i], i) << threads << " threads";
    EXPECT_LE(mostInFlight.load(), 5) << "the queue is bounded";
  }
}

TEST(OrderedWriter, AFailedJobStopsLaterCommitsAndIsRethrown) {
  std::vector<int> committed;
  OrderedWriter writer(2, 3);
  bool thrown = false;
  try {
    for (int i = 0; i < 50; ++i)
      writer.submit([&, i]() -> OrderedWriter::Commit {
        if (i == 7) throw std::runtime_error("disk full at 7");
        return [&, i] { committed.push_back(i); };
      });
    writer.finish();
  } catch (const std::runtime_error& e) {
    thrown = std::string(e.what()) == "disk full at 7";
  }
  EXPECT_TRUE(thrown);
  ASSERT_LE(committed.size(), 7u) << "nothing after the failed item commits";
  for (size_t i = 0; i < committed.size(); ++i) EXPECT_EQ(committed[i], static_cast<int>(i));
}

}  // namespace
}  // namespace acpca
