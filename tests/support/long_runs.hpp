// The suites' long runs, shortened in the sanitizer build.
//
// A few tests simulate tens of seconds or sweep thousands of states: seconds in an optimised build,
// minutes under AddressSanitizer's -O0 instrumentation. The asan preset sets
// HUMANDYN_TEST_SHORT_RUNS (tests/CMakeLists.txt); those tests then run a shorter span of the same code
// with the checks that hold over it, so that the sanitizers see its paths within CI's time. Every other
// build runs them in full, and the assertions that need the full spans (the 10-s tumble, 1000-state round
// trips, the stiff-and-extreme suite's cases, the integrators' orders on the tracked walk) hold there.
#pragma once

namespace humandyn::testing {

#ifdef HUMANDYN_TEST_SHORT_RUNS
inline constexpr bool short_runs = true;
#else
inline constexpr bool short_runs = false;
#endif

/// `full` in an ordinary build, `sanitized` in the sanitizer build (HUMANDYN_TEST_SHORT_RUNS).
template <class T>
constexpr T long_run(T full, T sanitized) noexcept {
  return short_runs ? sanitized : full;
}

}  // namespace humandyn::testing
