#include "bench/realtime_loop.hpp"

#include <pthread.h>
#include <sched.h>
#include <sys/mman.h>
#include <time.h>

#include <algorithm>
#include <cmath>

namespace humandyn::bench {

namespace {

std::int64_t monotonic_ns() {
  timespec t{};
  clock_gettime(CLOCK_MONOTONIC, &t);
  return std::int64_t(t.tv_sec) * 1'000'000'000 + t.tv_nsec;
}

void sleep_until(std::int64_t deadline_ns) {
  timespec t{};
  t.tv_sec = time_t(deadline_ns / 1'000'000'000);
  t.tv_nsec = long(deadline_ns % 1'000'000'000);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &t, nullptr) != 0) {
  }  // interrupted by a signal: sleep again to the same absolute time
}

// Asks for real-time priority for this thread; returns what it got. Unprivileged users keep SCHED_OTHER.
std::string try_realtime_priority(int& old_policy, sched_param& old_param) {
  pthread_getschedparam(pthread_self(), &old_policy, &old_param);
  sched_param p{};
  p.sched_priority = std::max(1, sched_get_priority_max(SCHED_FIFO) / 2);
  if (pthread_setschedparam(pthread_self(), SCHED_FIFO, &p) == 0) return "SCHED_FIFO";
  return "SCHED_OTHER";
}

// Pins this thread to the last CPU it may run on (the first CPU takes most interrupts and housekeeping);
// returns the CPU, or -1 if it could not pin. `old` receives the previous mask.
int pin_to_last_cpu(cpu_set_t& old) {
  CPU_ZERO(&old);
  if (pthread_getaffinity_np(pthread_self(), sizeof old, &old) != 0) return -1;
  int last = -1;
  for (int c = 0; c < CPU_SETSIZE; ++c)
    if (CPU_ISSET(c, &old)) last = c;
  if (last < 0) return -1;
  cpu_set_t one;
  CPU_ZERO(&one);
  CPU_SET(last, &one);
  return pthread_setaffinity_np(pthread_self(), sizeof one, &one) == 0 ? last : -1;
}

}  // namespace

double quantile(std::vector<double>& values, double p) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const auto k = std::size_t(std::min(double(values.size() - 1), std::floor(p * double(values.size()))));
  return values[k];
}

LoopStats run_fixed_period_loop(const std::string& name, int characters, const std::function<void(long tick)>& work,
                                double seconds, std::int64_t period_ns) {
  LoopStats s;
  s.work = name;
  s.characters = characters;
  s.seconds = seconds;
  s.period_us = double(period_ns) / 1e3;
  const long total = std::max(1L, long(std::llround(seconds * 1e9 / double(period_ns))));
  std::vector<double> latency, compute;
  latency.reserve(std::size_t(total));
  compute.reserve(std::size_t(total));

  // what a real-time controller would do, where allowed: real-time priority, one CPU of its own, and
  // every page of the process locked in memory (no page fault inside a tick)
  int old_policy = SCHED_OTHER;
  sched_param old_param{};
  s.scheduling = try_realtime_priority(old_policy, old_param);
  cpu_set_t old_cpus;
  const int cpu = pin_to_last_cpu(old_cpus);
  if (cpu >= 0) s.scheduling += " cpu" + std::to_string(cpu);
  const bool locked = mlockall(MCL_CURRENT | MCL_FUTURE | MCL_ONFAULT) == 0;  // each page as first touched
  if (locked) s.scheduling += " mlock";

  // warm-up, untimed: the characters' data into the caches
  for (long k = 0; k < 20; ++k) work(-1 - k);

  // first release one period from now; tick k released at start + k * period
  const std::int64_t start = monotonic_ns() + period_ns;
  for (long k = 0; k < total; ++k) {
    const std::int64_t release = start + k * period_ns;
    sleep_until(release);
    const std::int64_t begin = monotonic_ns();
    work(k);
    const std::int64_t end = monotonic_ns();
    latency.push_back(double(end - release) / 1e3);
    compute.push_back(double(end - begin) / 1e3);
    ++s.ticks;
    // a miss: the work ended after the next release; skip the releases already past
    s.max_wakeup_us = std::max(s.max_wakeup_us, double(begin - release) / 1e3);
    if (end > release + period_ns) {
      ++s.misses;
      if (end - begin > period_ns)
        ++s.misses_overrun;
      else
        ++s.misses_late;
      const long late = long((end - release) / period_ns) - 1;
      s.skipped += late;
      k += late;
    }
  }
  if (locked) munlockall();
  if (cpu >= 0) pthread_setaffinity_np(pthread_self(), sizeof old_cpus, &old_cpus);
  pthread_setschedparam(pthread_self(), old_policy, &old_param);

  double sum = 0;
  for (double c : compute) sum += c;
  s.compute_mean_us = sum / double(compute.size());
  s.share = s.compute_mean_us / s.period_us;
  s.compute_p99_us = quantile(compute, 0.99);
  s.p50_us = quantile(latency, 0.50);
  s.p99_us = quantile(latency, 0.99);
  s.p999_us = quantile(latency, 0.999);
  s.max_us = latency.back();  // sorted by quantile()
  return s;
}

}  // namespace humandyn::bench
