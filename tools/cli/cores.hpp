// The cores this process may run on.
#pragma once

#include <sched.h>

#include <algorithm>
#include <thread>

namespace humandyn::cli {

// The CPUs in this process's affinity mask (taskset, a container's cpuset), which
// std::thread::hardware_concurrency does not see (it counts the machine's); at least 1.
inline int usable_cores() {
  cpu_set_t set;
  CPU_ZERO(&set);
  if (sched_getaffinity(0, sizeof set, &set) == 0) return std::max(1, CPU_COUNT(&set));
  return int(std::max(1u, std::thread::hardware_concurrency()));
}

}  // namespace humandyn::cli
