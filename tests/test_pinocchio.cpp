// The floating form and the fixed one against Pinocchio (PyPI `pin`, its C++ headers), an independent
// implementation with a free-flyer joint: inverse dynamics (joint torques and the base wrench), the
// mass matrix with its base block, and forward dynamics by both methods, on 1000 random states; and the
// fixed form's analytical derivatives of inverse and forward dynamics against Pinocchio's.
// Pinocchio orders a free flyer's coordinates (linear; angular) in the base frame, humandyn (angular;
// linear): the comparison swaps the halves.
#include "humandyn/humandyn.hpp"
#include "support/pinocchio_model.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/rnea.hpp>

#include <Eigen/Geometry>

#include <algorithm>
#include <cstdio>

namespace test_pinocchio {

namespace {

using namespace humandyn;
using humandyn::testing::random_states;
using V = humandyn::testing::pin::Vector;  // Pinocchio's compiled algorithms take their vectors as this
using Body = HumanModel<double>;
using Floating = FloatingHumanModel<double>;
using Vec6 = SpatialVector<double>;

constexpr int kStates = 1000;

// (angular; linear) <-> (linear; angular)
Vec6 swap_halves(const Vec6& x) {
  Vec6 y;
  y << x.tail<3>(), x.head<3>();
  return y;
}

TEST(Pinocchio, FixedBaseInverseAndForwardDynamicsAndMassMatrix) {
  const Body model = default_model();
  const pinocchio::Model pm = humandyn::testing::pinocchio_model(model.description());
  pinocchio::Data pd(pm);
  Data<Body> data(model);
  double err_tau = 0, err_M = 0, err_qdd = 0, largest = 0;
  for (const auto& s : random_states(model.size(), kStates, 61)) {
    const Eigen::VectorXd tau = rnea(model, data, s.q, s.qd, s.qdd);
    err_tau = std::max(err_tau, (tau - pinocchio::rnea(pm, pd, V(s.q), V(s.qd), V(s.qdd))).cwiseAbs().maxCoeff());
    largest = std::max(largest, tau.cwiseAbs().maxCoeff());
    crba(model, data, s.q);
    pinocchio::crba(pm, pd, V(s.q));
    pd.M.triangularView<Eigen::StrictlyLower>() = pd.M.transpose().triangularView<Eigen::StrictlyLower>();
    err_M = std::max(err_M, (Eigen::MatrixXd(data.M) - pd.M).cwiseAbs().maxCoeff());
    const Eigen::VectorXd qdd = forward_dynamics<FdMethod::Articulated>(model, data, s.q, s.qd, tau);
    err_qdd = std::max(err_qdd, (qdd - pinocchio::aba(pm, pd, V(s.q), V(s.qd), V(tau))).cwiseAbs().maxCoeff());
  }
  EXPECT_LT(err_tau, 1e-9);
  EXPECT_LT(err_M, 1e-12);
  EXPECT_LT(err_qdd, 1e-9 * 50);
  EXPECT_GT(largest, 100.0);
}

// The derivatives of inverse dynamics (dtau/dq, dtau/dqd) and of forward dynamics (dqdd/dq, dqdd/dqd,
// dqdd/dtau = M^-1) against Pinocchio's computeRNEADerivatives and computeABADerivatives; errors
// relative to each matrix's largest entry.
TEST(Pinocchio, FixedBaseDerivativesOfInverseAndForwardDynamics) {
  const Body model = default_model();
  const pinocchio::Model pm = humandyn::testing::pinocchio_model(model.description());
  pinocchio::Data pd(pm);
  Data<Body> data(model);
  DerivativeData<Body> dd(model);
  const auto relative = [](const Eigen::MatrixXd& got, const Eigen::MatrixXd& want) {
    return (got - want).cwiseAbs().maxCoeff() / want.cwiseAbs().maxCoeff();
  };
  double err_id = 0, err_fd = 0, err_minv = 0;
  for (const auto& s : random_states(model.size(), kStates, 64)) {
    rnea_derivatives(model, dd, s.q, s.qd, s.qdd);
    pinocchio::computeRNEADerivatives(pm, pd, V(s.q), V(s.qd), V(s.qdd));
    err_id = std::max({err_id, relative(dd.dtau_dq, pd.dtau_dq), relative(dd.dtau_dqd, pd.dtau_dv)});

    const Eigen::VectorXd tau = rnea(model, data, s.q, s.qd, s.qdd);
    forward_dynamics_derivatives(model, data, dd, s.q, s.qd, tau);
    pinocchio::computeABADerivatives(pm, pd, V(s.q), V(s.qd), V(tau));
    pd.Minv.triangularView<Eigen::StrictlyLower>() = pd.Minv.transpose().triangularView<Eigen::StrictlyLower>();
    err_fd = std::max({err_fd, relative(dd.dqdd_dq, pd.ddq_dq), relative(dd.dqdd_dqd, pd.ddq_dv)});
    err_minv = std::max(err_minv, relative(dd.dqdd_dtau, pd.Minv));
  }
  std::printf("relative to Pinocchio: dtau %.2e, dqdd %.2e, M^-1 %.2e\n", err_id, err_fd, err_minv);
  EXPECT_LT(err_id, 1e-9);
  EXPECT_LT(err_fd, 1e-9);
  EXPECT_LT(err_minv, 1e-9);
}

// The floating form's derivatives against Pinocchio's computeRNEADerivatives with a free flyer: the
// joint columns of dtau/dq and every column of dtau/dv (the base velocity's and the joints'), for the
// joint torques and the base wrench (Pinocchio's (linear; angular) halves swapped).
TEST(Pinocchio, FloatingBaseDerivativesOfInverseDynamics) {
  const Floating model = default_floating_model();
  const pinocchio::Model pm = humandyn::testing::pinocchio_model(model.description(), true);
  pinocchio::Data pd(pm);
  FloatingDerivativeData<Floating> fdd(model);
  const int n = model.size();
  Eigen::Matrix<double, 6, 6> P = Eigen::Matrix<double, 6, 6>::Zero();  // (angular; linear) <-> (linear; angular)
  P.topRightCorner<3, 3>().setIdentity();
  P.bottomLeftCorner<3, 3>().setIdentity();
  const auto bases = random_states(6, kStates, 65, 1.0, 3.0, 10.0);
  double err_q = 0, err_v = 0;
  int k = 0;
  for (const auto& s : random_states<Floating::JointVector>(n, kStates, 66)) {
    const auto& b = bases[std::size_t(k++)];
    const Eigen::Quaterniond r =
        Eigen::Quaterniond(Eigen::AngleAxisd(b.q[3], Vec3<double>(b.q[4], b.q[5], 1).normalized()));
    const Pose<double> X{r.toRotationMatrix(), b.q.head<3>()};
    const Vec6 v = b.qd, a = b.qdd;
    Eigen::VectorXd q(7 + n), nu(6 + n), nud(6 + n);
    q << X.p, r.coeffs(), s.q;
    nu << swap_halves(v), s.qd;
    nud << swap_halves(a), s.qdd;
    floating_rnea_derivatives(model, fdd, X, v, a, s.q, s.qd, s.qdd);
    pinocchio::computeRNEADerivatives(pm, pd, V(q), V(nu), V(nud));
    Eigen::MatrixXd dq(6 + n, n), dv(6 + n, 6 + n);
    dq << P * fdd.dwrench_dq, fdd.dtau_dq;
    dv << P * fdd.dwrench_dvb * P, P * fdd.dwrench_dqd, fdd.dtau_dvb * P, fdd.dtau_dqd;
    const Eigen::MatrixXd theirs_q = pd.dtau_dq.rightCols(n);
    err_q = std::max(err_q, (dq - theirs_q).cwiseAbs().maxCoeff() / theirs_q.cwiseAbs().maxCoeff());
    err_v = std::max(err_v, (dv - pd.dtau_dv).cwiseAbs().maxCoeff() / pd.dtau_dv.cwiseAbs().maxCoeff());
  }
  std::printf("relative to Pinocchio: d/dq %.2e, d/dv %.2e\n", err_q, err_v);
  EXPECT_LT(err_q, 1e-9);
  EXPECT_LT(err_v, 1e-9);
}

// The floating form against Pinocchio's free flyer.
TEST(Pinocchio, FloatingBaseInverseAndForwardDynamicsAndMassMatrix) {
  const Floating model = default_floating_model();
  const pinocchio::Model pm = humandyn::testing::pinocchio_model(model.description(), true);
  ASSERT_EQ(pm.nq, 7 + model.size());
  ASSERT_EQ(pm.nv, 6 + model.size());
  pinocchio::Data pd(pm);
  FloatingData<Floating> fd(model);
  const int n = model.size();
  const auto bases = random_states(6, kStates, 62, 1.0, 3.0, 10.0);
  double err_tau = 0, err_base = 0, err_M = 0, err_fd = 0, err_aba = 0, largest = 0;
  int k = 0;
  for (const auto& s : random_states<Floating::JointVector>(n, kStates, 63)) {
    const auto& b = bases[std::size_t(k++)];
    const Eigen::Quaterniond r =
        Eigen::Quaterniond(Eigen::AngleAxisd(b.q[3], Vec3<double>(b.q[4], b.q[5], 1).normalized()));
    const Pose<double> X{r.toRotationMatrix(), b.q.head<3>()};
    Vec6 v, a;
    v << b.qd.tail<3>(), b.qd.head<3>();
    a << b.qdd.tail<3>(), b.qdd.head<3>();
    Eigen::VectorXd q(7 + n), nu(6 + n), nud(6 + n);
    q << X.p, r.coeffs(), s.q;
    nu << swap_halves(v), s.qd;
    nud << swap_halves(a), s.qdd;

    // inverse dynamics: joint torques and the base wrench
    floating_rnea(model, fd, X, v, a, s.q, s.qd, s.qdd);
    const Eigen::VectorXd theirs = pinocchio::rnea(pm, pd, V(q), V(nu), V(nud));
    err_tau = std::max(err_tau, (fd.data.tau - theirs.tail(n)).cwiseAbs().maxCoeff());
    err_base = std::max(err_base, (swap_halves(fd.base_wrench) - theirs.head<6>()).cwiseAbs().maxCoeff());
    largest = std::max(largest, theirs.cwiseAbs().maxCoeff());

    // the mass matrix with its base block
    floating_crba(model, fd, s.q);
    Eigen::MatrixXd M(6 + n, 6 + n);
    Eigen::Matrix<double, 6, 6> P = Eigen::Matrix<double, 6, 6>::Zero();
    P.topRightCorner<3, 3>().setIdentity();
    P.bottomLeftCorner<3, 3>().setIdentity();
    M << P * fd.Mbb * P, P * fd.Mbj, (P * fd.Mbj).transpose(), fd.data.M;
    pinocchio::crba(pm, pd, V(q));
    pd.M.triangularView<Eigen::StrictlyLower>() = pd.M.transpose().triangularView<Eigen::StrictlyLower>();
    err_M = std::max(err_M, (M - pd.M).cwiseAbs().maxCoeff());

    // forward dynamics, both methods, against Pinocchio's articulated bodies
    const Floating::JointVector tau = 20 * s.qdd / 50;
    Eigen::VectorXd tau_full(6 + n);
    tau_full << Vec6::Zero(), tau;
    const Eigen::VectorXd acc = pinocchio::aba(pm, pd, V(q), V(nu), V(tau_full));
    floating_forward_dynamics(model, fd, X, v, s.q, s.qd, tau);
    err_fd = std::max(err_fd, (fd.data.qdd - acc.tail(n)).cwiseAbs().maxCoeff());
    err_fd = std::max(err_fd, (swap_halves(fd.a_b) - acc.head<6>()).cwiseAbs().maxCoeff());
    floating_forward_dynamics<FdMethod::Articulated>(model, fd, X, v, s.q, s.qd, tau);
    err_aba = std::max(err_aba, (fd.data.qdd - acc.tail(n)).cwiseAbs().maxCoeff());
    err_aba = std::max(err_aba, (swap_halves(fd.a_b) - acc.head<6>()).cwiseAbs().maxCoeff());
  }
  RecordProperty("max |tau - tau_Pinocchio| (N m)", std::to_string(err_tau));
  EXPECT_LT(err_tau, 1e-9);
  EXPECT_LT(err_base, 1e-9 * largest);
  EXPECT_LT(err_M, 1e-12);
  EXPECT_LT(err_fd, 1e-9 * 100);  // accelerations up to some 100 rad/s^2: 1e-9 relative
  EXPECT_LT(err_aba, 1e-9 * 100);
  EXPECT_GT(largest, 100.0);
}

}  // namespace

}  // namespace test_pinocchio
