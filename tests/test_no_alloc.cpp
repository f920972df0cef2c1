// Per-call functions never allocate: forward kinematics, the three inverse-dynamics variants with and
// without external wrenches, gravity torques and wrench_from_world, the backward-Euler step, the floating
// form's calls, for the static and the runtime shape, in float and double.
//
// Two guards watch every call. Eigen's (EIGEN_RUNTIME_NO_MALLOC with set_is_malloc_allowed(false))
// aborts on any allocation by an Eigen object; a count of every operator new sees every other C++
// allocation (std::vector, std::string, ...). A death test shows that Eigen's guard is live. The count
// holds for the whole executable (test_dynamics) and counts only while a test here arms it: a replaced
// global operator new, or under AddressSanitizer a hook of its allocator, which serves every new and
// malloc, so that its own operators stay and go on matching each delete to its new in every suite.
#include "humandyn/humandyn.hpp"

#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <new>
#include <vector>

#if defined(__SANITIZE_ADDRESS__)
#define HUMANDYN_TEST_ASAN
#elif defined(__has_feature)
#if __has_feature(address_sanitizer)
#define HUMANDYN_TEST_ASAN
#endif
#endif
#ifdef HUMANDYN_TEST_ASAN
#include <sanitizer/allocator_interface.h>
#endif

#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "the allocation guard needs EIGEN_RUNTIME_NO_MALLOC"
#endif
#ifdef NDEBUG
#error "NDEBUG switches eigen_assert off, and with it the allocation guard"
#endif

// ---- counting every operator new of this program ----
namespace {
std::atomic<bool> counting{false};
std::atomic<long> allocations{0};
}  // namespace

#ifdef HUMANDYN_TEST_ASAN
namespace {
void count_allocation(const volatile void*, std::size_t) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
}
void ignore_free(const volatile void*) {}
// (installed at start-up, before any thread; both hooks must be given)
[[maybe_unused]] const int hooks = __sanitizer_install_malloc_and_free_hooks(count_allocation, ignore_free);
}  // namespace
#else
// (GCC cannot tell that these replace the global operators, and warns that free() meets new)
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void* operator new(std::size_t size) {
  if (counting.load(std::memory_order_relaxed)) allocations.fetch_add(1, std::memory_order_relaxed);
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void* operator new[](std::size_t size) { return ::operator new(size); }
void operator delete(void* p) noexcept { std::free(p); }
void operator delete[](void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
void operator delete[](void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop
#endif

namespace test_no_alloc {

namespace {

using namespace humandyn;

// Runs f with both guards up; returns how many operator new calls it made (Eigen's guard aborts).
template <class F>
long allocations_in(F&& f) {
  allocations = 0;
  counting = true;
  Eigen::internal::set_is_malloc_allowed(false);
  f();
  Eigen::internal::set_is_malloc_allowed(true);
  counting = false;
  return allocations.load();
}

// Every per-call function on one model, inputs and workspace made beforehand.
template <class M>
void every_call_without_allocation(const M& model) {
  using S = typename M::scalar_type;
  using V = Eigen::Matrix<S, M::nj, 1>;
  const int n = model.size();
  V q = V::Zero(n), qd = V::Zero(n), qdd = V::Zero(n);
  for (int i = 0; i < n; ++i) {
    q[i] = S(0.1 * i - 0.7);
    qd[i] = S(0.3 - 0.05 * i);
    qdd[i] = S(1.0 + 0.2 * i);
  }
  Data<M> data(model);
  LinkWrenches<M> fext{};
  if constexpr (M::nj == Eigen::Dynamic) fext.resize(std::size_t(n));
  const Vec3<S> load(0, 0, S(-49.05));
  const Vec3<S> point(S(0.3), S(0.2), S(1.1));

  // reference results, computed without the guards, to show the guarded calls do the work
  forward_kinematics(model, data, q);
  const Vec3<S> com = data.com;
  const V tau_full = rnea(model, data, q, qd, qdd);

  // outputs sized beforehand: assigning to a vector of the same size does not allocate
  V out_full = V::Zero(n), out_nc = V::Zero(n), out_g = V::Zero(n), out_gt = V::Zero(n), out_ext = V::Zero(n),
    out_ext_nc = V::Zero(n), out_ext_g = V::Zero(n);
  Vec3<S> com_guarded;
  Wrench<S> w;
  const long count = allocations_in([&] {
    forward_kinematics(model, data, q);
    com_guarded = data.com;
    w = wrench_from_world(data, 8, load, point);
    fext[8] = w;
    out_full = rnea<Terms::Full>(model, data, q, qd, qdd);
    out_nc = rnea<Terms::NoCoriolis>(model, data, q, qd, qdd);
    out_g = rnea<Terms::GravityOnly>(model, data, q, qd, qdd);
    out_gt = gravity_torques(model, data, q);
    out_ext = rnea<Terms::Full>(model, data, q, qd, qdd, fext);
    out_ext_nc = rnea<Terms::NoCoriolis>(model, data, q, qd, qdd, fext);
    out_ext_g = rnea<Terms::GravityOnly>(model, data, q, qd, qdd, fext);
  });
  EXPECT_EQ(count, 0) << "operator new called inside a per-call function";

  // the guarded calls computed what the unguarded ones did, and the variants differ as they should
  EXPECT_EQ(com_guarded, com);
  EXPECT_EQ(out_full, tau_full);
  EXPECT_EQ(out_g, out_gt);
  EXPECT_GT((out_full - out_nc).cwiseAbs().maxCoeff(), S(0));
  EXPECT_GT((out_ext - out_full).cwiseAbs().maxCoeff(), S(1));
  EXPECT_GT((out_ext_nc - out_nc).cwiseAbs().maxCoeff(), S(1));
  EXPECT_GT((out_ext_g - out_g).cwiseAbs().maxCoeff(), S(1));
  EXPECT_GT(w.force.norm(), S(49));
}

TEST(NoAllocation, StaticShapeDouble) { every_call_without_allocation(default_model<double>()); }
TEST(NoAllocation, StaticShapeFloat) { every_call_without_allocation(default_model<float>()); }
TEST(NoAllocation, RuntimeShapeDouble) {
  every_call_without_allocation(AnyModel<double>(human_description(default_parameters())));
}
TEST(NoAllocation, RuntimeShapeFloat) {
  every_call_without_allocation(AnyModel<float>(human_description(default_parameters()).cast<float>()));
}

// A moving state: angles and rates that differ from joint to joint.
template <class V>
void set_moving(V& q, V& qd) {
  using S = typename V::Scalar;
  for (int i = 0; i < q.size(); ++i) {
    q[i] = S(0.3 * std::sin(1.3 * i));
    qd[i] = S(std::cos(0.7 * i));
  }
}

// The backward-Euler step (Newton's method, its Jacobian's LU factorisation, substeps) with a servo and with
// a torque schedule, both shapes and scalars: no allocation of either kind.
template <class M>
void backward_euler_without_allocation(const M& model) {
  using S = typename M::scalar_type;
  using V = typename M::JointVector;
  StepWorkspace<M> ws(model);
  State<M> x(model);
  PdServo<M> servo(model);
  set_moving(x.q, x.qd);
  servo.kp.setConstant(S(1e3));
  servo.kd.setConstant(S(10));
  V tau = V::Constant(model.size(), S(2));
  const auto schedule = [](S s, V& out) noexcept { out.setConstant(S(2) + s); };
  StepStatus a, b;
  const long count = allocations_in([&] {
    a = step<Integrator::BackwardEuler>(model, ws, x, tau, &servo, S(1.0 / 60));
    b = step<Integrator::BackwardEuler>(model, ws, x, schedule, nullptr, S(1.0 / 240));
  });
  EXPECT_EQ(count, 0) << "operator new called inside the backward-Euler step";
  EXPECT_TRUE(a.ok() && b.ok());
  EXPECT_GE(ws.report.jacobians, 1);
}

TEST(NoAllocation, BackwardEulerStep) {
  backward_euler_without_allocation(default_model<double>());
  backward_euler_without_allocation(default_model<float>());
  backward_euler_without_allocation(AnyModel<double>(human_description(default_parameters())));
  backward_euler_without_allocation(AnyModel<float>(human_description(default_parameters()).cast<float>()));
}

// The floating form's calls (inverse dynamics, the mass matrix, forward dynamics by both methods, both steps,
// the derivatives), both shapes and scalars: no allocation of either kind.
template <class M>
void floating_calls_without_allocation(const M& model) {
  using S = typename M::scalar_type;
  using V = typename M::JointVector;
  FloatingData<M> fd(model);
  FloatingDerivativeData<M> fdd(model);
  FloatingState<M> x(model);
  const int n = model.size();
  V qdd = V::Zero(n), tau = V::Zero(n), out = V::Zero(n);
  set_moving(x.q, x.qd);
  for (int i = 0; i < n; ++i) {
    qdd[i] = S(0.5 - 0.1 * i);
    tau[i] = S(2 - 0.3 * i);
  }
  x.v_b << S(0.1), S(-0.2), S(0.3), S(0.5), S(0), S(-0.1);
  const SpatialVector<S> a_b = SpatialVector<S>::Constant(S(0.2));
  const V reference = floating_forward_dynamics(model, fd, x.base, x.v_b, x.q, x.qd, tau);
  StepStatus euler, rk4, euler_aba;
  FloatingState<M> y = x, z = x, w = x;
  const long count = allocations_in([&] {
    out = floating_rnea(model, fd, x.base, x.v_b, a_b, x.q, x.qd, qdd);
    floating_crba(model, fd, x.q);
    out = floating_forward_dynamics<FdMethod::Articulated>(model, fd, x.base, x.v_b, x.q, x.qd, tau);
    out = floating_forward_dynamics<FdMethod::MassMatrix>(model, fd, x.base, x.v_b, x.q, x.qd, tau);
    euler = floating_step<Integrator::SemiImplicitEuler>(model, fd, y, tau, S(1e-3));
    euler_aba = floating_step<Integrator::SemiImplicitEuler, FdMethod::Articulated>(model, fd, w, tau, S(1e-3));
    rk4 = floating_step<Integrator::RungeKutta4>(model, fd, z, tau, S(1e-3));
    floating_rnea_derivatives(model, fdd, x.base, x.v_b, a_b, x.q, x.qd, qdd);
  });
  EXPECT_EQ(count, 0) << "operator new called inside a floating-form call";
  EXPECT_TRUE(euler.ok() && rk4.ok() && euler_aba.ok());
  EXPECT_NE(y.q, x.q);
  EXPECT_NE(z.q, x.q);
  EXPECT_LE((out - reference).cwiseAbs().maxCoeff(), S(1e-3) * (S(1) + reference.cwiseAbs().maxCoeff()));
}

TEST(NoAllocation, FloatingForm) {
  const ModelDescription<double> d = floating_description(human_description(default_parameters()));
  floating_calls_without_allocation(FloatingHumanModel<double>(d));
  floating_calls_without_allocation(FloatingHumanModel<float>(d.cast<float>()));
  floating_calls_without_allocation(AnyModel<double>(d));
  floating_calls_without_allocation(AnyModel<float>(d.cast<float>()));
}

// A runtime model with mounts and general twists takes the other branches of the same code.
TEST(NoAllocation, RuntimeShapeWithMountsAndGeneralTwists) {
  ModelDescription<double> d = human_description(default_parameters());
  d.joints[4].mounted = true;
  d.joints[4].mount.p = Eigen::Vector3d(0.01, 0.02, 0.03);
  d.joints[7].dh.alpha = 0.7;
  d.joints[8].dh.alpha = 3.14159265358979323846;
  every_call_without_allocation(AnyModel<double>(d));
  every_call_without_allocation(AnyModel<float>(d.cast<float>()));
}

// The guards are live: an Eigen allocation under Eigen's guard aborts the program, and the counter
// sees an operator new.
TEST(NoAllocationDeathTest, EigenGuardAbortsOnAllocation) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        Eigen::internal::set_is_malloc_allowed(false);
        Eigen::VectorXd v(64);
        v.setOnes();
        std::printf("%g\n", v.sum());
      },
      "heap allocation is forbidden");
}

TEST(NoAllocationGuard, CounterSeesOperatorNew) {
  std::vector<int>* v = nullptr;
  const long count = allocations_in([&] { v = new std::vector<int>(10, 1); });
  delete v;
  EXPECT_GE(count, 2);  // the vector object and its buffer
}

}  // namespace

}  // namespace test_no_alloc
