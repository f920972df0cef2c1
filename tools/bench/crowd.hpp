// Crowd throughput: how many characters one core, and every core, serves at 1 kHz with half the period
// free, for inverse dynamics and the full simulation step (PD servo + mass-matrix forward dynamics +
// semi-implicit Euler or implicit PD), one character at a time (the scalar loop) and W at a time in the
// SIMD lanes of each instruction set the CPU has (crowd_kernels.hpp), in double and float; then the
// 1 kHz loop run at the crowd size fitted for one core.
#pragma once

#include "bench/realtime_loop.hpp"
#include "humandyn/model.hpp"

#include <string>
#include <vector>

namespace humandyn::bench {

struct CrowdRow {
  std::string work;    // "ID", "step euler", "step implicit"
  std::string scalar;  // "double", "float"
  std::string lanes;   // "scalar loop", or the instruction set and width, e.g. "avx512 x8"
  int threads = 1;
  std::size_t crowd = 0;        // characters stepped by each call (all threads together)
  double ns_per_character = 0;  // wall clock per character per call (all threads: the crowd's time / its size)
  int characters = 0;           // that fit in half of a 1 ms period: 0.5 ms / ns_per_character
  double speedup = 0;           // over the scalar loop of the same work and type, one thread each
  double per_core_share = 0;    // all threads: characters / (threads x one thread's), else 1
  long refused = 0;             // steps refused (status not ok) while timing; 0 expected
};

struct CrowdReport {
  int cores = 1;
  std::vector<CrowdRow> rows;
  LoopStats loop;  // widest lanes, double, implicit step, at the fitted per-core size
};

// The crowd rows for model `d`: each row timed for about `seconds`; the loop runs `loop_seconds`.
CrowdReport run_crowd(const ModelDescription<double>& d, double seconds, double loop_seconds);

}  // namespace humandyn::bench
