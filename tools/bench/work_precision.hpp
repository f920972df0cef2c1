// One point of the integration work-precision measurement: a scenario simulated with one integrator and
// one fixed step, its computing time and its end-state error against the long double reference.
#pragma once

#include <string>

namespace humandyn::bench {

struct WorkPrecisionPoint {
  std::string scenario, integrator;
  double h = 0;  // step (s)
  int steps = 0;
  double ms_per_sim_second = 0;  // computing time per simulated second (ms)
  double q_error = 0;            // |q(T) - q_ref(T)|_inf (rad); infinite when the run failed
  double qd_error = 0;           // |qd(T) - qd_ref(T)|_inf (rad/s)
  bool ok = true;                // every step succeeded (no non-finite or runaway state)
};

}  // namespace humandyn::bench
