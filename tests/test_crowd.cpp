// Characters in SIMD lanes (crowd.hpp, detail/batch.hpp): every lane of every batched algorithm equals
// the scalar algorithm for that character, on random batches whose lanes reach |q| = 1e3 rad and
// |q̇| = 100 rad/s — forward kinematics, inverse dynamics with each Terms, the mass matrix, its LTDL
// factors and solve, forward dynamics, the servo — for one model broadcast and for a different body
// per lane. The checked crowd step gives each character the scalar step's status and state (a crowd of
// 1001, poisoned characters among them, which stay as they were), allocates nothing, and 1, 2 and 4
// threads give bitwise the same crowd.
#include "humandyn/builders.hpp"
#include "humandyn/crowd.hpp"
#include "humandyn/crowd_kernels.hpp"
#include "humandyn/humandyn.hpp"
#include "support/long_runs.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <string>
#include <thread>
#include <vector>

namespace test_crowd {

namespace {

using namespace humandyn;
using humandyn::testing::long_run;
using humandyn::testing::short_runs;

// |a - b|∞ / |b|∞: normwise relative difference of a lane's result from the scalar one
template <class A, class B>
double relative(const Eigen::MatrixBase<A>& a, const Eigen::MatrixBase<B>& b) {
  const double scale = double(b.cwiseAbs().maxCoeff());
  const double diff = double((a.template cast<double>() - b.template cast<double>()).cwiseAbs().maxCoeff());
  return scale > 0 ? diff / scale : diff;
}

template <class B>
struct Crowd : ::testing::Test {
  using Lanes_ = B;
  using T = typename detail::lanes<B>::value_type;
  using Scalar = HumanModel<T>;
  using Batch = BatchModel<B>;
  using Vec = typename Scalar::JointVector;
  static constexpr int W = Batch::width;
  static constexpr int nj = Scalar::nj;
  static constexpr double tol = std::is_same_v<T, double> ? 1e-12 : 1e-5;

  // lane l's q, q̇, q̈, τ: lanes 0 and 1 at the extremes (|q| to 1e3 rad, |q̇| to 100 rad/s), the others
  // human-sized
  struct Lanes {
    std::vector<Vec> q, qd, qdd, tau;
  };
  static Lanes random_lanes(unsigned seed) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    const auto draw = [&](double scale) {
      Vec v;
      for (int i = 0; i < nj; ++i) v[i] = T(scale * u(rng));
      return v;
    };
    Lanes x;
    for (int l = 0; l < W; ++l) {
      const bool extreme = l % 4 < 2;
      x.q.push_back(draw(extreme ? 1e3 : 3.0));
      x.qd.push_back(draw(extreme ? 100.0 : 5.0));
      x.qdd.push_back(draw(50.0));
      x.tau.push_back(draw(30.0));
    }
    return x;
  }
  static typename Batch::JointVector gather(const std::vector<Vec>& v) {
    typename Batch::JointVector b;
    for (int l = 0; l < W; ++l) detail::put_lane(b, l, v[std::size_t(l)]);
    return b;
  }

  // every batched algorithm against the scalar one, lane by lane, each lane with its own model
  static void expect_lanes_equal_scalar(const Batch& batch, const std::vector<const Scalar*>& models, unsigned seed) {
    const Lanes x = random_lanes(seed);
    const auto q = gather(x.q), qd = gather(x.qd), qdd = gather(x.qdd), tau = gather(x.tau);
    Data<Batch> bd(batch);
    double worst = 0;
    const auto check = [&](const auto& lane_result, const auto& scalar_result, const char* what, int l) {
      const double e = relative(lane_result, scalar_result);
      worst = std::max(worst, e);
      EXPECT_LE(e, tol) << what << ", lane " << l << " of " << W;
    };

    forward_kinematics(batch, bd, q);
    for (int l = 0; l < W; ++l) {
      const Scalar& m = *models[std::size_t(l)];
      Data<Scalar> d(m);
      forward_kinematics(m, d, x.q[std::size_t(l)]);
      for (int i = 0; i < nj; ++i) {
        check(lane(bd.oMi[std::size_t(i)].R, l), d.oMi[std::size_t(i)].R, "link rotation", l);
        check(lane(bd.oMi[std::size_t(i)].p, l), d.oMi[std::size_t(i)].p, "link origin", l);
        check(lane(bd.com_world[std::size_t(i)], l), d.com_world[std::size_t(i)], "link centre of mass", l);
      }
      check(lane(bd.com, l), d.com, "centre of mass", l);
    }

    const auto each_rnea = [&]<Terms terms>(std::integral_constant<Terms, terms>, const char* what) {
      const typename Batch::JointVector bt = rnea<terms>(batch, bd, q, qd, qdd);
      for (int l = 0; l < W; ++l) {
        const Scalar& m = *models[std::size_t(l)];
        Data<Scalar> d(m);
        check(lane(bt, l), rnea<terms>(m, d, x.q[std::size_t(l)], x.qd[std::size_t(l)], x.qdd[std::size_t(l)]), what,
              l);
      }
    };
    each_rnea(std::integral_constant<Terms, Terms::Full>{}, "rnea Full");
    each_rnea(std::integral_constant<Terms, Terms::NoCoriolis>{}, "rnea NoCoriolis");
    each_rnea(std::integral_constant<Terms, Terms::GravityOnly>{}, "rnea GravityOnly");

    // the mass matrix, its factors and a solve; then forward dynamics (M, h, LTDL) in one call
    crba(batch, bd, q);
    factorize_mass_matrix(batch, bd);
    typename Batch::JointVector x_b = tau;
    solve_mass_matrix(batch, bd, x_b);
    for (int l = 0; l < W; ++l) {
      const Scalar& m = *models[std::size_t(l)];
      Data<Scalar> d(m);
      check(lane(bd.M, l), crba(m, d, x.q[std::size_t(l)]), "mass matrix", l);
      factorize_mass_matrix(m, d);
      check(lane(bd.L, l), d.L, "L", l);
      check(lane(bd.D, l), d.D, "D", l);
      Vec xs = x.tau[std::size_t(l)];
      solve_mass_matrix(m, d, xs);
      check(lane(x_b, l), xs, "solve", l);
    }
    forward_dynamics(batch, bd, q, qd, tau);
    for (int l = 0; l < W; ++l) {
      const Scalar& m = *models[std::size_t(l)];
      Data<Scalar> d(m);
      check(lane(bd.qdd, l), forward_dynamics(m, d, x.q[std::size_t(l)], x.qd[std::size_t(l)], x.tau[std::size_t(l)]),
            "forward dynamics", l);
      check(lane(bd.nle, l), d.nle, "bias", l);
    }
    std::cout << "  lanes of width " << W << ", seed " << seed << ": largest relative difference " << worst << "\n";
  }
};

// The native widths, and 8 doubles whatever the instruction set. Clang refuses an Eigen matrix of a batch
// aligned beyond Eigen's static alignment (16 bytes without AVX; GCC aligns such a matrix as its element
// needs), so there 8 doubles are tested where the instruction set makes them native (AVX-512).
#if defined(__clang__) && EIGEN_MAX_STATIC_ALIGN_BYTES < 64
using Batches = ::testing::Types<NativeBatch<double>, NativeBatch<float>>;
#else
using Batches = ::testing::Types<NativeBatch<double>, FixedBatch<double, 8>, NativeBatch<float>>;
#endif
TYPED_TEST_SUITE(Crowd, Batches);

TYPED_TEST(Crowd, EveryAlgorithmLaneByLaneEqualsScalarOneModel) {
  using F = TestFixture;
  const auto model = default_model<typename F::T>();
  const typename F::Batch batch(model);
  std::vector<const typename F::Scalar*> models(F::W, &model);
  for (unsigned seed = 1; seed <= 20; ++seed) F::expect_lanes_equal_scalar(batch, models, seed);
}

TYPED_TEST(Crowd, EveryAlgorithmLaneByLaneEqualsScalarOneBodyPerLane) {
  using F = TestFixture;
  std::vector<typename F::Scalar> bodies;
  for (int l = 0; l < F::W; ++l)
    bodies.push_back(human_model<typename F::T>(de_leva_parameters(
        1.5 + 0.05 * l, 50.0 + 4.0 * l, l % 2 ? anthropometry::Sex::Female : anthropometry::Sex::Male)));
  std::vector<const typename F::Scalar*> models;
  for (const auto& b : bodies) models.push_back(&b);
  const typename F::Batch batch{std::span<const typename F::Scalar* const>(models)};
  for (unsigned seed = 100; seed < 110; ++seed) F::expect_lanes_equal_scalar(batch, models, seed);
}

TYPED_TEST(Crowd, ServoLaneByLaneEqualsScalar) {
  using F = TestFixture;
  using Value = typename F::T;
  const auto model = default_model<Value>();
  const typename F::Batch batch(model);
  PdServo<typename F::Scalar> s(model);
  PdServo<typename F::Batch> bs(batch);
  const auto x = F::random_lanes(7);
  std::vector<PdServo<typename F::Scalar>> per_lane;
  for (int l = 0; l < F::W; ++l) {
    s.kp = x.tau[std::size_t(l)].cwiseAbs() * Value(10);
    s.kd = x.tau[std::size_t(l)].cwiseAbs();
    s.q_ref = x.qdd[std::size_t(l)] / Value(50);
    s.qd_ref = x.qdd[std::size_t(l)] / Value(25);
    s.damping.setConstant(Value(0.5));
    s.q_min.setConstant(Value(-0.5));
    s.q_max.setConstant(Value(0.5));  // lanes inside, below and above the limits
    s.limit_stiffness.setConstant(Value(200));
    per_lane.push_back(s);
    for (auto [b, v] : {std::pair{&bs.kp, &s.kp},
                        {&bs.kd, &s.kd},
                        {&bs.q_ref, &s.q_ref},
                        {&bs.qd_ref, &s.qd_ref},
                        {&bs.damping, &s.damping},
                        {&bs.q_min, &s.q_min},
                        {&bs.q_max, &s.q_max},
                        {&bs.limit_stiffness, &s.limit_stiffness}})
      detail::put_lane(*b, l, *v);
  }
  const auto q = F::gather(x.q), qd = F::gather(x.qd);
  typename F::Batch::JointVector bt, bk, bdmp;
  servo_torque(bs, q, qd, typename F::Lanes_(Value(0.001)), bt);
  servo_gains(bs, q, bk, bdmp);
  for (int l = 0; l < F::W; ++l) {
    typename F::Vec t, k, dmp;
    servo_torque(per_lane[std::size_t(l)], x.q[std::size_t(l)], x.qd[std::size_t(l)], Value(0.001), t);
    servo_gains(per_lane[std::size_t(l)], x.q[std::size_t(l)], k, dmp);
    EXPECT_LE(relative(lane(bt, l), t), F::tol) << "lane " << l;
    EXPECT_EQ(lane(bk, l), k) << "lane " << l;
    EXPECT_EQ(lane(bdmp, l), dmp) << "lane " << l;
  }
}

// The crowds' size: 1001 characters (101 in the sanitizer build, support/long_runs.hpp), every poisoned
// character of CrowdArrays among them and a partial last batch at every width.
const std::size_t crowd_size = long_run<std::size_t>(1001, 101);

// A crowd as a game keeps it, character after character, with a servo each.
template <class T, int nj>
struct CrowdArrays {
  std::size_t n;
  std::vector<T> q, qd, tau, kp, kd, q_ref, qd_ref, damping, q_min, q_max, limit_stiffness;
  std::vector<StepStatus> status;
  CrowdServo<T> servo_view() const {
    return {kp.data(),      kd.data(),    q_ref.data(), qd_ref.data(),
            damping.data(), q_min.data(), q_max.data(), limit_stiffness.data()};
  }
  // (the view holds a pointer to `servo`, which the caller keeps)
  CrowdView<T> view(const CrowdServo<T>* servo) { return {n, q.data(), qd.data(), tau.data(), servo, status.data()}; }

  // random characters: every fourth at the extremes (|q| to 1e3 rad, |q̇| to 100 rad/s), the rest
  // human-sized; servos tracking near the start, some past their limits; and poisoned characters
  CrowdArrays(std::size_t count, unsigned seed) : n(count), status(count) {
    std::mt19937_64 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0), v(0.0, 1.0);
    for (auto* a : {&q, &qd, &tau, &kp, &kd, &q_ref, &qd_ref, &damping, &q_min, &q_max, &limit_stiffness})
      a->resize(n * nj);
    for (std::size_t c = 0; c < n; ++c)
      for (int i = 0; i < nj; ++i) {
        const std::size_t k = c * nj + std::size_t(i);
        const bool extreme = c % 4 == 0;
        q[k] = T((extreme ? 1e3 : 2.0) * u(rng));
        qd[k] = T((extreme ? 100.0 : 3.0) * u(rng));
        tau[k] = T(20.0 * u(rng));
        kp[k] = T(50.0 + 400.0 * v(rng));
        kd[k] = T(5.0 + 30.0 * v(rng));
        q_ref[k] = T(double(q[k]) + 0.1 * u(rng));
        qd_ref[k] = T(u(rng));
        damping[k] = T(0.5);
        q_min[k] = T(c % 3 == 0 ? -1.5 : -std::numeric_limits<double>::infinity());
        q_max[k] = T(c % 3 == 0 ? 1.5 : std::numeric_limits<double>::infinity());
        limit_stiffness[k] = T(c % 3 == 0 ? 300.0 : 0.0);
      }
    q[3 * nj + 5] = std::numeric_limits<T>::quiet_NaN();     // bad input angle
    qd[10 * nj + 2] = T(2e4);                                // runs away (beyond 1e4 rad/s)
    kp[20 * nj + 7] = T(-1);                                 // unusable servo
    tau[(n - 1) * nj] = std::numeric_limits<T>::infinity();  // bad torque, in the last (partial) batch
    if (n > 80) {  // each condition of the servo's check once (the lanes test them all at once: none may be missed)
      kd[30 * nj + 1] = T(-2);
      damping[40 * nj + 15] = std::numeric_limits<T>::quiet_NaN();
      qd_ref[50 * nj + 9] = -std::numeric_limits<T>::infinity();
      limit_stiffness[60 * nj + 4] = T(-1);
      q_min[70 * nj + 12] = T(2);  // above q_max
      q_max[80 * nj + 0] = std::numeric_limits<T>::quiet_NaN();
      if (n > 85) q_min[85 * nj + 3] = q_max[85 * nj + 3] = std::numeric_limits<T>::infinity();  // both at +inf
      q_ref[87 * nj + 10] = T(2e4);  // references beyond the step's limits
      qd_ref[88 * nj + 11] = T(-2e4);
      // each condition of the end state's check (tested in the lanes at once too): an angle carried past
      // 1e4 rad, a velocity whose products overflow
      q[91 * nj + 3] = q_ref[91 * nj + 3] = T(1e4 - 0.05);
      qd[91 * nj + 3] = qd_ref[91 * nj + 3] = T(100);
      qd[94 * nj + 6] = std::numeric_limits<T>::max();
    }
  }

  // character c's servo as a PdServo, for the scalar step
  template <class M>
  PdServo<M> scalar_servo(const M& model, std::size_t c) const {
    PdServo<M> s(model);
    character_servo(servo_view(), c, s);
    return s;
  }
};

// The scalar step of one character, the integrator chosen at run time.
template <class M>
StepStatus scalar_step(Integrator integrator, const M& model, StepWorkspace<M>& ws, State<M>& x,
                       const typename M::JointVector& tau, const PdServo<M>& servo, typename M::scalar_type h) {
  switch (integrator) {
    case Integrator::SemiImplicitEuler:
      return step<Integrator::SemiImplicitEuler>(model, ws, x, tau, &servo, h);
    case Integrator::RungeKutta4:
      return step<Integrator::RungeKutta4>(model, ws, x, tau, &servo, h);
    case Integrator::ImplicitPD:
      return step<Integrator::ImplicitPD>(model, ws, x, tau, &servo, h);
    case Integrator::BackwardEuler:  // from a fresh start, as the crowd takes each character
      ws.forget();
      return step<Integrator::BackwardEuler>(model, ws, x, tau, &servo, h);
  }
  ADD_FAILURE() << "no crowd step for this integrator";
  return {};
}

// The crowd's end states, one per way of splitting it (q[k], qd[k]), each bit for bit the first's.
template <class T>
void expect_splits_bitwise_equal(const std::vector<std::vector<T>>& q, const std::vector<std::vector<T>>& qd) {
  for (std::size_t k = 1; k < q.size(); ++k) {
    EXPECT_EQ(0, std::memcmp(q[0].data(), q[k].data(), sizeof(T) * q[0].size())) << "angles, split " << k;
    EXPECT_EQ(0, std::memcmp(qd[0].data(), qd[k].data(), sizeof(T) * qd[0].size())) << "velocities, split " << k;
  }
}

// The checked crowd step (by step_all(view, h)) equals the scalar step character by
// character: the same status (error, quantity, joint), the same end state where it succeeds, the start
// state untouched where it fails.
template <class T, class StepAll>
void expect_crowd_step_equals_scalar(Integrator integrator, StepAll&& step_all, double tol, const std::string& what) {
  using M = HumanModel<T>;
  constexpr int nj = M::nj;
  const auto model = default_model<T>();
  CrowdArrays<T, nj> crowd(crowd_size, 42);
  const CrowdArrays<T, nj> start = crowd;
  const auto servo = crowd.servo_view();
  const T h = T(1e-3);
  step_all(crowd.view(&servo), h);

  StepWorkspace<M> sws(model);
  int failed = 0;
  double worst = 0;
  for (std::size_t c = 0; c < crowd.n; ++c) {
    State<M> x(model);
    typename M::JointVector tau;
    for (int i = 0; i < nj; ++i) {
      x.q[i] = start.q[c * nj + std::size_t(i)];
      x.qd[i] = start.qd[c * nj + std::size_t(i)];
      tau[i] = start.tau[c * nj + std::size_t(i)];
    }
    const StepStatus expected = scalar_step(integrator, model, sws, x, tau, start.scalar_servo(model, c), h);
    const StepStatus got = crowd.status[c];
    EXPECT_EQ(int(got.error), int(expected.error)) << what << ", character " << c;
    EXPECT_EQ(int(got.quantity), int(expected.quantity)) << what << ", character " << c;
    EXPECT_EQ(got.joint, expected.joint) << what << ", character " << c;
    const Eigen::Map<const typename M::JointVector> q(crowd.q.data() + c * nj), qd(crowd.qd.data() + c * nj);
    if (expected.ok()) {
      const double e = std::max(relative(q, x.q), relative(qd, x.qd));
      worst = std::max(worst, e);
      EXPECT_LE(e, tol) << what << ", character " << c;
    } else {
      ++failed;
      EXPECT_EQ(0, std::memcmp(q.data(), start.q.data() + c * nj, sizeof(T) * nj)) << what << ", character " << c;
      EXPECT_EQ(0, std::memcmp(qd.data(), start.qd.data() + c * nj, sizeof(T) * nj)) << what << ", character " << c;
    }
  }
  EXPECT_GE(failed, 10) << what;  // the ten poisoned ones at least
  // the two references beyond the step's limits, refused before the step
  if (crowd.n > 88)
    for (const auto& [c, joint] : {std::pair{87, 10}, {88, 11}}) {
      EXPECT_EQ(int(crowd.status[std::size_t(c)].error), int(StepError::BadServo)) << what << ", character " << c;
      EXPECT_EQ(crowd.status[std::size_t(c)].joint, joint) << what << ", character " << c;
    }
  std::cout << "  " << what << ", " << integrator_name(integrator) << ": " << failed << " of " << crowd.n
            << " characters refused, as by the scalar step; largest relative difference " << worst << "\n";
}

// the header-only crowd step, without allocation; and a time step that is not a positive finite number
// refuses every character, as step() refuses it, leaving every state as it was
template <Integrator integrator, class F>
void expect_batched_step_equals_scalar() {
  using T = typename F::T;
  const auto model = default_model<T>();
  const typename F::Batch batch(model);
  CrowdWorkspace<typename F::Lanes_> ws(batch);
  for (T h : {T(0), T(-1e-3), std::numeric_limits<T>::quiet_NaN()}) {
    CrowdArrays<T, F::nj> crowd(37, 5);
    const auto q0 = crowd.q, qd0 = crowd.qd;
    const auto servo = crowd.servo_view();
    step_crowd<integrator>(batch, ws, crowd.view(&servo), 0, crowd.n, h);
    for (const StepStatus& st : crowd.status) EXPECT_EQ(st.error, StepError::BadTimeStep) << "h = " << h;
    EXPECT_EQ(0, std::memcmp(crowd.q.data(), q0.data(), sizeof(T) * q0.size()));
    EXPECT_EQ(0, std::memcmp(crowd.qd.data(), qd0.data(), sizeof(T) * qd0.size()));
  }
  expect_crowd_step_equals_scalar<T>(
      integrator,
      [&](const CrowdView<T>& view, T h) {
        Eigen::internal::set_is_malloc_allowed(false);
        step_crowd<integrator>(batch, ws, view, 0, view.size, h);
        Eigen::internal::set_is_malloc_allowed(true);
      },
      F::tol, "lanes of width " + std::to_string(F::W));
}

TYPED_TEST(Crowd, CheckedStepSemiImplicitEulerEqualsScalarStep) {
  expect_batched_step_equals_scalar<Integrator::SemiImplicitEuler, TestFixture>();
}

TYPED_TEST(Crowd, CheckedStepImplicitPdEqualsScalarStep) {
  expect_batched_step_equals_scalar<Integrator::ImplicitPD, TestFixture>();
}

// A body whose mass matrix is singular (a massless left foot, at rest off the home pose): every character's
// step comes out non-finite, and its status is the one step() gives it alone, SingularMassMatrix at the
// left ankle pitch (joint 16), not the first non-finite entry; its state is left as it was
TYPED_TEST(Crowd, ASingularMassMatrixIsNamedAsStepNamesIt) {
  using F = TestFixture;
  using V = typename F::T;
  using M = HumanModel<V>;
  constexpr int joints = M::nj;
  auto d = human_description(default_parameters());
  d.joints[15].body = {};
  const M model(d.template cast<V>());
  const typename F::Batch batch(model);
  CrowdWorkspace<typename F::Lanes_> ws(batch);
  StepWorkspace<M> sws(model);
  const std::size_t n = std::size_t(F::W) + 1;
  const auto run = [&](auto integrator, const char* name) {
    std::vector<V> q(n * joints, V(0.2)), qd(n * joints, V(0)), tau(n * joints, V(0));
    std::vector<StepStatus> status(n);
    step_crowd<decltype(integrator)::value>(
        batch, ws, CrowdView<V>{n, q.data(), qd.data(), tau.data(), nullptr, status.data()}, 0, n, V(1e-3));
    State<M> x(model);
    x.q.setConstant(V(0.2));
    const StepStatus alone = step<decltype(integrator)::value>(model, sws, x, M::JointVector::Zero().eval(), V(1e-3));
    EXPECT_EQ(alone.error, StepError::SingularMassMatrix) << name;
    EXPECT_EQ(alone.joint, 15) << name;
    for (std::size_t c = 0; c < n; ++c) {
      EXPECT_EQ(status[c].error, alone.error) << name << ", character " << c;
      EXPECT_EQ(status[c].joint, alone.joint) << name << ", character " << c;
    }
    EXPECT_TRUE(std::all_of(q.begin(), q.end(), [](V v) { return v == V(0.2); })) << name;
  };
  run(std::integral_constant<Integrator, Integrator::SemiImplicitEuler>{}, "euler");
  run(std::integral_constant<Integrator, Integrator::RungeKutta4>{}, "rk4");
  run(std::integral_constant<Integrator, Integrator::ImplicitPD>{}, "implicit");
}

// 1, 2 and 4 threads, each with its own workspace, over ten steps (three in the sanitizer build):
// bitwise the same crowd
TYPED_TEST(Crowd, ThreadsGiveBitwiseTheSameCrowd) {
  using F = TestFixture;
  using Value = typename F::T;
  const auto model = default_model<Value>();
  const typename F::Batch batch(model);
  std::vector<std::vector<Value>> q, qd;
  const int steps = long_run(10, 3);
  for (int threads : {1, 2, 4}) {
    CrowdArrays<Value, F::nj> crowd(crowd_size, 7);
    const auto servo = crowd.servo_view();
    std::vector<CrowdWorkspace<typename F::Lanes_>> ws(4, CrowdWorkspace<typename F::Lanes_>(batch));
    for (int k = 0; k < steps; ++k)
      split_crowd(crowd.n, threads, F::W, [&](int t, std::size_t begin, std::size_t end) {
        step_crowd<Integrator::ImplicitPD>(batch, ws[std::size_t(t)], crowd.view(&servo), begin, end, Value(1e-3));
      });
    q.push_back(crowd.q);
    qd.push_back(crowd.qd);
  }
  // the same on kept threads (CrowdThreads), each range stepped by the thread it names and every
  // character exactly once per run; then a crowd of fewer batches than threads
  for (int threads : {1, 2, 4}) {
    CrowdThreads team(threads);
    EXPECT_EQ(team.size(), threads);
    CrowdArrays<Value, F::nj> crowd(crowd_size, 7);
    const auto servo = crowd.servo_view();
    std::vector<CrowdWorkspace<typename F::Lanes_>> ws(4, CrowdWorkspace<typename F::Lanes_>(batch));
    std::vector<std::thread::id> by(4);
    std::vector<int> visits(crowd.n, 0);
    for (int k = 0; k < steps; ++k)
      team.run(crowd.n, F::W, [&](int t, std::size_t begin, std::size_t end) {
        by[std::size_t(t)] = std::this_thread::get_id();
        for (std::size_t c = begin; c < end; ++c) ++visits[c];
        step_crowd<Integrator::ImplicitPD>(batch, ws[std::size_t(t)], crowd.view(&servo), begin, end, Value(1e-3));
      });
    for (std::size_t c = 0; c < crowd.n; ++c) ASSERT_EQ(visits[c], steps) << "character " << c;
    for (int t = 0; t < threads; ++t)
      EXPECT_EQ(by[std::size_t(t)] == std::this_thread::get_id(), t == 0) << "range " << t << " of " << threads;
    q.push_back(crowd.q);
    qd.push_back(crowd.qd);
    std::array<std::size_t, 4> end_of{};
    team.run(std::size_t(F::W) + 1, F::W, [&](int t, std::size_t, std::size_t end) { end_of[std::size_t(t)] = end; });
    EXPECT_EQ(std::count_if(end_of.begin(), end_of.end(), [](std::size_t e) { return e > 0; }), std::min(threads, 2))
        << "two batches over " << threads << " threads";
    EXPECT_EQ(end_of[std::size_t(std::min(threads, 2) - 1)], std::size_t(F::W) + 1);
  }
  expect_splits_bitwise_equal(q, qd);
}

// Backward Euler for a crowd (step_crowd_backward_euler), character by character: each character's status
// and state are step()'s from a fresh workspace, bit for bit, without allocation, however the crowd is
// split into ranges (1, 2 or 4 threads, one workspace each, over three steps).
TEST(CrowdBackwardEuler, EveryCharacterIsTheScalarStepFromAFreshStartWhateverTheSplit) {
  using M = HumanModel<double>;
  constexpr int nj = M::nj;
  const auto model = default_model<double>();
  const double h = 1e-3;
  std::vector<std::vector<double>> q, qd;
  for (int ranges : {1, 2, 4}) {
    CrowdArrays<double, nj> crowd(crowd_size, 11);
    const CrowdArrays<double, nj> start = crowd;
    const auto servo = crowd.servo_view();
    std::vector<StepWorkspace<M>> ws(4, StepWorkspace<M>(model));
    std::vector<State<M>> x(4, State<M>(model));
    std::vector<PdServo<M>> character(4, PdServo<M>(model));
    for (int k = 0; k < long_run(3, 1); ++k)
      split_crowd(crowd.n, ranges, 1, [&](int t, std::size_t begin, std::size_t end) {
        const auto r = std::size_t(t);
        step_crowd_backward_euler(model, ws[r], x[r], character[r], crowd.view(&servo), begin, end, h);
      });
    q.push_back(crowd.q);
    qd.push_back(crowd.qd);
    if (ranges > 1) continue;
    // one step against the scalar step, character by character
    CrowdArrays<double, nj> once = start;
    Eigen::internal::set_is_malloc_allowed(false);
    step_crowd_backward_euler(model, ws[0], x[0], character[0], once.view(&servo), 0, once.n, h);
    Eigen::internal::set_is_malloc_allowed(true);
    StepWorkspace<M> fresh(model);
    int failed = 0;
    for (std::size_t c = 0; c < once.n; ++c) {
      State<M> y(model);
      y.q = Eigen::Map<const M::JointVector>(start.q.data() + c * nj);
      y.qd = Eigen::Map<const M::JointVector>(start.qd.data() + c * nj);
      const PdServo<M> servo_c = start.scalar_servo(model, c);
      fresh.forget();
      const StepStatus expected = step<Integrator::BackwardEuler>(
          model, fresh, y, M::JointVector(Eigen::Map<const M::JointVector>(start.tau.data() + c * nj)), &servo_c, h);
      EXPECT_EQ(int(once.status[c].error), int(expected.error)) << "character " << c;
      EXPECT_EQ(int(once.status[c].quantity), int(expected.quantity)) << "character " << c;
      EXPECT_EQ(once.status[c].joint, expected.joint) << "character " << c;
      failed += !expected.ok();
      EXPECT_EQ(0, std::memcmp(y.q.data(), once.q.data() + c * nj, sizeof(double) * nj)) << "character " << c;
      EXPECT_EQ(0, std::memcmp(y.qd.data(), once.qd.data() + c * nj, sizeof(double) * nj)) << "character " << c;
    }
    EXPECT_GE(failed, 10);  // the poisoned ones at least, their states untouched (y kept the start)
  }
  expect_splits_bitwise_equal(q, qd);
}

// Backward Euler for a crowd with each character's memory: each character's statuses and states over twenty
// steps are those of step() with a workspace of its own kept over its steps (continuing steps: its energy,
// its extrapolated q̈ and its Jacobian), bit for bit, without allocation, however the crowd is split into
// ranges, with the servo left out of some steps and the step length changed in others; and not those of
// fresh steps from the same states (which agree only within Newton's tolerance). Newton's work per step, continuing and
// fresh, printed for the human-sized characters' second ten steps.
TEST(CrowdBackwardEuler, CharactersWithMemoryContinueAsStepWithAWorkspaceOfTheirOwn) {
  using M = HumanModel<double>;
  constexpr int nj = M::nj;
  const auto model = default_model<double>();
  // every seventh step without the servo, every fifth of 2 ms: a Jacobian kept, dropped and taken up again
  const auto with_servo = [](int k) { return k % 7 != 3; };
  const auto h_of = [](int k) { return k % 5 == 4 ? 2e-3 : 1e-3; };
  const int steps = long_run(20, 4);
  // (in the sanitizer build 29 characters, the first three poisoned ones and the last among them, split
  // into 1 and 4 ranges: each step is four backward-Euler steps of every character, minutes at -O0 with a
  // hundred)
  const std::size_t characters = long_run<std::size_t>(crowd_size, 29);
  std::vector<std::vector<double>> q, qd;
  const std::vector<int> splits = short_runs ? std::vector<int>{1, 4} : std::vector<int>{1, 2, 4};
  for (int ranges : splits) {
    CrowdArrays<double, nj> crowd(characters, 13);
    const CrowdArrays<double, nj> start = crowd;
    const auto servo = crowd.servo_view();
    std::vector<StepWorkspace<M>> ws(4, StepWorkspace<M>(model));
    std::vector<State<M>> x(4, State<M>(model));
    std::vector<PdServo<M>> character(4, PdServo<M>(model));
    std::vector<BackwardEulerMemory<M>> memory(crowd.n, BackwardEulerMemory<M>(model));
    std::vector<std::vector<StepStatus>> statuses;
    for (int k = 0; k < steps; ++k) {
      Eigen::internal::set_is_malloc_allowed(false);
      split_crowd(crowd.n, ranges, 1, [&](int t, std::size_t begin, std::size_t end) {
        const auto r = std::size_t(t);
        step_crowd_backward_euler(model, ws[r], x[r], character[r], crowd.view(with_servo(k) ? &servo : nullptr),
                                  std::span(memory), begin, end, h_of(k));
      });
      Eigen::internal::set_is_malloc_allowed(true);
      statuses.emplace_back(crowd.status.begin(), crowd.status.end());
    }
    q.push_back(crowd.q);
    qd.push_back(crowd.qd);
    if (ranges > 1) continue;
    // against step() character by character, each with its workspace kept over its steps
    int failed = 0, carried = 0, unlike_fresh = 0;
    long continuing_residuals = 0, fresh_residuals = 0, continuing_jacobians = 0, fresh_jacobians = 0;
    StepWorkspace<M> kept(model), fresh(model);
    for (std::size_t c = 0; c < crowd.n; ++c) {
      State<M> y(model);
      y.q = Eigen::Map<const M::JointVector>(start.q.data() + c * nj);
      y.qd = Eigen::Map<const M::JointVector>(start.qd.data() + c * nj);
      const PdServo<M> servo_c = start.scalar_servo(model, c);
      const M::JointVector tau = Eigen::Map<const M::JointVector>(start.tau.data() + c * nj);
      kept.forget();
      for (int k = 0; k < steps; ++k) {
        State<M> z = y;  // the same start, from a fresh workspace: what memory saves
        fresh.forget();
        const PdServo<M>* s = with_servo(k) ? &servo_c : nullptr;
        const bool fresh_ok = step<Integrator::BackwardEuler>(model, fresh, z, tau, s, h_of(k)).ok();
        const StepStatus expected = step<Integrator::BackwardEuler>(model, kept, y, tau, s, h_of(k));
        const StepStatus& got = statuses[std::size_t(k)][c];
        if (k > 0 && expected.ok() && fresh_ok)
          unlike_fresh += std::memcmp(z.q.data(), y.q.data(), sizeof(double) * nj) != 0;
        EXPECT_EQ(int(got.error), int(expected.error)) << "character " << c << ", step " << k;
        EXPECT_EQ(int(got.quantity), int(expected.quantity)) << "character " << c << ", step " << k;
        EXPECT_EQ(got.joint, expected.joint) << "character " << c << ", step " << k;
        failed += !expected.ok();
        if (k >= steps / 2 && expected.ok() && fresh_ok && c % 4 != 0) {
          continuing_jacobians += kept.report.jacobians;
          fresh_jacobians += fresh.report.jacobians;
          continuing_residuals += kept.report.residuals;
          fresh_residuals += fresh.report.residuals;
          ++carried;
        }
      }
      EXPECT_EQ(0, std::memcmp(y.q.data(), crowd.q.data() + c * nj, sizeof(double) * nj)) << "character " << c;
      EXPECT_EQ(0, std::memcmp(y.qd.data(), crowd.qd.data() + c * nj, sizeof(double) * nj)) << "character " << c;
    }
    EXPECT_GE(failed, 10);                      // the poisoned ones at least, their states untouched
    EXPECT_GT(unlike_fresh, int(crowd.n) / 2);  // (continued, not started afresh)
    std::printf(
        "crowd backward Euler with memory: %d continuing steps, %.2f residuals and %.3f Jacobians each "
        "against %.2f and %.3f fresh; %zu bytes of memory per character\n",
        carried, double(continuing_residuals) / carried, double(continuing_jacobians) / carried,
        double(fresh_residuals) / carried, double(fresh_jacobians) / carried, sizeof(BackwardEulerMemory<M>));
  }
  expect_splits_bitwise_equal(q, qd);
}

// Two corners of the memory, one character against step() with a workspace of its own, bit for bit: a step
// without the servo that needs no Jacobian of its own (its torques make the extrapolated first q̈ exact)
// between steps with it, so that the Jacobian made with the servo serves again after it; and the crowd
// stepped with another model object (an equal copy), where the memory's step is not continued.
TEST(CrowdBackwardEuler, MemoryKeepsAServoJacobianOverAStepWithoutAndStartsAfreshWithAnotherModel) {
  using M = HumanModel<double>;
  constexpr int nj = M::nj;
  const M A = default_model<double>(), B = A;
  const double h = 1e-3;
  CrowdArrays<double, nj> crowd(21, 17);  // (the poisoned characters 3, 10 and 20 not stepped)
  for (int i = 0; i < nj; ++i) {
    crowd.q[i] = 0.3 * std::sin(i + 1.0), crowd.qd[i] = 0.5 * std::cos(i + 2.0), crowd.tau[i] = 0;
    crowd.q_ref[i] = crowd.q[i] + 0.05, crowd.qd_ref[i] = 0;
    crowd.q_min[i] = -std::numeric_limits<double>::infinity(), crowd.q_max[i] = -crowd.q_min[i];
  }
  const auto servo = crowd.servo_view();
  StepWorkspace<M> ws(A), own(A);
  State<M> x(A), y(A);
  PdServo<M> scratch(A);
  const PdServo<M> own_servo = crowd.scalar_servo(A, 0);
  std::vector<BackwardEulerMemory<M>> memory(1, BackwardEulerMemory<M>(A));
  y.q = Eigen::Map<const M::JointVector>(crowd.q.data());
  y.qd = Eigen::Map<const M::JointVector>(crowd.qd.data());
  DerivativeData<M> dd(A);
  int kept_over_the_gap = 0;
  for (int k = 0; k < 8; ++k) {
    const bool with_servo = k != 3;
    const M& model = k < 6 ? A : B;
    M::JointVector tau = M::JointVector::Zero();
    if (!with_servo) {  // the torques the continuing step's first guess of q̈ solves exactly
      ASSERT_EQ(own.carried_known, 2);
      const M::JointVector a = 3 * (own.carried_qdd - own.carried_qdd_1) + own.carried_qdd_2;
      const M::JointVector qd_end = y.qd + h * a, q_end = y.q + h * qd_end;
      rnea_derivatives(A, dd, q_end, qd_end, a);
      tau = dd.tau;
    }
    Eigen::Map<M::JointVector>(crowd.tau.data()) = tau;
    step_crowd_backward_euler(model, ws, x, scratch, crowd.view(with_servo ? &servo : nullptr), std::span(memory), 0, 1,
                              h);
    const StepStatus expected =
        step<Integrator::BackwardEuler>(model, own, y, tau, with_servo ? &own_servo : nullptr, h);
    ASSERT_TRUE(expected.ok()) << "step " << k;
    EXPECT_EQ(int(crowd.status[0].error), int(expected.error)) << "step " << k;
    EXPECT_EQ(ws.report.jacobians, own.report.jacobians) << "step " << k;
    EXPECT_EQ(ws.report.residuals, own.report.residuals) << "step " << k;
    EXPECT_EQ(0, std::memcmp(y.q.data(), crowd.q.data(), sizeof(double) * nj)) << "step " << k;
    EXPECT_EQ(0, std::memcmp(y.qd.data(), crowd.qd.data(), sizeof(double) * nj)) << "step " << k;
    if (k == 3) {
      EXPECT_EQ(own.report.jacobians, 0) << "the step without the servo needs no Jacobian";
    }
    if (k == 4) kept_over_the_gap = own.report.jacobians == 0;
  }
  EXPECT_TRUE(kept_over_the_gap) << "the servo's Jacobian serves again after the step without it";
}

// Every instruction set's compiled kernels this CPU runs (crowd_kernels.hpp), in double and float: the
// checked step by each integrator and inverse dynamics equal the scalar code character by character.
template <class T>
void expect_kernels_equal_scalar() {
  constexpr double tol = std::is_same_v<T, double> ? 1e-12 : 1e-5;
  const auto model = default_model<T>();
  const auto isas = available_isas();
  ASSERT_FALSE(isas.empty());
  EXPECT_EQ(isas.front(), Isa::Sse2);
  EXPECT_EQ(isas.back(), widest_isa());
  for (Isa isa : isas) {
    const CrowdKernel<T> kernel(model, isa);
    auto ws = kernel.workspace();
    const std::string what = std::string(isa_name(isa)) + " kernel, " +
                             (std::is_same_v<T, double> ? "double" : "float") + ", width " +
                             std::to_string(kernel.width());
    // (backward Euler, not batched, character by character)
    for (Integrator integrator :
         {Integrator::SemiImplicitEuler, Integrator::RungeKutta4, Integrator::ImplicitPD, Integrator::BackwardEuler})
      expect_crowd_step_equals_scalar<T>(
          integrator, [&](const CrowdView<T>& view, T h) { kernel.step(integrator, ws, view, 0, view.size, h); }, tol,
          what);

    // backward Euler with each character's memory, over three steps (in the sanitizer build two, of 29
    // characters: the poisoned inputs, but not the servo's and the end state's checks planted past the
    // 80th): what step_crowd_backward_euler gives
    {
      using M = HumanModel<T>;
      constexpr int nj = M::nj;
      const std::size_t characters = long_run<std::size_t>(crowd_size, 29);
      CrowdArrays<T, nj> a(characters, 5), b(characters, 5);
      const auto servo_a = a.servo_view(), servo_b = b.servo_view();
      std::vector<BackwardEulerMemory<M>> memory_a(a.n, BackwardEulerMemory<M>(model)), memory_b = memory_a;
      StepWorkspace<M> sws(model);
      State<M> x(model);
      PdServo<M> servo(model);
      for (int k = 0; k < long_run(3, 2); ++k) {
        kernel.step_backward_euler(ws, a.view(&servo_a), std::span(memory_a), 0, a.n, T(1e-3));
        step_crowd_backward_euler(model, sws, x, servo, b.view(&servo_b), std::span(memory_b), 0, b.n, T(1e-3));
      }
      double worst_be = 0;
      for (std::size_t c = 0; c < a.n; ++c) {
        EXPECT_EQ(int(a.status[c].error), int(b.status[c].error)) << what << ", character " << c;
        if (!b.status[c].ok()) continue;
        using V = Eigen::Map<const typename M::JointVector>;
        for (const auto& [got, expected] : {std::pair{&a.q, &b.q}, {&a.qd, &b.qd}}) {
          const double e = relative(V(got->data() + c * nj), V(expected->data() + c * nj));
          EXPECT_TRUE(e <= tol) << what << ", backward Euler with memory, character " << c << ": " << e;
          worst_be = std::max(worst_be, e);
        }
      }
      std::cout << "  " << what << ", backward Euler with memory: largest relative difference " << worst_be << "\n";
    }

    // inverse dynamics of the crowd
    CrowdArrays<T, HumanModel<T>::nj> crowd(crowd_size, 3);
    std::vector<T> tau(crowd.q.size());
    kernel.inverse_dynamics(ws, crowd.q.data(), crowd.qd.data(), crowd.tau.data(), tau.data(), 0, crowd.n);
    Data<HumanModel<T>> d(model);
    double worst = 0;
    for (std::size_t c = 0; c < crowd.n; ++c) {
      using V = Eigen::Map<const typename HumanModel<T>::JointVector>;
      const std::size_t k = c * HumanModel<T>::nj;
      const auto& expected = rnea(model, d, V(crowd.q.data() + k), V(crowd.qd.data() + k), V(crowd.tau.data() + k));
      if (!expected.allFinite()) {  // the poisoned characters: theirs alone not finite
        EXPECT_FALSE(V(tau.data() + k).allFinite()) << what << ", character " << c;
        continue;
      }
      const double e = relative(V(tau.data() + k), expected);
      worst = std::max(worst, e);
      EXPECT_LE(e, tol) << what << ", inverse dynamics of character " << c;
    }
    std::cout << "  " << what << ", inverse dynamics: largest relative difference " << worst << "\n";
  }
}

TEST(CrowdKernels, EveryAvailableInstructionSetEqualsScalarDouble) { expect_kernels_equal_scalar<double>(); }
TEST(CrowdKernels, EveryAvailableInstructionSetEqualsScalarFloat) { expect_kernels_equal_scalar<float>(); }

}  // namespace

}  // namespace test_crowd
