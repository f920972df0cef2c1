// The 1 kHz loop counts what it says: a tick whose work outlasts the period is a miss and an overrun,
// the releases it swallowed are skipped, and every miss is either late (the work fitted but started
// late) or an overrun.
#include "bench/realtime_loop.hpp"

#include <gtest/gtest.h>

#include <chrono>

namespace test_bench_loop {

namespace hb = humandyn::bench;

namespace {

void busy_for(std::chrono::nanoseconds d) {
  const auto t0 = std::chrono::steady_clock::now();
  while (std::chrono::steady_clock::now() - t0 < d) {
  }
}

}  // namespace

TEST(BenchLoop, AnOverrunIsAMissAndSkipsTheLostReleases) {
  const hb::LoopStats s = hb::run_fixed_period_loop(
      "test", 1,
      [](long tick) {
        if (tick == 10) busy_for(std::chrono::milliseconds(3));
      },
      0.05);
  EXPECT_GE(s.ticks, 40);
  EXPECT_GE(s.misses_overrun, 1);
  EXPECT_GE(s.skipped, 2);  // a 3 ms tick swallows the next two releases
  EXPECT_EQ(s.misses, s.misses_late + s.misses_overrun);
  EXPECT_GE(s.max_us, 3000.0);
  EXPECT_GT(s.compute_p99_us, 0.0);
}

TEST(BenchLoop, LightWorkIsStatistics) {
  const hb::LoopStats s = hb::run_fixed_period_loop(
      "test", 1, [](long) { busy_for(std::chrono::microseconds(50)); }, 0.05);
  EXPECT_EQ(s.misses, s.misses_late + s.misses_overrun);
  EXPECT_GE(s.compute_mean_us, 50.0);
  EXPECT_LE(s.p50_us, s.p99_us);
  EXPECT_LE(s.p99_us, s.max_us);
  EXPECT_NEAR(s.share, s.compute_mean_us / 1000.0, 1e-12);
}

}  // namespace test_bench_loop
