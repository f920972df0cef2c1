// A fixed-period real-time loop: tick k is released at the absolute time start + k * period (slept to with
// clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME), so errors never accumulate) and runs the work of that
// tick. Measured per tick: the latency from the release to the end of the work (wake-up delay included,
// as a controller sees it) and the compute time alone. A tick whose work ends after the next release is
// a deadline miss; the loop then skips the releases it has lost instead of running late forever. Where
// the system allows, the loop runs at SCHED_FIFO priority, pinned to one CPU, with its memory locked.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

namespace humandyn::bench {

struct LoopStats {
  std::string work;    // what each tick computes, e.g. "humandyn ID"
  int characters = 0;  // K: characters per tick
  double seconds = 0;  // length of the run
  double period_us = 0;
  long ticks = 0;            // ticks run
  long misses = 0;           // ticks that ended after the next release, of which:
  long misses_late = 0;      //   the work itself fitted in a period, but it started late (the thread did
                             //   not run at its release: a wake-up delay or a pause of the machine)
  long misses_overrun = 0;   //   the work itself took longer than a period
  double max_wakeup_us = 0;  // largest delay from a release to the start of its work
  long skipped = 0;          // releases skipped after misses
  double p50_us = 0, p99_us = 0, p999_us = 0, max_us = 0;  // latency, release to end of work
  double compute_mean_us = 0, compute_p99_us = 0;          // the work alone
  double share = 0;                                        // mean compute time / period
  std::string scheduling;  // "SCHED_FIFO" when real-time priority was granted, else "SCHED_OTHER"; then
                           // " cpuN" when pinned to CPU N and " mlock" when memory was locked
};

// Runs work(tick) every `period_ns` for `seconds` and returns the statistics; 20 untimed warm-up calls with
// negative ticks come first.
LoopStats run_fixed_period_loop(const std::string& name, int characters, const std::function<void(long tick)>& work,
                                double seconds, std::int64_t period_ns = 1'000'000);

// The p-quantile (0..1) of `values` (sorted in place).
double quantile(std::vector<double>& values, double p);

}  // namespace humandyn::bench
