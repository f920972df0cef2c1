// The analytical derivatives of inverse and forward dynamics (rnea_derivatives.hpp) against central
// finite differences of rnea and forward_dynamics on 1000 random states of the default body; the
// runtime shape with mounts and general twists; float against double; no allocation. The floating
// form's derivatives against central differences of floating_rnea; the mass matrix from the same passes
// against crba.
// forward-mode dual numbers run through the same algorithms give the third, exact reference for all three.
// (Pinocchio's analytical derivatives are the other reference: test_pinocchio.)
#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/rnea_derivatives.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/floating.hpp"
#include "humandyn/integrators.hpp"
#include "support/dual.hpp"
#include "support/long_runs.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Eigen/LU>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <limits>

namespace test_derivatives {

#ifndef EIGEN_RUNTIME_NO_MALLOC
#error "the allocation check needs EIGEN_RUNTIME_NO_MALLOC"
#endif

using namespace humandyn;
using humandyn::testing::Dual;
using humandyn::testing::random_states;

namespace {

constexpr int kStates = humandyn::testing::long_run(1000, 40);  // support/long_runs.hpp

// The Jacobian of f: R^n -> R^m at x by central differences, the step chosen per column (entry of x):
// h = eps^(1/3) max(1, |x_j|), the step that balances truncation against round-off, rounded so that
// x + h - x is h exactly.
template <class F>
Eigen::MatrixXd central_differences(F&& f, const Eigen::VectorXd& x) {
  const int n = int(x.size());
  Eigen::MatrixXd J(f(x).size(), n);
  const double base = std::cbrt(std::numeric_limits<double>::epsilon());
  for (int j = 0; j < n; ++j) {
    const double step = base * std::max(1.0, std::abs(x[j]));
    Eigen::VectorXd up = x, down = x;
    up[j] += step;
    down[j] -= step;
    J.col(j) = (f(up) - f(down)) / (up[j] - down[j]);
  }
  return J;
}

// The Jacobian of f: R^n -> R^m at x by forward-mode dual numbers: column j is the derivative part of
// f(x + e_j ε), exact up to the rounding of the derivative's own arithmetic.
using DualVector = Eigen::Matrix<Dual, Eigen::Dynamic, 1>;
template <class F>
Eigen::MatrixXd dual_jacobian(F&& f, const Eigen::VectorXd& x) {
  Eigen::MatrixXd J;
  for (int j = 0; j < int(x.size()); ++j) {
    DualVector seeded = x.cast<Dual>();
    seeded[j].d = 1;
    const DualVector y = f(seeded);
    J.resize(y.size(), x.size());  // (a no-op after the first column)
    for (int i = 0; i < int(y.size()); ++i) J(i, j) = y[i].d;
  }
  return J;
}

// The largest entry-wise difference relative to the largest entry of `want`.
double relative_error(const Eigen::MatrixXd& got, const Eigen::MatrixXd& want) {
  return (got - want).cwiseAbs().maxCoeff() / want.cwiseAbs().maxCoeff();
}

// The default body with a mounted joint and general twists: the runtime shape's other branches.
ModelDescription<double> mounted_description() {
  ModelDescription<double> d = human_description(default_parameters());
  d.joints[4].mounted = true;
  d.joints[4].mount.p = Eigen::Vector3d(0.01, 0.02, 0.03);
  d.joints[4].mount.R = Eigen::Matrix3d(Eigen::AngleAxisd(0.3, Eigen::Vector3d(1, 2, 3).normalized()));
  d.joints[7].dh.alpha = 0.7;
  d.joints[8].dh.alpha = 3.14159265358979323846;
  return d;
}

struct Errors {
  double dq = 0, dqd = 0, tau = 0;
};

// rnea_derivatives against central differences of rnea on `states`: the worst relative errors.
template <class M>
Errors rnea_against_differences(const M& model, const std::vector<humandyn::testing::JointState>& states) {
  Data<M> data(model);
  DerivativeData<M> dd(model);
  Errors e;
  for (const auto& s : states) {
    rnea_derivatives(model, dd, s.q, s.qd, s.qdd);
    const Eigen::VectorXd tau = rnea(model, data, s.q, s.qd, s.qdd);
    e.tau = std::max(e.tau, (Eigen::VectorXd(dd.tau) - tau).cwiseAbs().maxCoeff() / tau.cwiseAbs().maxCoeff());
    const auto by_q = [&](const Eigen::VectorXd& q) { return Eigen::VectorXd(rnea(model, data, q, s.qd, s.qdd)); };
    const auto by_qd = [&](const Eigen::VectorXd& qd) { return Eigen::VectorXd(rnea(model, data, s.q, qd, s.qdd)); };
    e.dq = std::max(e.dq, relative_error(dd.dtau_dq, central_differences(by_q, s.q)));
    e.dqd = std::max(e.dqd, relative_error(dd.dtau_dqd, central_differences(by_qd, s.qd)));
  }
  return e;
}

struct FdErrors {
  double dq = 0, dqd = 0, dtau = 0, qdd = 0;
};

// forward_dynamics_derivatives against central differences of forward_dynamics, at the torques that
// give each state's accelerations.
template <class M>
FdErrors forward_against_differences(const M& model, const std::vector<humandyn::testing::JointState>& states) {
  Data<M> data(model);
  DerivativeData<M> dd(model);
  FdErrors e;
  for (const auto& s : states) {
    const Eigen::VectorXd tau = rnea(model, data, s.q, s.qd, s.qdd);
    forward_dynamics_derivatives(model, data, dd, s.q, s.qd, tau);
    e.qdd = std::max(e.qdd, (Eigen::VectorXd(data.qdd) - s.qdd).cwiseAbs().maxCoeff() / s.qdd.cwiseAbs().maxCoeff());
    const auto fd = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& t) {
      return Eigen::VectorXd(forward_dynamics(model, data, q, qd, t));
    };
    const auto by_q = [&](const Eigen::VectorXd& q) { return fd(q, s.qd, tau); };
    const auto by_qd = [&](const Eigen::VectorXd& qd) { return fd(s.q, qd, tau); };
    const auto by_tau = [&](const Eigen::VectorXd& t) { return fd(s.q, s.qd, t); };
    e.dq = std::max(e.dq, relative_error(dd.dqdd_dq, central_differences(by_q, s.q)));
    e.dqd = std::max(e.dqd, relative_error(dd.dqdd_dqd, central_differences(by_qd, s.qd)));
    e.dtau = std::max(e.dtau, relative_error(dd.dqdd_dtau, central_differences(by_tau, tau)));
  }
  return e;
}

TEST(RneaDerivatives, EqualCentralDifferencesOfRnea) {
  const auto model = default_model();
  const Errors e = rnea_against_differences(model, random_states(model.size(), kStates, 71));
  std::printf("dtau/dq %.2e, dtau/dqd %.2e, tau %.2e (relative)\n", e.dq, e.dqd, e.tau);
  EXPECT_LT(e.dq, 1e-6);
  EXPECT_LT(e.dqd, 1e-6);
  EXPECT_LT(e.tau, 1e-12);
}

TEST(RneaDerivatives, RuntimeShapeWithMountsAndGeneralTwists) {
  const AnyModel<double> model(mounted_description());
  const Errors e = rnea_against_differences(model, random_states(model.size(), kStates, 72));
  std::printf("dtau/dq %.2e, dtau/dqd %.2e, tau %.2e (relative)\n", e.dq, e.dqd, e.tau);
  EXPECT_LT(e.dq, 1e-6);
  EXPECT_LT(e.dqd, 1e-6);
  EXPECT_LT(e.tau, 1e-12);
}

// derivatives_mass_matrix (the mass matrix from the derivative pass's subtree inertias) equals crba's, both
// shapes, with the mount and general twists.
template <class M>
double mass_matrix_error(const M& model, const std::vector<humandyn::testing::JointState>& states) {
  Data<M> data(model);
  DerivativeData<M> dd(model);
  typename DerivativeData<M>::JointMatrix Md(model.size(), model.size());
  double worst = 0;
  for (const auto& s : states) {
    rnea_derivatives(model, dd, s.q, s.qd, s.qdd);
    derivatives_mass_matrix(model, dd, Md);
    crba(model, data, s.q);
    const Eigen::MatrixXd Mc = Eigen::MatrixXd(data.M).selfadjointView<Eigen::Lower>();
    worst = std::max(worst, relative_error(Md, Mc));
  }
  return worst;
}

TEST(RneaDerivatives, MassMatrixEqualsCrba) {
  const double e = mass_matrix_error(default_model(), random_states(16, kStates, 73));
  const double r = mass_matrix_error(AnyModel<double>(mounted_description()), random_states(16, kStates, 74));
  std::printf("M from the derivatives against crba: %.2e, %.2e (relative)\n", e, r);
  EXPECT_LT(e, 1e-13);
  EXPECT_LT(r, 1e-13);
}

// TreeLU (ldlt.hpp) on backward Euler's Jacobian M + h (dtau/dqd + D) + h^2 (dtau/dq + K), which is not
// symmetric but has the mass matrix's sparsity: its solutions equal a dense LU's with partial pivoting,
// both shapes (with mounts and general twists), without allocation. With the benchmarks' servo (kp 200,
// kd 20) every random state's is accepted, at 1 ms and at 1/30 s; without one, at 1/30 s, a few of these
// states (|q̇| up to 10 rad/s) make it nearly singular and are refused, for the dense LU to take.
struct TreeLuErrors {
  double worst = 0;
  int refused = 0;
};

template <class M>
TreeLuErrors tree_lu_error(const M& model, const std::vector<humandyn::testing::JointState>& states, double h,
                           double kp, double kd) {
  const int n = model.size();
  DerivativeData<M> dd(model);
  TreeLU<M> lu(model);
  typename DerivativeData<M>::JointMatrix J(n, n), X(n, n);
  TreeLuErrors e;
  for (const auto& s : states) {
    rnea_derivatives(model, dd, s.q, s.qd, s.qdd);
    derivatives_mass_matrix(model, dd, J);
    J += h * dd.dtau_dqd + (h * h) * dd.dtau_dq;
    J.diagonal().array() += h * kd + h * h * kp;
    X.setIdentity();
    Eigen::internal::set_is_malloc_allowed(false);
    const bool accepted = lu.compute(model, J);
    lu.solve_in_place(model, X);
    Eigen::internal::set_is_malloc_allowed(true);
    if (!accepted) {
      ++e.refused;
      continue;
    }
    const Eigen::MatrixXd dense = Eigen::MatrixXd(J).partialPivLu().inverse();
    e.worst = std::max(e.worst, relative_error(X, dense));
  }
  return e;
}

TEST(TreeLU, SolvesBackwardEulersJacobianAsADenseLUDoes) {
  const auto model = default_model();
  const AnyModel<double> mounted(mounted_description());
  for (const double h : {1e-3, 1.0 / 30}) {
    const TreeLuErrors e = tree_lu_error(model, random_states(16, kStates, 75), h, 200, 20);
    const TreeLuErrors r = tree_lu_error(mounted, random_states(16, kStates, 76), h, 200, 20);
    std::printf("h = %.4f s, servo: J^-1 along the tree against a dense LU's: %.2e, %.2e (relative)\n", h, e.worst,
                r.worst);
    EXPECT_EQ(e.refused + r.refused, 0);
    EXPECT_LT(e.worst, 1e-10);
    EXPECT_LT(r.worst, 1e-10);
  }
  const TreeLuErrors passive = tree_lu_error(model, random_states(16, kStates, 75), 1.0 / 30, 0, 0);
  std::printf("h = 1/30 s, no servo: %d of %d refused; the others %.2e (relative)\n", passive.refused, kStates,
              passive.worst);
  EXPECT_LE(passive.refused * 20, kStates);  // (11 of 1000)
  EXPECT_LT(passive.worst, 1e-10);
  // the matrix is not symmetric (else this would be LTDL's test again)
  DerivativeData<HumanModel<double>> dd(model);
  const auto s = random_states(16, 1, 77).front();
  rnea_derivatives(model, dd, s.q, s.qd, s.qdd);
  EXPECT_GT((dd.dtau_dqd - dd.dtau_dqd.transpose()).cwiseAbs().maxCoeff(), 1e-3);
}

// What the elimination without pivoting refuses, for the caller to factorise densely: a zero or
// non-finite pivot, and a multiplier beyond TreeLU::max_multiplier.
TEST(TreeLU, RefusesAZeroPivotAndLargeGrowth) {
  const auto model = default_model();
  Data<HumanModel<double>> data(model);
  crba(model, data, random_states(16, 1, 78).front().q);
  Eigen::Matrix<double, 16, 16> M = data.M.selfadjointView<Eigen::Lower>();
  TreeLU<HumanModel<double>> lu(model);
  EXPECT_TRUE(lu.compute(model, M));
  auto singular = M;
  singular.row(15).setZero();
  singular.col(15).setZero();
  EXPECT_FALSE(lu.compute(model, singular));
  singular(15, 15) = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(lu.compute(model, singular));
  const int parent = model.joint(15).parent;
  auto lopsided = M;  // joint 15's coupling to its parent 1e4 times its own pivot
  lopsided(15, parent) = 1e4 * std::abs(M(15, 15));
  EXPECT_FALSE(lu.compute(model, lopsided));
  // which JacobianFactorisation then factorises densely, solving as a dense LU does
  JacobianFactorisation<HumanModel<double>> jf(model);
  jf.compute(model, lopsided);
  EXPECT_FALSE(jf.sparse);
  HumanModel<double>::JointVector x, b = HumanModel<double>::JointVector::LinSpaced(-1, 1);
  jf.solve(model, b, x);
  const HumanModel<double>::JointVector want = Eigen::MatrixXd(lopsided).partialPivLu().solve(Eigen::VectorXd(b));
  EXPECT_LT((x - want).norm(), 1e-9 * want.norm());
  lopsided(15, parent) = 10 * std::abs(M(15, 15));
  EXPECT_TRUE(lu.compute(model, lopsided));
  jf.compute(model, lopsided);
  EXPECT_TRUE(jf.sparse);
}

TEST(ForwardDynamicsDerivatives, EqualCentralDifferencesOfForwardDynamics) {
  const auto model = default_model();
  const FdErrors e = forward_against_differences(model, random_states(model.size(), kStates, 73));
  std::printf("dqdd/dq %.2e, dqdd/dqd %.2e, dqdd/dtau %.2e, qdd %.2e (relative)\n", e.dq, e.dqd, e.dtau, e.qdd);
  EXPECT_LT(e.dq, 1e-6);
  EXPECT_LT(e.dqd, 1e-6);
  EXPECT_LT(e.dtau, 1e-6);
  EXPECT_LT(e.qdd, 1e-9);
}

TEST(ForwardDynamicsDerivatives, RuntimeShapeWithMountsAndGeneralTwists) {
  const AnyModel<double> model(mounted_description());
  const FdErrors e = forward_against_differences(model, random_states(model.size(), kStates, 74));
  std::printf("dqdd/dq %.2e, dqdd/dqd %.2e, dqdd/dtau %.2e, qdd %.2e (relative)\n", e.dq, e.dqd, e.dtau, e.qdd);
  EXPECT_LT(e.dq, 1e-6);
  EXPECT_LT(e.dqd, 1e-6);
  EXPECT_LT(e.dtau, 1e-6);
  EXPECT_LT(e.qdd, 1e-9);
}

// The floating form: the joint torques and the base wrench of floating_rnea, differentiated with respect
// to the joint angles, the joint velocities and the base velocity, against central differences, with the
// base in random poses, velocities and accelerations.
TEST(FloatingRneaDerivatives, EqualCentralDifferencesOfFloatingRnea) {
  using Floating = FloatingHumanModel<double>;
  using Vec6 = SpatialVector<double>;
  const Floating model = default_floating_model();
  const int n = model.size();
  FloatingData<Floating> fd(model);
  FloatingDerivativeData<Floating> fdd(model);
  const auto bases = random_states(6, kStates, 78, 1.0, 3.0, 10.0);
  double err_q = 0, err_qd = 0, err_vb = 0, err_value = 0;
  int k = 0;
  for (const auto& s : random_states(n, kStates, 79)) {
    const auto& b = bases[std::size_t(k++)];
    const Pose<double> X{Eigen::AngleAxisd(b.q[3], Eigen::Vector3d(b.q[4], b.q[5], 1).normalized()).toRotationMatrix(),
                         b.q.head<3>()};
    const Vec6 v_b = b.qd, a_b = b.qdd;
    floating_rnea_derivatives(model, fdd, X, v_b, a_b, s.q, s.qd, s.qdd);
    // (tau; base wrench) of floating_rnea
    const auto both = [&](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Vec6& v) {
      Eigen::VectorXd out(n + 6);
      out << floating_rnea(model, fd, X, v, a_b, q, qd, s.qdd), fd.base_wrench;
      return out;
    };
    const Eigen::VectorXd value = both(s.q, s.qd, v_b);
    Eigen::VectorXd ours(n + 6);
    ours << fdd.tau, fdd.base_wrench;
    err_value = std::max(err_value, (ours - value).cwiseAbs().maxCoeff() / value.cwiseAbs().maxCoeff());
    Eigen::MatrixXd d_dq(n + 6, n), d_dqd(n + 6, n), d_dvb(n + 6, 6);
    d_dq << fdd.dtau_dq, fdd.dwrench_dq;
    d_dqd << fdd.dtau_dqd, fdd.dwrench_dqd;
    d_dvb << fdd.dtau_dvb, fdd.dwrench_dvb;
    const auto by_q = [&](const Eigen::VectorXd& q) { return both(q, s.qd, v_b); };
    const auto by_qd = [&](const Eigen::VectorXd& qd) { return both(s.q, qd, v_b); };
    const auto by_vb = [&](const Eigen::VectorXd& v) { return both(s.q, s.qd, Vec6(v)); };
    err_q = std::max(err_q, relative_error(d_dq, central_differences(by_q, s.q)));
    err_qd = std::max(err_qd, relative_error(d_dqd, central_differences(by_qd, s.qd)));
    err_vb = std::max(err_vb, relative_error(d_dvb, central_differences(by_vb, Eigen::VectorXd(v_b))));
  }
  std::printf("d/dq %.2e, d/dqd %.2e, d/dv_b %.2e, values %.2e (relative)\n", err_q, err_qd, err_vb, err_value);
  EXPECT_LT(err_q, 1e-6);
  EXPECT_LT(err_qd, 1e-6);
  EXPECT_LT(err_vb, 1e-6);
  EXPECT_LT(err_value, 1e-12);
}

// The static shape's unrolled passes and the runtime shape's loop give the same matrices; M^-1 is symmetric.
TEST(Derivatives, StaticAndRuntimeShapesAgree) {
  const auto model = default_model();
  const AnyModel<double> any(human_description(default_parameters()));
  Data<HumanModel<double>> data(model);
  Data<AnyModel<double>> any_data(any);
  DerivativeData<HumanModel<double>> dd(model);
  DerivativeData<AnyModel<double>> any_dd(any);
  double err = 0, asym = 0;
  for (const auto& s : random_states(model.size(), 100, 75)) {
    forward_dynamics_derivatives(model, data, dd, s.q, s.qd, s.qdd);
    forward_dynamics_derivatives(any, any_data, any_dd, s.q, s.qd, s.qdd);
    err = std::max({err, relative_error(any_dd.dtau_dq, dd.dtau_dq), relative_error(any_dd.dtau_dqd, dd.dtau_dqd),
                    relative_error(any_dd.dqdd_dq, dd.dqdd_dq), relative_error(any_dd.dqdd_dqd, dd.dqdd_dqd),
                    relative_error(any_dd.dqdd_dtau, dd.dqdd_dtau)});
    asym = std::max(asym, relative_error(dd.dqdd_dtau.transpose(), dd.dqdd_dtau));
  }
  EXPECT_LT(err, 1e-12);
  EXPECT_LT(asym, 1e-12);
}

// Float compiles and agrees with double to its precision.
TEST(Derivatives, FloatAgreesWithDouble) {
  const auto model = default_model<double>();
  const auto model_f = default_model<float>();
  Data<HumanModel<double>> data(model);
  Data<HumanModel<float>> data_f(model_f);
  DerivativeData<HumanModel<double>> dd(model);
  DerivativeData<HumanModel<float>> dd_f(model_f);
  double err_id = 0, err_fd = 0;
  for (const auto& s : random_states(model.size(), 100, 76)) {
    const Eigen::Matrix<float, 16, 1> q = s.q.cast<float>(), qd = s.qd.cast<float>(), qdd = s.qdd.cast<float>();
    // the same (float-rounded) state for both
    const Eigen::VectorXd qx = q.cast<double>(), qdx = qd.cast<double>(), qddx = qdd.cast<double>();
    rnea_derivatives(model, dd, qx, qdx, qddx);
    rnea_derivatives(model_f, dd_f, q, qd, qdd);
    err_id = std::max({err_id, relative_error(dd_f.dtau_dq.cast<double>(), dd.dtau_dq),
                       relative_error(dd_f.dtau_dqd.cast<double>(), dd.dtau_dqd)});
    forward_dynamics_derivatives(model, data, dd, qx, qdx, qddx);
    forward_dynamics_derivatives(model_f, data_f, dd_f, q, qd, qdd);
    err_fd = std::max({err_fd, relative_error(dd_f.dqdd_dq.cast<double>(), dd.dqdd_dq),
                       relative_error(dd_f.dqdd_dqd.cast<double>(), dd.dqdd_dqd),
                       relative_error(dd_f.dqdd_dtau.cast<double>(), dd.dqdd_dtau)});
  }
  std::printf("float against double: inverse %.2e, forward %.2e (relative)\n", err_id, err_fd);
  EXPECT_LT(err_id, 1e-5);
  EXPECT_LT(err_fd, 1e-3);
}

// The analytical derivatives against dual numbers run through rnea and forward_dynamics of the same body
// in Dual: no step, no truncation, so the two agree to rounding. `model` and `dual` are one body in the
// two scalars.
template <class M, class MD>
void against_dual_numbers(const M& model, const MD& dual, unsigned seed) {
  Data<M> data(model);
  DerivativeData<M> dd(model);
  Data<MD> dual_data(dual);
  Errors id;
  FdErrors fd;
  for (const humandyn::testing::JointState& s : random_states(model.size(), kStates, seed)) {
    const DualVector q = s.q.cast<Dual>(), qd = s.qd.cast<Dual>(), qdd = s.qdd.cast<Dual>();
    rnea_derivatives(model, dd, s.q, s.qd, s.qdd);
    const auto by_q = [&](const DualVector& x) { return DualVector(rnea(dual, dual_data, x, qd, qdd)); };
    const auto by_qd = [&](const DualVector& x) { return DualVector(rnea(dual, dual_data, q, x, qdd)); };
    id.dq = std::max(id.dq, relative_error(dd.dtau_dq, dual_jacobian(by_q, s.q)));
    id.dqd = std::max(id.dqd, relative_error(dd.dtau_dqd, dual_jacobian(by_qd, s.qd)));

    const Eigen::VectorXd tau = rnea(model, data, s.q, s.qd, s.qdd);
    const DualVector tau_d = tau.cast<Dual>();
    forward_dynamics_derivatives(model, data, dd, s.q, s.qd, tau);
    const auto fd_q = [&](const DualVector& x) { return DualVector(forward_dynamics(dual, dual_data, x, qd, tau_d)); };
    const auto fd_qd = [&](const DualVector& x) { return DualVector(forward_dynamics(dual, dual_data, q, x, tau_d)); };
    const auto fd_tau = [&](const DualVector& x) { return DualVector(forward_dynamics(dual, dual_data, q, qd, x)); };
    fd.dq = std::max(fd.dq, relative_error(dd.dqdd_dq, dual_jacobian(fd_q, s.q)));
    fd.dqd = std::max(fd.dqd, relative_error(dd.dqdd_dqd, dual_jacobian(fd_qd, s.qd)));
    fd.dtau = std::max(fd.dtau, relative_error(dd.dqdd_dtau, dual_jacobian(fd_tau, tau)));
  }
  std::printf("inverse: dtau/dq %.2e, dtau/dqd %.2e; forward: dqdd/dq %.2e, dqdd/dqd %.2e, dqdd/dtau %.2e (relative)\n",
              id.dq, id.dqd, fd.dq, fd.dqd, fd.dtau);
  for (const double e : {id.dq, id.dqd, fd.dq, fd.dqd, fd.dtau}) EXPECT_LT(e, 1e-11);
}

TEST(DualNumbers, AgreeWithTheDerivatives) { against_dual_numbers(default_model(), default_model<Dual>(), 81); }

TEST(DualNumbers, AgreeWithTheDerivativesOfTheRuntimeShape) {
  against_dual_numbers(AnyModel<double>(mounted_description()), AnyModel<Dual>(mounted_description().cast<Dual>()), 82);
}

// The floating form's derivatives by the joint angles, joint velocities and base velocity against dual
// numbers through floating_rnea (joint torques and base wrench).
TEST(DualNumbers, AgreeWithTheFloatingDerivatives) {
  using Floating = FloatingHumanModel<double>;
  using FloatingDual = FloatingHumanModel<Dual>;
  const Floating model = default_floating_model();
  const FloatingDual dual = default_floating_model<Dual>();
  const int n = model.size();
  FloatingDerivativeData<Floating> fdd(model);
  FloatingData<FloatingDual> fd(dual);
  const auto bases = random_states(6, kStates, 83, 1.0, 3.0, 10.0);
  double err_q = 0, err_qd = 0, err_vb = 0;
  int k = 0;
  for (const auto& s : random_states(n, kStates, 84)) {
    const auto& b = bases[std::size_t(k++)];
    const Pose<double> X{Eigen::AngleAxisd(b.q[3], Eigen::Vector3d(b.q[4], b.q[5], 1).normalized()).toRotationMatrix(),
                         b.q.head<3>()};
    const SpatialVector<double> v_b = b.qd, a_b = b.qdd;
    floating_rnea_derivatives(model, fdd, X, v_b, a_b, s.q, s.qd, s.qdd);
    const Pose<Dual> Xd{X.R.cast<Dual>(), X.p.cast<Dual>()};
    const SpatialVector<Dual> v_bd = v_b.cast<Dual>(), a_bd = a_b.cast<Dual>();
    const DualVector q = s.q.cast<Dual>(), qd = s.qd.cast<Dual>(), qdd = s.qdd.cast<Dual>();
    const auto both = [&](const DualVector& x, const DualVector& xd, const SpatialVector<Dual>& v) {
      DualVector out(n + 6);
      out << floating_rnea(dual, fd, Xd, v, a_bd, x, xd, qdd), fd.base_wrench;
      return out;
    };
    Eigen::MatrixXd d_dq(n + 6, n), d_dqd(n + 6, n), d_dvb(n + 6, 6);
    d_dq << fdd.dtau_dq, fdd.dwrench_dq;
    d_dqd << fdd.dtau_dqd, fdd.dwrench_dqd;
    d_dvb << fdd.dtau_dvb, fdd.dwrench_dvb;
    const auto by_q = [&](const DualVector& x) { return both(x, qd, v_bd); };
    const auto by_qd = [&](const DualVector& x) { return both(q, x, v_bd); };
    const auto by_vb = [&](const DualVector& x) { return both(q, qd, SpatialVector<Dual>(x)); };
    err_q = std::max(err_q, relative_error(d_dq, dual_jacobian(by_q, s.q)));
    err_qd = std::max(err_qd, relative_error(d_dqd, dual_jacobian(by_qd, s.qd)));
    err_vb = std::max(err_vb, relative_error(d_dvb, dual_jacobian(by_vb, Eigen::VectorXd(v_b))));
  }
  std::printf("d/dq %.2e, d/dqd %.2e, d/dv_b %.2e (relative)\n", err_q, err_qd, err_vb);
  EXPECT_LT(err_q, 1e-11);
  EXPECT_LT(err_qd, 1e-11);
  EXPECT_LT(err_vb, 1e-11);
}

// Neither call allocates, for either shape and scalar; the guarded calls give the unguarded results.
template <class M>
void derivatives_without_allocation(const M& model) {
  using S = typename M::scalar_type;
  using V = Eigen::Matrix<S, M::nj, 1>;
  const auto s = random_states(model.size(), 1, 77).front();
  const V q = s.q.template cast<S>(), qd = s.qd.template cast<S>(), qdd = s.qdd.template cast<S>();
  Data<M> data(model);
  DerivativeData<M> dd(model);
  forward_dynamics_derivatives(model, data, dd, q, qd, qdd);
  const auto want_fd = dd.dqdd_dq;
  rnea_derivatives(model, dd, q, qd, qdd);
  const auto want_id = dd.dtau_dq;
  dd.dtau_dq.setZero();
  dd.dqdd_dq.setZero();
  Eigen::internal::set_is_malloc_allowed(false);
  rnea_derivatives(model, dd, q, qd, qdd);
  const bool id_same = dd.dtau_dq == want_id;
  forward_dynamics_derivatives(model, data, dd, q, qd, qdd);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(id_same);
  EXPECT_TRUE(dd.dqdd_dq == want_fd);
  EXPECT_GT(want_id.cwiseAbs().maxCoeff(), S(1));
}

TEST(Derivatives, FloatingNoAllocation) {
  using Floating = FloatingHumanModel<double>;
  const Floating model = default_floating_model();
  FloatingDerivativeData<Floating> fdd(model);
  const auto s = random_states(model.size(), 1, 80).front();
  const Floating::JointVector q = s.q, qd = s.qd, qdd = s.qdd;
  const Pose<double> X{Eigen::Matrix3d(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 2, 3).normalized())),
                       Eigen::Vector3d(0.1, 0.2, 1.0)};
  SpatialVector<double> v_b, a_b;
  v_b << 0.3, -0.2, 0.5, 1.0, 0.1, -0.4;
  a_b << 2.0, 1.0, -1.0, 0.5, 3.0, 1.0;
  Eigen::internal::set_is_malloc_allowed(false);
  floating_rnea_derivatives(model, fdd, X, v_b, a_b, q, qd, qdd);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_GT(fdd.dwrench_dvb.cwiseAbs().maxCoeff(), 1.0);
}

TEST(Derivatives, NoAllocation) {
  derivatives_without_allocation(default_model<double>());
  derivatives_without_allocation(default_model<float>());
  derivatives_without_allocation(AnyModel<double>(mounted_description()));
  derivatives_without_allocation(AnyModel<float>(mounted_description().cast<float>()));
}

}  // namespace

}  // namespace test_derivatives
