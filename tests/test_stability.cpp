// The stiff-and-extreme suite (stability_suite.hpp), case by case, with the expectations asserted.
// `humandyn stability` prints the same rows, and the integrators' orders of convergence on its swing.
#include "stability_suite.hpp"
#include "support/long_runs.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <utility>

namespace test_stability {

namespace {

using namespace humandyn;
using namespace humandyn::stability;

// The cases simulate seconds to a minute each, which takes minutes apiece under the sanitizer build's -O0
// instrumentation (support/long_runs.hpp). There the tests of this file that run them skip, and the
// servo, the swing, the flail, fast motion and the round trips run over short spans instead
// (ShortSpans.CasesHoldOverAShortSpan), with the bad states and the goal's counter-example; the full runs
// and what they assert (the held loads, the convergence orders) are the other builds'.
#define HUMANDYN_SKIP_IN_SHORT_RUNS()                                                                    \
  do {                                                                                                   \
    if (humandyn::testing::short_runs) GTEST_SKIP() << "runs of seconds to a minute: the other builds'"; \
  } while (false)

std::string show(const Row& r) {
  return r.group + " / " + r.name + " / " + r.method + " / " + r.scalar + " / h=" + std::to_string(r.dt) +
         " / status: " + r.status + " / error " + std::to_string(r.error) + " / " + r.note;
}

// A failure is a reported status or a non-converged run; never a NaN passed on.
void expect_reported(const Row& r) {
  if (r.stable) return;
  EXPECT_TRUE(r.status != "ok" || std::isfinite(r.error)) << show(r);
}

// Stiff servos: the implicit step holds everywhere; explicit steps hold where the linearised step's
// spectral radius is below one with ω h well inside the limit, and fail (reported) where it predicts growth
// of 1e6 or more over the run.
TEST(StiffServo, ImplicitAlwaysHoldsExplicitFailsWhereTheoryPredicts) {
  HUMANDYN_SKIP_IN_SHORT_RUNS();
  int predicted_unstable = 0, predicted_stable_explicit = 0;
  for (double kp : servo_kp)
    for (double h : servo_dt)
      for (Integrator m : integrators) {
        const Row r = stiff_servo(m, kp, h);
        expect_reported(r);
        if (r.expect == Expect::Stable) {
          EXPECT_TRUE(r.stable) << show(r);
        }
        if (r.expect == Expect::Unstable) {
          EXPECT_FALSE(r.stable) << show(r);
          ++predicted_unstable;
        }
        if (m != Integrator::ImplicitPD && r.expect == Expect::Stable) ++predicted_stable_explicit;
      }
  // the grid spans both sides of the explicit limit
  EXPECT_GT(predicted_unstable, 10);
  EXPECT_GT(predicted_stable_explicit, 3);
}

// The implicit step converges at every stiffness: the end state at h = 1/240, 1/480, 1/960 against the
// same servo at 1/7680 s; each halving of h cuts the error (first order: about 2x once ω h is small).
TEST(StiffServo, ImplicitConvergesAsStepShrinks) {
  HUMANDYN_SKIP_IN_SHORT_RUNS();
  for (double kp : servo_kp) {
    Vec reference, q;
    ASSERT_TRUE(stiff_servo(Integrator::ImplicitPD, kp, 1.0 / 7680, servo_duration, &reference).stable);
    double previous = std::numeric_limits<double>::infinity();
    for (double h : {1.0 / 240, 1.0 / 480, 1.0 / 960}) {
      const Row r = stiff_servo(Integrator::ImplicitPD, kp, h, servo_duration, &q);
      ASSERT_TRUE(r.stable) << show(r);
      const double error = (q - reference).cwiseAbs().maxCoeff();
      std::printf("kp %.0e h 1/%.0f: end-state error %.3e\n", kp, 1 / h, error);
      EXPECT_LT(error, previous / 1.5) << show(r);
      previous = error;
    }
  }
}

// Light and heavy bodies: forward dynamics still inverts inverse dynamics to 1e-8 with both methods,
// and holding the standing pose goes as the linearised servo predicts (the implicit step always holds).
TEST(LightHeavy, RoundTripAndHold) {
  HUMANDYN_SKIP_IN_SHORT_RUNS();
  for (Load load : {Load::Nominal, Load::LightExtremities, Load::HeavyHand}) {
    for (FdMethod f : {FdMethod::MassMatrix, FdMethod::Articulated}) {
      const Row r = light_heavy_round_trip(load, f);
      EXPECT_TRUE(r.stable) << show(r);
      EXPECT_LT(r.error, 1e-8) << show(r);
    }
    for (Integrator m : integrators) {
      const Row r = light_heavy_hold(load, m);
      expect_reported(r);
      if (r.expect == Expect::Stable) {
        EXPECT_TRUE(r.stable) << show(r);
      }
      if (r.expect == Expect::Unstable) {
        EXPECT_FALSE(r.stable) << show(r);
      }
    }
  }
  // the paper model (Table 1's massless pelvis): M is singular, explicit steps fail (reported), the
  // implicit steps hold
  for (Integrator m : integrators) {
    const Row r = light_heavy_hold(Load::PaperModel, m);
    expect_reported(r);
    EXPECT_EQ(r.stable, implicit(m)) << show(r);
  }
  // the extreme masses do make M ill-conditioned
  const auto states = random_states(20, 3.14159265358979, 10, 100);
  EXPECT_GT(max_condition(load_model(Load::LightExtremities), states),
            100 * max_condition(load_model(Load::Nominal), states));
}

// Fast motion: the round trip holds in double (1e-8) and float (1e-3); passive stepping from 100 rad/s
// (the distal links whipped to thousands of rad/s) ends cleanly or reports, and RK4 at 10 kHz keeps
// the energy.
TEST(FastMotion, RoundTripAndStepping) {
  HUMANDYN_SKIP_IN_SHORT_RUNS();
  for (FdMethod f : {FdMethod::MassMatrix, FdMethod::Articulated}) {
    const Row d = fast_round_trip<double>(f);
    EXPECT_LT(d.error, 1e-8) << show(d);
    const Row s = fast_round_trip<float>(f);
    EXPECT_LT(s.error, 1e-3) << show(s);
  }
  for (double h : {1e-3, 1e-4})
    for (Integrator m : integrators) {
      const Row d = fast_passive<double>(m, h);
      expect_reported(d);
      const Row s = fast_passive<float>(m, h);
      expect_reported(s);
      if (m == Integrator::RungeKutta4 && h <= 1e-4) {
        EXPECT_TRUE(d.stable && s.stable) << show(d) << "\n" << show(s);
        EXPECT_LT(d.energy_drift, 1e-4) << show(d);
        EXPECT_LT(s.energy_drift, 1e-3) << show(s);
      }
    }
}

// The long passive swing: RK4 at 1 kHz keeps the energy within 1e-4 of the swing's energy over 60 s.
TEST(PassiveSwing, Rk4SixtySecondsAtOneKilohertz) {
  HUMANDYN_SKIP_IN_SHORT_RUNS();
  const Row r = passive_swing(Integrator::RungeKutta4, 1.0 / 1000);
  ASSERT_TRUE(r.stable) << show(r);
  EXPECT_LT(r.energy_drift, 1e-4) << show(r);
}

// Over the first 2 s, before the swing turns chaotic and runs with different h part ways, halving h
// cuts RK4's drift about 16x and semi-implicit Euler's about 2x.
TEST(PassiveSwing, DriftFallsAtEachIntegratorsOrder) {
  HUMANDYN_SKIP_IN_SHORT_RUNS();
  const Row r250 = passive_swing(Integrator::RungeKutta4, 1.0 / 250, 2);
  const Row r500 = passive_swing(Integrator::RungeKutta4, 1.0 / 500, 2);
  const Row r1000 = passive_swing(Integrator::RungeKutta4, 1.0 / 1000, 2);
  for (const auto& [coarse, fine] : {std::pair{&r250, &r500}, std::pair{&r500, &r1000}}) {
    const double ratio = coarse->energy_drift / fine->energy_drift;
    EXPECT_GT(ratio, 8) << show(*coarse) << "\n" << show(*fine);
    EXPECT_LT(ratio, 32) << show(*coarse) << "\n" << show(*fine);
  }
  const Row e1000 = passive_swing(Integrator::SemiImplicitEuler, 1.0 / 1000, 2);
  const Row e4000 = passive_swing(Integrator::SemiImplicitEuler, 1.0 / 4000, 2);
  ASSERT_TRUE(e1000.stable && e4000.stable) << show(e1000) << "\n" << show(e4000);
  const double ratio = e1000.energy_drift / e4000.energy_drift;  // two halvings: about 4
  EXPECT_GT(ratio, 2) << show(e1000) << "\n" << show(e4000);
  EXPECT_LT(ratio, 8) << show(e1000) << "\n" << show(e4000);
}

// Semi-implicit Euler in joint coordinates is not symplectic here (M depends on q): over 60 s at 1 kHz
// its energy error grows, and wherever it runs away the step says so.
TEST(PassiveSwing, SymplecticEulerEndsCleanlyOrReports) {
  HUMANDYN_SKIP_IN_SHORT_RUNS();
  const Row r = passive_swing(Integrator::SemiImplicitEuler, 1.0 / 1000);
  expect_reported(r);
  if (!r.stable) {
    EXPECT_NE(r.status.find("run away"), std::string::npos) << show(r);
  }
}

// The falling upright body (chaotic, past 300 rad/s): whatever happens is a clean run or a reported
// error; RK4 at 1 kHz stays finite for 5 s, and halving its step cuts the drift (at least 4x; the
// fourth-order rate is 16x, the chaotic runs part ways).
TEST(Flail, EndsCleanlyOrReports) {
  HUMANDYN_SKIP_IN_SHORT_RUNS();
  for (Integrator m : integrators) {
    const Row r = flail(m, 1.0 / 240, 5);
    expect_reported(r);
    if (r.stable) {
      EXPECT_TRUE(std::isfinite(r.energy_drift)) << show(r);
    }
  }
  const Row rk4 = flail(Integrator::RungeKutta4, 1.0 / 1000, 5);
  const Row rk4_fine = flail(Integrator::RungeKutta4, 1.0 / 2000, 5);
  ASSERT_TRUE(rk4.stable && rk4_fine.stable) << show(rk4) << "\n" << show(rk4_fine);
  EXPECT_LT(rk4_fine.energy_drift, rk4.energy_drift / 4) << show(rk4) << "\n" << show(rk4_fine);
}

// Backward Euler's goal: the 60-s hang (0.3 rad push) and the 10-s upright flail at every step from 1 ms to
// 1/30 s never run away, never fail a step, and their energy never rises above the start by more than 1e-6
// of the case's scale; the energy they lose per simulated second is reported (and is positive). The same
// runs as `humandyn stability`'s rows (about a second of computing in all).
TEST(BackwardEuler, HangAndFlailNeitherRunAwayNorGainEnergy) {
  HUMANDYN_SKIP_IN_SHORT_RUNS();
  for (double h : servo_dt)
    for (const Row& r : {passive_swing(Integrator::BackwardEuler, h), flail(Integrator::BackwardEuler, h)}) {
      std::printf("%s h=1/%.0f: max |qd| %.3g rad/s, rise %.2e, dissipation %.3g W\n", r.group.c_str(), 1 / h, r.error,
                  r.energy_rise, r.dissipation);
      EXPECT_EQ(r.status, "ok") << show(r);
      EXPECT_NEAR(r.t_end, r.group == "flail" ? 10.0 : swing_duration, 1e-9) << show(r);
      EXPECT_LE(r.energy_rise, energy_rise_bound) << show(r);
      EXPECT_GT(r.dissipation, 0) << show(r);
      EXPECT_TRUE(r.stable) << show(r);
    }
}

// The semi-implicit step on the same runs does not reach the goal: the goal can fail.
TEST(BackwardEuler, TheGoalIsOneTheImplicitPdStepMisses) {
  const Row r = flail(Integrator::ImplicitPD, 1.0 / 60);
  EXPECT_TRUE(r.status != "ok" || r.energy_rise > energy_rise_bound) << show(r);
}

// Order of convergence on the suite's smooth swing: halving h cuts the error about 2x (first order:
// Euler, implicit PD, backward Euler) or 16x (RK4).
TEST(Convergence, EachIntegratorAtItsOrder) {
  HUMANDYN_SKIP_IN_SHORT_RUNS();
  for (Integrator m : stability::integrators) {
    const auto rows = stability::convergence(m);
    ASSERT_EQ(rows.size(), 3u);
    const double order = m == Integrator::RungeKutta4 ? 4 : 1;
    for (std::size_t k = 1; k < rows.size(); ++k) {
      ASSERT_TRUE(rows[k].stable) << rows[k].method;
      const double ratio = rows[k - 1].error / rows[k].error;
      const double expected = std::pow(2.0, order);
      EXPECT_GT(ratio, 0.75 * expected) << rows[k].method << " h=" << rows[k].dt;
      EXPECT_LT(ratio, 1.35 * expected) << rows[k].method << " h=" << rows[k].dt;
    }
  }
}

// The cases over a tenth of a second or less (the sanitizer build's view of the suite's code; cheap in the
// others): a clean run or a reported error, never a NaN passed on; the implicit steps hold the stiff servo,
// backward Euler runs the swing and the flail to the end without gaining energy, and the round trips hold.
TEST(ShortSpans, CasesHoldOverAShortSpan) {
  const double h = 1.0 / 240, span = 0.1;
  for (Integrator m : integrators) {
    const Row servo = stiff_servo(m, 1e4, h, span);
    expect_reported(servo);
    if (implicit(m)) {
      EXPECT_TRUE(servo.stable) << show(servo);
    }
    for (const Row& r : {passive_swing(m, h, span), flail(m, h, span)}) {
      expect_reported(r);
      if (m == Integrator::BackwardEuler) {
        EXPECT_EQ(r.status, "ok") << show(r);
        EXPECT_NEAR(r.t_end, span, 1e-12) << show(r);
        EXPECT_LE(r.energy_rise, energy_rise_bound) << show(r);
      }
    }
    for (const Row& r : {fast_passive<double>(m, 1e-3, 0.01), fast_passive<float>(m, 1e-3, 0.01)}) expect_reported(r);
  }
  for (FdMethod f : {FdMethod::MassMatrix, FdMethod::Articulated}) {
    for (const Row& r : {light_heavy_round_trip(Load::HeavyHand, f), fast_round_trip<double>(f)}) {
      EXPECT_TRUE(r.stable) << show(r);
      EXPECT_LT(r.error, 1e-8) << show(r);
    }
    const Row single = fast_round_trip<float>(f);
    EXPECT_LT(single.error, 1e-3) << show(single);
  }
}

TEST(BadState, RefusedAndUntouched) {
  for (const BadInput& bad : bad_inputs)
    for (Integrator m : integrators) {
      const Row r = bad_state(m, bad);
      EXPECT_TRUE(r.stable) << show(r);
    }
}

}  // namespace

}  // namespace test_stability
