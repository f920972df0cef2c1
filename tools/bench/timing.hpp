// Wall-clock timing of a per-call function over a pool of states, for the error-against-run-time table.
// The call is inlined in the timing loop (no indirect call per state). The figure is the best of a few
// repetitions of the mean time per call, which filters out the other processes of a shared machine.
#pragma once

#include <algorithm>
#include <chrono>
#include <cstdint>

namespace humandyn::bench {

// Keeps the compiler from dropping a result nobody reads.
template <class T>
inline void do_not_optimize(const T& value) {
  asm volatile("" : : "g"(&value) : "memory");
}

inline std::int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Mean nanoseconds per call of call(i), i cycling over [0, pool): one warm-up pass, then `repetitions`
// timed runs of whole passes lasting at least `seconds` / repetitions each; the fastest run counts.
template <class Call>
double ns_per_call(int pool, double seconds, Call&& call, int repetitions = 5) {
  for (int i = 0; i < pool; ++i) call(i);  // warm-up: caches, branch predictors, frequency
  const auto budget = std::int64_t(1e9 * seconds / repetitions);
  double best = 1e300;
  for (int r = 0; r < repetitions; ++r) {
    std::int64_t calls = 0;
    const std::int64_t start = now_ns();
    std::int64_t elapsed = 0;
    do {
      for (int i = 0; i < pool; ++i) call(i);
      calls += pool;
      elapsed = now_ns() - start;
    } while (elapsed < budget);
    best = std::min(best, double(elapsed) / double(calls));
  }
  return best;
}

}  // namespace humandyn::bench
