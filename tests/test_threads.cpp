// One const model shared by several threads, each with its own workspace: every thread gives bitwise
// the results of a single thread (inverse dynamics, forward dynamics by both methods, one Runge-Kutta
// step) over 10,000 random states (400 in the AddressSanitizer build, support/long_runs.hpp). Nothing
// in the model is written after construction, so nothing is shared but what is read; ThreadSanitizer
// checks that claim when this test runs under it. And the crowds' kept threads (CrowdThreads) hand out
// their ranges and wait for them without a race.
#include "humandyn/builders.hpp"
#include "humandyn/crowd.hpp"
#include "humandyn/humandyn.hpp"
#include "humandyn/integrators.hpp"
#include "support/long_runs.hpp"

#include <gtest/gtest.h>

#include <array>
#include <chrono>
#include <cstring>
#include <random>
#include <thread>
#include <vector>

namespace test_threads {

namespace {

using namespace humandyn;
using Model = HumanModel<double>;
using Vec = Model::JointVector;

constexpr int n_states = humandyn::testing::long_run(10000, 400);
constexpr int n_threads = 4;
constexpr int nj = Model::nj;

struct Input {
  Vec q, qd, qdd, tau;
};

// Per state, side by side: tau = RNEA(q, qd, qdd), qdd from the mass matrix and from ABA at
// (q, qd, tau), then q and qd after one RK4 step of 1 ms under tau.
constexpr int outputs = 5 * nj;

std::vector<Input> random_inputs(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const auto draw = [&](double scale) {
    Vec v;
    for (int i = 0; i < nj; ++i) v[i] = scale * u(rng);
    return v;
  };
  std::vector<Input> in(n_states);
  for (auto& s : in) s = {draw(3.14), draw(10.0), draw(50.0), draw(30.0)};
  return in;
}

// The results of states first, first + 1, ... (all of them, wrapping around) into out[k * outputs ...],
// with a workspace of this call's own.
void compute(const Model& model, const std::vector<Input>& in, int first, std::vector<double>& out) {
  Data<Model> data(model);
  StepWorkspace<Model> ws(model);
  State<Model> x(model);
  out.assign(std::size_t(n_states) * outputs, 0.0);
  for (int n = 0; n < n_states; ++n) {
    const int k = (first + n) % n_states;
    const Input& s = in[std::size_t(k)];
    double* o = out.data() + std::size_t(k) * outputs;
    const auto put = [&](const Vec& v) {
      std::memcpy(o, v.data(), sizeof(double) * nj);
      o += nj;
    };
    put(rnea(model, data, s.q, s.qd, s.qdd));
    put(forward_dynamics<FdMethod::MassMatrix>(model, data, s.q, s.qd, s.tau));
    put(forward_dynamics<FdMethod::Articulated>(model, data, s.q, s.qd, s.tau));
    x.q = s.q;
    x.qd = s.qd;
    const StepStatus status = step<Integrator::RungeKutta4>(model, ws, x, s.tau, 1e-3);
    ASSERT_TRUE(status.ok()) << "state " << k << ": " << describe(status, model);
    put(x.q);
    put(x.qd);
  }
}

TEST(Threads, FourThreadsSharingOneConstModelGiveBitwiseTheResultsOfOne) {
  const Model model = default_model<double>();
  const std::vector<Input> in = random_inputs(2024);

  std::vector<double> alone;
  compute(model, in, 0, alone);

  // each thread runs every state, starting at a different one, so that different states of the same
  // model are computed at the same time
  std::vector<std::vector<double>> results(n_threads);
  std::vector<std::thread> threads;
  for (int t = 0; t < n_threads; ++t)
    threads.emplace_back([&, t] { compute(model, in, t * n_states / n_threads, results[std::size_t(t)]); });
  for (auto& th : threads) th.join();

  for (int t = 0; t < n_threads; ++t) {
    ASSERT_EQ(results[std::size_t(t)].size(), alone.size()) << "thread " << t;
    for (int k = 0; k < n_states; ++k) {
      const std::size_t at = std::size_t(k) * outputs;
      ASSERT_EQ(std::memcmp(results[std::size_t(t)].data() + at, alone.data() + at, sizeof(double) * outputs), 0)
          << "thread " << t << ", state " << k << " differs from the single thread's";
    }
  }
  // and the results are real numbers, not a shared failure: every step succeeded (asserted in compute)
  // and the torques of the first state are not all zero
  EXPECT_NE(Eigen::Map<const Vec>(alone.data()).norm(), 0.0);
}

// Thousands of back-to-back runs (500 in the AddressSanitizer build) of a crowd over kept threads,
// whose waiting threads sleep at once or poll first: each range by the thread it names, every character
// exactly once per run, nothing lost between runs; runs after the workers went to sleep; an empty crowd;
// a team of one; a team ended at once.
TEST(Threads, CrowdThreadsRunEveryRangeOnceWithoutARace) {
  using std::chrono::microseconds, std::chrono::nanoseconds;
  for (const nanoseconds spin : {nanoseconds(0), nanoseconds(microseconds(200))})
    for (int threads : {1, 2, 4}) {
      CrowdThreads team(threads, spin);
      constexpr std::size_t n = 1001;
      constexpr int width = 8, runs = humandyn::testing::long_run(2000, 500);
      std::vector<int> visits(n, 0);
      std::array<long, 4> calls{};
      for (int r = 0; r < runs; ++r)
        team.run(n, width, [&](int t, std::size_t begin, std::size_t end) {
          ++calls[std::size_t(t)];
          for (std::size_t c = begin; c < end; ++c) ++visits[c];
        });
      for (std::size_t c = 0; c < n; ++c)
        ASSERT_EQ(visits[c], runs) << "character " << c << ", " << threads << " threads";
      for (int t = 0; t < threads; ++t) EXPECT_EQ(calls[std::size_t(t)], runs) << "range " << t;
      int empty_calls = 0;
      team.run(0, width, [&](int, std::size_t begin, std::size_t end) {
        EXPECT_EQ(begin, end);
        ++empty_calls;
      });
      EXPECT_EQ(empty_calls, 1) << "an empty crowd is one empty range, on the caller";
    }
  {
    CrowdThreads team(2, microseconds(50));
    std::vector<int> visits(100, 0);
    for (int r = 0; r < 20; ++r) {
      std::this_thread::sleep_for(microseconds(500));  // (longer than the polling: the worker sleeps)
      team.run(visits.size(), 8, [&](int, std::size_t begin, std::size_t end) {
        for (std::size_t c = begin; c < end; ++c) ++visits[c];
      });
    }
    for (std::size_t c = 0; c < visits.size(); ++c) ASSERT_EQ(visits[c], 20) << "character " << c;
  }
  EXPECT_EQ(CrowdThreads(0).size(), 1);
  for (int k = 0; k < 100; ++k) CrowdThreads ended_at_once(4);
}

}  // namespace

}  // namespace test_threads
