// The figures of `humandyn bench` are real: the reference and every variant see the same states, the
// error function measures what it says, the full double variant agrees with the long double reference to
// round-off while float does not, the realistic motions are what docs/performance.md says they are, and
// the work-precision chart's tracked walk shows each integrator's order.
#include "bench/simulation.hpp"
#include "bench/variants.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/builders.hpp"
#include "support/fd_models.hpp"
#include "support/long_runs.hpp"
#include "support/motions.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <memory>

namespace test_bench {

namespace hb = humandyn::bench;
using namespace humandyn;

namespace {

const ModelDescription<double>& description() {
  static const ModelDescription<double> d = human_description(default_parameters());
  return d;
}

std::vector<hb::Workload> workloads() {
  return {hb::inverse_dynamics_workload(description(), hb::random_states(16, 200)),
          hb::inverse_dynamics_workload(description(), hb::realistic_motions(100))};
}

TEST(BenchErrors, ErrorStatsByHand) {
  const std::vector<hb::VectorLD> ref{(hb::VectorLD(2) << 1, -2).finished(), (hb::VectorLD(2) << 4, 0).finished()};
  const std::vector<Eigen::VectorXd> out{Eigen::Vector2d(1.5, -2), Eigen::Vector2d(4, 0)};
  const auto e = hb::error_stats(ref, out);
  EXPECT_DOUBLE_EQ(e.max_abs, 0.5);
  EXPECT_DOUBLE_EQ(e.rms_abs, std::sqrt(0.25 / 4));
  EXPECT_DOUBLE_EQ(e.max_rel, 0.25);  // |0.5| / max(|1|, |-2|)
  EXPECT_EQ(e.states, 2);
  // a different number of results, or a NaN among them, is never a small error (Eigen's largest
  // coefficient passes over a NaN that is not the first)
  EXPECT_TRUE(std::isinf(hb::error_stats(ref, {out[0]}).max_abs));
  const std::vector<Eigen::VectorXd> nan{Eigen::Vector2d(1.5, std::nan("")), Eigen::Vector2d(4, 0)};
  const auto e_nan = hb::error_stats(ref, nan);
  EXPECT_TRUE(std::isinf(e_nan.max_abs) && std::isinf(e_nan.max_rel) && std::isinf(e_nan.rms_abs));
}

TEST(BenchErrors, ReferenceIsTheLongDoubleModelOnTheWorkloadStates) {
  const HumanModel<long double> model(description().cast<long double>());
  Data<HumanModel<long double>> data(model);
  const auto motions = hb::realistic_motions(100);
  const auto w = hb::inverse_dynamics_workload(description(), motions);
  ASSERT_EQ(w.size(), motions.size());
  ASSERT_EQ(int(w.reference.size()), w.size());
  for (int s = 0; s < w.size(); ++s) {
    const auto k = std::size_t(s);
    // the workload's inputs are the motion's states, unchanged
    ASSERT_EQ(w.q[k], motions.q[k]);
    ASSERT_EQ(w.qd[k], motions.qd[k]);
    ASSERT_EQ(w.x[k], motions.qdd[k]);
    // its reference is the full model in long double on those states (static shape here, dynamic there)
    const hb::VectorLD tau = rnea(model, data, w.q[k].cast<long double>().eval(), w.qd[k].cast<long double>().eval(),
                                  w.x[k].cast<long double>().eval());
    EXPECT_LE(double((tau - w.reference[k]).cwiseAbs().maxCoeff()), 1e-15 * double(tau.cwiseAbs().maxCoeff()) + 1e-15);
  }
}

TEST(BenchErrors, FullDoubleIsAtRoundOffFloatIsNot) {
  const auto sd = std::make_shared<const HumanModel<double>>(description());
  const auto sf = std::make_shared<const HumanModel<float>>(description().cast<float>());
  const auto dd = std::make_shared<const AnyModel<double>>(description());
  const auto full_double = hb::rnea_variant<Terms::Full>("full double", "double", sd);
  const auto full_dynamic = hb::rnea_variant<Terms::Full>("full double dynamic", "double", dd);
  const auto full_float = hb::rnea_variant<Terms::Full>("full float", "float", sf);
  for (const auto& w : workloads()) {
    SCOPED_TRACE(w.name);
    const auto ed = hb::measure_error(full_double, w);
    const auto edyn = hb::measure_error(full_dynamic, w);
    const auto ef = hb::measure_error(full_float, w);
    EXPECT_EQ(ed.states, w.size());
    EXPECT_LE(ed.max_rel, 1e-9);
    EXPECT_LE(ed.max_abs, 1e-9);
    EXPECT_LE(edyn.max_rel, 1e-9);
    // float rounds: a relative error of order 1e-7 .. 1e-5, never zero
    EXPECT_GT(ef.max_rel, 1e-9);
    EXPECT_LT(ef.max_rel, 1e-4);
    EXPECT_GT(ef.rms_abs, 0.0);
  }
}

TEST(BenchErrors, VariantOnOtherStatesIsCaught) {
  // the same variant, handed the states shifted by one, must show a large error: the test above can fail
  const auto sd = std::make_shared<const HumanModel<double>>(description());
  const auto full_double = hb::rnea_variant<Terms::Full>("full double", "double", sd);
  for (auto w : workloads()) {
    std::rotate(w.q.begin(), w.q.begin() + 1, w.q.end());
    EXPECT_GT(hb::measure_error(full_double, w).max_rel, 1e-3) << w.name;
  }
}

TEST(BenchErrors, DroppedTermsCostAccuracyAndGravityOnlyMore) {
  const auto sd = std::make_shared<const HumanModel<double>>(description());
  const auto no_coriolis = hb::rnea_variant<Terms::NoCoriolis>("nc", "double", sd);
  const auto gravity = hb::rnea_variant<Terms::GravityOnly>("g", "double", sd);
  for (const auto& w : workloads()) {
    const auto enc = hb::measure_error(no_coriolis, w);
    const auto eg = hb::measure_error(gravity, w);
    EXPECT_GT(enc.max_abs, 1e-3) << w.name;  // the velocity products matter at these speeds
    EXPECT_GT(eg.rms_abs, enc.rms_abs) << w.name;
  }
}

TEST(BenchErrors, TimingRunsOnTheWorkload) {
  const auto sd = std::make_shared<const HumanModel<double>>(description());
  const auto v = hb::rnea_variant<Terms::Full>("full double", "double", sd);
  const auto w = workloads().front();
  const double ns = v.time(w, 0.002);
  EXPECT_GT(ns, 0.0);
  EXPECT_LT(ns, 1e6);
}

TEST(BenchErrors, ForwardDynamicsReferenceInvertsTheInverseDynamics) {
  const auto fd_desc = description();
  using FdModel = HumanModel<double>;
  const auto pd = std::make_shared<const FdModel>(fd_desc);
  const auto pf = std::make_shared<const Model<float, SeedShape>>(fd_desc.cast<float>());
  const auto mass_matrix = hb::forward_dynamics_variant<FdMethod::MassMatrix, Terms::Full>("mm", "double", pd);
  const auto articulated = hb::forward_dynamics_variant<FdMethod::Articulated, Terms::Full>("ab", "double", pd);
  const auto mass_matrix_f = hb::forward_dynamics_variant<FdMethod::MassMatrix, Terms::Full>("mmf", "float", pf);
  for (const auto& states : {hb::random_states(16, 200), hb::realistic_motions(100)}) {
    const auto w = hb::forward_dynamics_workload(fd_desc, states);
    ASSERT_EQ(w.size(), states.size());
    for (int s = 0; s < w.size(); ++s) {
      const auto k = std::size_t(s);
      ASSERT_EQ(w.q[k], states.q[k]);
      // the torques realise the states' accelerations: the reference gives them back
      EXPECT_LE(double((w.reference[k] - states.qdd[k].cast<long double>()).cwiseAbs().maxCoeff()),
                1e-9 * (1 + states.qdd[k].cwiseAbs().maxCoeff()));
    }
    EXPECT_LE(hb::measure_error(mass_matrix, w).max_rel, 1e-9) << w.name;
    EXPECT_LE(hb::measure_error(articulated, w).max_rel, 1e-9) << w.name;
    EXPECT_GT(hb::measure_error(mass_matrix_f, w).max_rel, 1e-9) << w.name;
  }
}

// ---- the realistic motions ----

// Central differences of q and qd against the exact derivatives.
void expect_consistent_derivatives(const hb::StateSet& s, double dt, double tol) {
  for (int i = 1; i + 1 < s.size(); ++i) {
    const auto k = std::size_t(i);
    const Eigen::VectorXd qd_fd = (s.q[k + 1] - s.q[k - 1]) / (2 * dt);
    const Eigen::VectorXd qdd_fd = (s.qd[k + 1] - s.qd[k - 1]) / (2 * dt);
    ASSERT_LE((qd_fd - s.qd[k]).cwiseAbs().maxCoeff(), tol) << s.name << " sample " << i;
    ASSERT_LE((qdd_fd - s.qdd[k]).cwiseAbs().maxCoeff(), 10 * tol) << s.name << " sample " << i;
  }
}

double peak(const std::vector<Eigen::VectorXd>& v) {
  double m = 0;
  for (const auto& x : v) m = std::max(m, x.cwiseAbs().maxCoeff());
  return m;
}

TEST(BenchMotions, WalkingIsSmoothPeriodicAndHumanFast) {
  const int n = 2200;
  const auto walk = hb::walking_cycle(n);
  ASSERT_EQ(walk.size(), n);
  expect_consistent_derivatives(walk, 1.1 / n, 1e-3);
  // human gait: joint speeds of a few rad/s, not tens
  EXPECT_GT(peak(walk.qd), 2.0);
  EXPECT_LT(peak(walk.qd), 8.0);
  EXPECT_LT(peak(walk.qdd), 100.0);
  // one whole cycle: the sample after the last is the first (central difference across the wrap)
  const double dt = 1.1 / n;
  EXPECT_LE(((walk.q[0] - walk.q[std::size_t(n - 2)]) / (2 * dt) - walk.qd[std::size_t(n - 1)]).cwiseAbs().maxCoeff(),
            1e-3);
  // the stance hip cancels ankle and knee: the trunk stays upright (the waist pitch is the only tilt)
  for (std::size_t k = 0; k < walk.q.size(); k += 50)
    EXPECT_NEAR(walk.q[k][0] + walk.q[k][1] + walk.q[k][3], 0.0, 1e-12);
}

TEST(BenchMotions, ArmRaiseEndsWithTheLeftArmForwardAndHorizontal) {
  const int n = 1200;
  const auto raise = hb::arm_raise(n);
  expect_consistent_derivatives(raise, 1.2 / (n - 1), 1e-3);
  // rest to rest
  EXPECT_EQ(raise.qd.front().cwiseAbs().maxCoeff(), 0.0);
  EXPECT_NEAR(raise.qd.back().cwiseAbs().maxCoeff(), 0.0, 1e-12);
  EXPECT_NEAR(peak(raise.qd), 1.875 * 1.5707963267948966 / 1.2, 1e-3);  // minimum jerk: 15/8 of the mean speed
  // the left wrist ends in front of the shoulder, at its height
  const HumanModel<double> model(description());
  Data<HumanModel<double>> data(model);
  forward_kinematics(model, data, Eigen::Matrix<double, 16, 1>(raise.q.back()));
  const Eigen::Vector3d shoulder = data.oMi[6].p, wrist = data.oMi[8].p;  // frames 7 and 9: shoulder, wrist
  EXPECT_GT(wrist.x() - shoulder.x(), 0.4);
  EXPECT_NEAR(wrist.z(), shoulder.z(), 0.25 * (wrist - shoulder).norm());  // elbow bent by 0.3 rad
}

// The work-precision chart's tracked walk: started on the walking cycle with its inverse-dynamics
// feed-forward evaluated at each stage, the exact motion is the cycle itself, so the end-state error
// against it measures the integrator alone: each halving of h cuts it 16x for RK4, 2x for the first-order
// steps. (The sanitizer build runs the longest step of each integrator alone, support/long_runs.hpp, its
// error below a bound: 6.4e-9 rad for RK4, 6.1e-4 to 2.3e-3 rad for the others in a GCC build. The orders
// are asserted in the other builds.)
TEST(WorkPrecision, TrackedWalkAtEachIntegratorsOrder) {
  using HD = HumanModel<double>;
  const HD model(human_description(default_parameters()));
  const double T = bench::scenario_duration(bench::Scenario::TrackedWalk);
  HD::JointVector q_end, qd_end, qdd_end;
  bench::evaluate_harmonics(bench::walking_terms(), bench::walking_period, T, q_end, qd_end, qdd_end);
  const auto error = [&](Integrator m, int steps) {
    bench::ScenarioRun<HD> run(model, bench::Scenario::TrackedWalk);
    const bool ok = m == Integrator::RungeKutta4     ? run.run<Integrator::RungeKutta4>(steps)
                    : m == Integrator::BackwardEuler ? run.run<Integrator::BackwardEuler>(steps)
                    : m == Integrator::ImplicitPD    ? run.run<Integrator::ImplicitPD>(steps)
                                                     : run.run<Integrator::SemiImplicitEuler>(steps);
    return ok ? (run.state().q - q_end).cwiseAbs().maxCoeff() : std::numeric_limits<double>::infinity();
  };
  for (Integrator m :
       {Integrator::SemiImplicitEuler, Integrator::RungeKutta4, Integrator::ImplicitPD, Integrator::BackwardEuler}) {
    const bool rk4 = m == Integrator::RungeKutta4;
    const int n0 = rk4 ? 1760 : 2200;  // h = 1/1600 s (RK4 runs away at 1/400 s), 1/2000 s
    double previous = error(m, n0);
    if (humandyn::testing::short_runs) {
      EXPECT_LT(previous, rk4 ? 1e-7 : 5e-3) << integrator_name(m) << " h=" << T / n0 << ": rad";
      continue;
    }
    for (int n : {2 * n0, 4 * n0}) {
      const double e = error(m, n), ratio = previous / e, expected = rk4 ? 16 : 2;
      std::printf("%s h=%.2e: error %.3e, ratio %.2f\n", integrator_name(m), T / n, e, ratio);
      EXPECT_GT(ratio, 0.75 * expected) << integrator_name(m) << " h=" << T / n;
      EXPECT_LT(ratio, 1.35 * expected) << integrator_name(m) << " h=" << T / n;
      previous = e;
    }
  }
}

}  // namespace

}  // namespace test_bench
