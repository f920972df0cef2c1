// The floating form (floating.hpp): the same body as the stance-rooted model, its inverse dynamics
// against KDL with the base on six virtual joints, its mass matrix against inverse dynamics, forward
// dynamics against inverse dynamics, and time stepping against the conservation laws of a free body.
#include "humandyn/floating.hpp"
#include "humandyn/humandyn.hpp"
#include "support/kdl_moving_base.hpp"
#include "support/long_runs.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <string>
#include <vector>

namespace test_floating {

namespace {

using namespace humandyn;
using humandyn::testing::BaseJoints;
using humandyn::testing::JointState;
using humandyn::testing::KdlOnMovingBase;
using humandyn::testing::long_run;
using humandyn::testing::random_base_joints;
using humandyn::testing::random_states;
using Body = HumanModel<double>;
using Floating = FloatingHumanModel<double>;
using Vec6 = SpatialVector<double>;

constexpr int kStates = long_run(1000, 100);  // support/long_runs.hpp

// Every body's centre of mass in the world, by link name (the base included).
template <class M>
std::map<std::string, Vec3<double>> body_centres(const M& model, const typename M::JointVector& q,
                                                 const Pose<double>& base) {
  Data<M> data(model);
  forward_kinematics(model, data, q);
  const Pose<double> carry = base * model.base_pose().inverse();
  std::map<std::string, Vec3<double>> out;
  const auto& d = model.description();
  out[d.base_link_name] = base * d.base_body.com;
  for (int i = 0; i < model.size(); ++i)
    out[d.joints[std::size_t(i)].link_name] = carry * data.com_world[std::size_t(i)];
  return out;
}

TEST(Floating, SameBodyStandingTheSameWayAtHome) {
  const Body stance = default_model();
  const Floating floating = default_floating_model();
  EXPECT_NEAR(floating.total_mass(), stance.total_mass(), 1e-12);
  EXPECT_EQ(floating.description().base_link_name, "pelvis");
  const auto a = body_centres(stance, Body::JointVector::Zero(), stance.base_pose());
  const auto b = body_centres(floating, Floating::JointVector::Zero(), floating.base_pose());
  ASSERT_EQ(a.size(), b.size());
  for (const auto& [name, c] : a) {
    ASSERT_TRUE(b.count(name)) << name;
    EXPECT_LT((b.at(name) - c).norm(), 1e-12) << name;
  }
  // the right leg hangs straight down from the pelvis, as the left one does
  EXPECT_EQ(floating.joint_index("r_hip_pitch"), 0);
  EXPECT_EQ(floating.joint_index("r_ankle_pitch"), 3);
}

// The stance switch carries any state of the stance model to the floating form, every body in place.
TEST(Floating, StateMapPutsEveryBodyInPlace) {
  const Body stance = default_model();
  const Floating floating = default_floating_model();
  const StanceSwitch<Body, Floating> to_floating(stance, floating);
  StanceState<Floating> s;
  double worst = 0;
  for (const auto& x : random_states<Body::JointVector>(stance.size(), 200, 51)) {
    to_floating(stance, floating, x.q, x.qd, s);
    const auto a = body_centres(stance, x.q, stance.base_pose());
    const auto b = body_centres(floating, s.q, s.base_pose);
    for (const auto& [name, c] : a) worst = std::max(worst, (b.at(name) - c).norm());
  }
  EXPECT_LT(worst, 1e-12);
}

// Floating-base inverse dynamics equals KDL's with the pelvis carried by six virtual joints: joint
// torques, and the base wrench against the virtual joints' torques.
TEST(Floating, InverseDynamicsEqualsKdlOnVirtualJoints) {
  const Floating model = default_floating_model();
  KdlOnMovingBase kdl(model.description());
  FloatingData<Floating> fd(model);
  const auto states = random_states(model.size(), kStates, 52);
  const auto bases = random_base_joints(kStates, 53);
  double err_tau = 0, err_base = 0, largest = 0;
  for (int k = 0; k < kStates; ++k) {
    const auto& s = states[std::size_t(k)];
    BaseJoints b = bases[std::size_t(k)];
    b.q.head<3>() += model.base_pose().p;
    const BaseMotion<double> m = humandyn::testing::base_motion_of(b, model.base_pose().R);
    // the same motion as base-frame coordinates: v_b, and a_b = d/dt v_b
    const Mat3<double> Rt = m.pose.R.transpose();
    const Vec3<double> w_b = Rt * m.w, v_b = Rt * b.qd.head<3>();
    Vec6 v, a;
    v << w_b, v_b;
    a << Rt * m.wd, Rt * m.a - w_b.cross(v_b);
    const Eigen::VectorXd ref = kdl.torques(b, s);
    floating_rnea(model, fd, m.pose, v, a, s.q, s.qd, s.qdd);
    err_tau = std::max(err_tau, (fd.data.tau - ref.tail(model.size())).cwiseAbs().maxCoeff());
    const Vec3<double> F = m.pose.R * fd.base_wrench.tail<3>(), M = m.pose.R * fd.base_wrench.head<3>();
    err_base = std::max(err_base, (F - ref.head<3>()).cwiseAbs().maxCoeff());
    const auto axes = humandyn::testing::rotation_axes(b);
    for (int e = 0; e < 3; ++e) err_base = std::max(err_base, std::abs(axes[std::size_t(e)].dot(M) - ref[3 + e]));
    largest = std::max(largest, ref.cwiseAbs().maxCoeff());
  }
  RecordProperty("max |tau - tau_KDL| (N m)", std::to_string(err_tau));
  EXPECT_LT(err_tau, 1e-9);
  EXPECT_LT(err_base, 1e-9 * largest);
  EXPECT_GT(largest, 100.0);
}

// The mass matrix is what inverse dynamics says it is: column k of M equals the generalised forces of
// a unit acceleration k minus those of zero acceleration (base and joints alike).
TEST(Floating, MassMatrixColumnsAreInverseDynamicsDifferences) {
  const Floating model = default_floating_model();
  FloatingData<Floating> fd(model);
  const int n = model.size();
  for (const auto& s : random_states(n, 50, 54)) {
    Pose<double> X{Eigen::AngleAxisd(s.q[0], Vec3<double>(0.3, 0.5, 0.8).normalized()).toRotationMatrix(),
                   Vec3<double>(0.1, -0.2, 0.9)};
    Vec6 v;
    v << s.qd.head<3>(), s.qd.tail<3>();
    floating_crba(model, fd, s.q);
    Eigen::MatrixXd M(6 + n, 6 + n);
    M << fd.Mbb, fd.Mbj, fd.Mbj.transpose(), fd.data.M;
    Eigen::VectorXd h(6 + n);
    floating_rnea(model, fd, X, v, Vec6::Zero(), s.q, s.qd, Eigen::VectorXd::Zero(n));
    h << fd.base_wrench, fd.data.tau;
    double err = 0;
    for (int k = 0; k < 6 + n; ++k) {
      Vec6 a = Vec6::Zero();
      Eigen::VectorXd qdd = Eigen::VectorXd::Zero(n);
      if (k < 6)
        a[k] = 1;
      else
        qdd[k - 6] = 1;
      floating_rnea(model, fd, X, v, a, s.q, s.qd, qdd);
      Eigen::VectorXd f(6 + n);
      f << fd.base_wrench, fd.data.tau;
      err = std::max(err, (f - h - M.col(k)).cwiseAbs().maxCoeff());
    }
    EXPECT_LT(err, 1e-10 * M.cwiseAbs().maxCoeff());
    EXPECT_LT((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-12 * M.cwiseAbs().maxCoeff());
    EXPECT_GT(Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues().minCoeff(), 0.0);
  }
}

// Forward dynamics inverts inverse dynamics: the torques come back, and the base needs no wrench.
TEST(Floating, ForwardDynamicsInvertsInverseDynamics) {
  const Floating model = default_floating_model();
  FloatingData<Floating> fd(model);
  const int n = model.size();
  double err_tau = 0, err_base = 0, err_aba = 0, scale = 0;
  for (const auto& s : random_states<Floating::JointVector>(n, kStates, 55)) {
    const Pose<double> X{Eigen::AngleAxisd(s.qdd[0], Vec3<double>(0.6, -0.3, 0.7).normalized()).toRotationMatrix(),
                         Vec3<double>(0.4, 0.2, 1.0)};
    Vec6 v;
    v << s.qd.head<3>(), 0.3 * s.qd.tail<3>();
    const Floating::JointVector tau = 20 * s.qdd / 50;  // up to 20 N m
    floating_forward_dynamics(model, fd, X, v, s.q, s.qd, tau);
    const Vec6 a = fd.a_b;
    const Floating::JointVector qdd = fd.data.qdd;
    // the articulated-body algorithm gives the same accelerations
    floating_forward_dynamics<FdMethod::Articulated>(model, fd, X, v, s.q, s.qd, tau);
    err_aba = std::max(err_aba, (fd.data.qdd - qdd).cwiseAbs().maxCoeff() / (1 + qdd.cwiseAbs().maxCoeff()));
    err_aba = std::max(err_aba, (fd.a_b - a).cwiseAbs().maxCoeff() / (1 + a.cwiseAbs().maxCoeff()));
    floating_rnea(model, fd, X, v, a, s.q, s.qd, qdd);
    err_tau = std::max(err_tau, (fd.data.tau - tau).cwiseAbs().maxCoeff());
    err_base = std::max(err_base, fd.base_wrench.cwiseAbs().maxCoeff());
    scale = std::max(scale, model.total_mass() * 9.81);
  }
  EXPECT_LT(err_tau, 1e-9 * scale);
  EXPECT_LT(err_base, 1e-9 * scale);
  EXPECT_LT(err_aba, 1e-9);
}

// The whole body's momentum (angular about the world origin; linear), world axes, from the mass
// matrix's base rows: h_b = Mbb v_b + Mbj qd is the momentum at the base origin in base axes.
Vec6 momentum(const Floating& model, FloatingData<Floating>& fd, const FloatingState<Floating>& x) {
  floating_crba(model, fd, x.q);
  const Vec6 h = fd.Mbb * x.v_b + fd.Mbj * x.qd;
  const Vec3<double> p = x.base.R * h.tail<3>();
  Vec6 out;
  out << x.base.R * h.head<3>() + x.base.p.cross(p), p;
  return out;
}

// A passive body thrown into a somersault with a twist: no torques, limbs starting at rest, 0.5 rad
// and more away from home (they whip up to 10 rad/s as it spins).
FloatingState<Floating> somersault(const Floating& model) {
  FloatingState<Floating> x(model);
  for (int i = 0; i < model.size(); ++i) x.q[i] = 0.5 * std::sin(1.3 * i);
  x.v_b << 1.5, -4.0, 0.8, 0.5, 0.2, 1.0;  // rad/s; m/s, base frame
  return x;
}

// With no gravity and no torques, linear and angular momentum stay what they were along a 10-s
// tumble: RK4 carries the momentum as its state, so at 1 ms it keeps it to round-off (1e-9 relative
// asserted), while the pose and the angles converge at fourth order (the differences between runs at h,
// h/2 and h/4 over 1 s fall 16-fold). The sanitizer build tumbles 1 s and 0.5 s (support/long_runs.hpp).
TEST(Floating, TumblingConservesMomentum) {
  ModelDescription<double> d = floating_description(human_description(default_parameters()));
  d.gravity.setZero();
  const Floating model(d);
  FloatingData<Floating> fd(model);
  const Floating::JointVector tau = Floating::JointVector::Zero();
  // the tumble for `seconds` at step h: the largest momentum drift (relative), the end state, the fastest joint
  struct Run {
    double drift = 0, whip = 0;
    Eigen::VectorXd end;
  };
  const auto tumble = [&](double h, double seconds) {
    Run run;
    FloatingState<Floating> x = somersault(model);
    const Vec6 start = momentum(model, fd, x);
    for (int k = 0; k < int(seconds / h + 0.5); ++k) {
      EXPECT_TRUE(floating_step<Integrator::RungeKutta4>(model, fd, x, tau, h)) << "step " << k;
      if (k % 100 == 99) run.drift = std::max(run.drift, (momentum(model, fd, x) - start).norm() / start.norm());
      run.whip = std::max(run.whip, x.qd.cwiseAbs().maxCoeff());
    }
    run.end.resize(3 + 9 + model.size());
    run.end << x.base.p, x.base.R.reshaped(), x.q;
    return run;
  };
  const double seconds = long_run(10.0, 1.0), span = long_run(1.0, 0.5);
  const Run ten = tumble(1e-3, seconds);
  RecordProperty("momentum drift over the tumble, RK4 1 ms (relative)", std::to_string(ten.drift));
  std::printf("  momentum drift over %g s at 1 ms: %.3g; joints up to %.3g rad/s\n", seconds, ten.drift, ten.whip);
  EXPECT_LT(ten.drift, 1e-9);
  EXPECT_GT(ten.whip, 5.0);  // the limbs did flail
  // fourth order over 1 s: successive differences at 4, 2, 1 ms
  const Run r4 = tumble(4e-3, span), r2 = tumble(2e-3, span), r1 = tumble(1e-3, span);
  const double d42 = (r4.end - r2.end).norm(), d21 = (r2.end - r1.end).norm();
  std::printf("  end-state differences over %g s: %.3g (4-2 ms), %.3g (2-1 ms)\n", span, d42, d21);
  EXPECT_GT(d42 / d21, 12.0);
  EXPECT_LT(d42 / d21, 20.0);
}

// A free body steps the same wherever it is: the same start shifted 1e9 m (or 1e6 m, in gravity) gives,
// step after step, the same orientation, velocities and angles bit for bit, and positions that differ by
// the shift to its rounding, with both integrators. (RK4 takes the momentum's moment about the step's
// starting position: taken about the world origin 1e9 m away, the linear momentum's moment swamped the
// angular momentum, and the steps differed from the first.)
TEST(Floating, StepsAreTheSameWhereverTheBodyIs) {
  for (const bool gravity : {false, true}) {
    ModelDescription<double> d = floating_description(human_description(default_parameters()));
    if (!gravity) d.gravity.setZero();
    const Floating model(d);
    FloatingData<Floating> fd(model);
    const Floating::JointVector tau = Floating::JointVector::Zero();
    const Vec3<double> shift = gravity ? Vec3<double>(1e6, -3e5, 2e4) : Vec3<double>(1e9, -4e8, 3e8);
    for (const bool rk4 : {false, true}) {
      FloatingState<Floating> x = somersault(model), y = x;
      y.base.p += shift;
      for (int k = 0; k < 200; ++k) {
        ASSERT_TRUE(rk4 ? floating_step<Integrator::RungeKutta4>(model, fd, x, tau, 1e-3)
                        : floating_step<Integrator::SemiImplicitEuler>(model, fd, x, tau, 1e-3));
        ASSERT_TRUE(rk4 ? floating_step<Integrator::RungeKutta4>(model, fd, y, tau, 1e-3)
                        : floating_step<Integrator::SemiImplicitEuler>(model, fd, y, tau, 1e-3));
        ASSERT_EQ(x.base.R, y.base.R) << k << (rk4 ? " rk4" : " euler");
        ASSERT_EQ(x.v_b, y.v_b) << k;
        ASSERT_EQ(x.q, y.q) << k;
        ASSERT_EQ(x.qd, y.qd) << k;
        ASSERT_LE((y.base.p - x.base.p - shift).norm(), 1e-15 * double(k + 1) * shift.norm()) << k;
      }
    }
  }
}

// In gravity the centre of mass of a free body follows the parabola c0 + c'0 t + g t^2 / 2, whatever
// the limbs and the torques between them do: RK4 to 1e-8 m after 1 s at 1 ms, and semi-implicit Euler
// converging at first order (0.25 s in the sanitizer build, support/long_runs.hpp).
TEST(Floating, CentreOfMassFollowsTheParabola) {
  const Floating model = default_floating_model();
  FloatingData<Floating> fd(model);
  const auto com_of = [&](const FloatingState<Floating>& x) {
    forward_kinematics(model, fd.data, x.q);
    return Vec3<double>(x.base * (model.base_pose().inverse() * fd.data.com));
  };
  Floating::JointVector tau;  // internal torques change nothing: +-0.3 N m on alternate joints
  for (int i = 0; i < model.size(); ++i) tau[i] = i % 2 ? -0.3 : 0.3;
  const double t = long_run(1.0, 0.25);
  const auto miss = [&](bool rk4, double h) {
    FloatingState<Floating> x = somersault(model);
    const Vec3<double> c0 = com_of(x), cd0 = momentum(model, fd, x).tail<3>() / model.total_mass();
    for (int k = 0; k < int(t / h + 0.5); ++k) {
      const bool ok = (rk4 ? floating_step<Integrator::RungeKutta4>(model, fd, x, tau, h)
                           : floating_step<Integrator::SemiImplicitEuler>(model, fd, x, tau, h))
                          .ok();
      if (!ok) return 1e9;
    }
    return (com_of(x) - (c0 + cd0 * t + 0.5 * model.gravity() * t * t)).norm();
  };
  const double rk4 = miss(true, 1e-3), euler1 = miss(false, 1e-3), euler2 = miss(false, 0.5e-3);
  std::printf("  centre of mass after %g s: RK4 %.3g m, Euler %.3g m (1 ms), %.3g m (0.5 ms)\n", t, rk4, euler1,
              euler2);
  EXPECT_LT(rk4, 1e-8);
  EXPECT_NEAR(euler1 / euler2, 2.0, 0.3);  // first order
}

// The stance-rooted torques are the floating-base torques with the full ground reaction applied to the
// stance foot: one body, two descriptions, one set of joint torques (up to each joint's sign), and no
// wrench left for the floating base. On either foot: the left-stance form's pelvis frame is the mirror
// image of the floating base frame, so its velocities reach the base through a constant offset.
TEST(Floating, StanceTorquesAreFloatingTorquesWithTheGroundReactionOnTheFoot) {
  const Floating floating = default_floating_model();
  for (const bool left : {false, true}) {
    SCOPED_TRACE(left ? "left stance" : "right stance");
    const Body stance = left ? left_stance_model(default_parameters()) : default_model();
    const FloatingMap<Body, Floating> map(stance, floating);
    EXPECT_EQ(stance.description().joints[std::size_t(map.pelvis())].link_name, "pelvis");
    Data<Body> ds(stance), ws(stance);
    FloatingData<Floating> fd(floating);
    FloatingState<Floating> x(floating);
    const int n = stance.size();
    const int foot = floating.joint_index(left ? "l_ankle_pitch" : "r_ankle_pitch");
    double err = 0, err_back = 0, err_pose = 0, largest = 0;
    for (const auto& s : random_states<Body::JointVector>(n, 200, 58, 1.0, 3.0, 10.0)) {
      const Body::JointVector tau = rnea(stance, ds, s.q, s.qd, s.qdd);
      const GroundReaction<double> r = ground_reaction(stance, ds);
      map.state(stance, floating, ws, s.q, s.qd, x);
      Vec6 a;
      Floating::JointVector qdd;
      map.acceleration(stance, ws, s.q, s.qd, s.qdd, a, qdd);
      forward_kinematics(stance, ws, s.q);
      const Pose<double> base = ws.oMi[std::size_t(map.pelvis())] * map.base_in_pelvis();
      err_pose = std::max(err_pose, (x.base.p - base.p).norm() + (x.base.R - base.R).norm());
      // the reaction on the floating model's foot, in its link frame about its origin
      forward_kinematics(floating, fd.data, x.q);
      const Pose<double> F = x.base * floating.base_pose().inverse() * fd.data.oMi[std::size_t(foot)];
      LinkWrenches<Floating> fext{};
      fext[std::size_t(foot)].force = F.R.transpose() * r.force;
      fext[std::size_t(foot)].moment = F.R.transpose() * r.moment_about(F.p);
      floating_rnea(floating, fd, x.base, x.v_b, a, x.q, x.qd, qdd, &fext);
      err = std::max(err, (fd.data.tau - map.floating_torques(tau)).cwiseAbs().maxCoeff());
      err = std::max(err, fd.base_wrench.cwiseAbs().maxCoeff());
      err_back = std::max(err_back, (map.stance_torques(fd.data.tau) - tau).cwiseAbs().maxCoeff());
      largest = std::max(largest, tau.cwiseAbs().maxCoeff());
    }
    EXPECT_LT(err, 1e-9 * largest);
    EXPECT_LT(err_back, 1e-9 * largest);
    EXPECT_LT(err_pose, 1e-12);
    EXPECT_GT(largest, 50.0);
    // the form the floating one was made from has its pelvis frame as the base frame; the mirror's does not
    if (left)
      EXPECT_GT((map.base_in_pelvis().R - Eigen::Matrix3d::Identity()).norm(), 0.5);
    else
      EXPECT_LT((map.base_in_pelvis().R - Eigen::Matrix3d::Identity()).norm() + map.base_in_pelvis().p.norm(), 1e-14);
  }
  // the re-hung leg's joints turn the other way; the rest keep their sense
  const Body stance = default_model();
  const FloatingMap<Body, Floating> map(stance, floating);
  EXPECT_EQ(map.source(floating.joint_index("r_knee_pitch")), stance.joint_index("r_knee_pitch"));
  EXPECT_EQ(map.sign(floating.joint_index("l_knee_pitch")), 1.0);
}

// The floating step is checked like the fixed one: bad input is refused naming the joint or the base, a
// runaway is refused, and a refused step leaves the state as it was.
TEST(Floating, StepRefusesBadInputAndRunawaysAndKeepsTheState) {
  const Floating model = default_floating_model();
  FloatingData<Floating> fd(model);
  const Floating::JointVector tau = Floating::JointVector::Zero();
  const auto same = [](const FloatingState<Floating>& a, const FloatingState<Floating>& b) {  // bit for bit
    const auto bits = [](const auto& u, const auto& v) {
      return std::memcmp(u.data(), v.data(), sizeof(double) * std::size_t(u.size())) == 0;
    };
    return bits(a.base.R, b.base.R) && bits(a.base.p, b.base.p) && bits(a.v_b, b.v_b) && bits(a.q, b.q) &&
           bits(a.qd, b.qd);
  };
  const auto expect = [&](FloatingState<Floating> x, const Floating::JointVector& t, double h,
                          const StepLimits<double>& limits, StepError error, Quantity quantity, int joint,
                          const std::string& message) {
    SCOPED_TRACE(message);
    const FloatingState<Floating> before = x;
    for (const StepStatus s : {floating_step<Integrator::SemiImplicitEuler>(model, fd, x, t, h, limits),
                               floating_step<Integrator::RungeKutta4>(model, fd, x, t, h, limits)}) {
      EXPECT_EQ(s.error, error);
      EXPECT_EQ(s.quantity, quantity);
      EXPECT_EQ(s.joint, joint);
      EXPECT_EQ(describe(s, model), message);
    }
    EXPECT_TRUE(same(x, before));
  };
  const FloatingState<Floating> rest(model);
  const int knee = model.joint_index("l_knee_pitch");
  const std::string knee_name = "joint " + std::to_string(knee + 1) + " 'l_knee_pitch'";
  expect(rest, tau, 0.0, {}, StepError::BadTimeStep, Quantity::None, -1, "time step is not a positive finite number");
  FloatingState<Floating> x = rest;
  x.q[knee] = std::nan("");
  expect(x, tau, 1e-3, {}, StepError::BadInput, Quantity::Angle, knee,
         "input angle of " + knee_name + " is not finite");
  x = rest;
  x.base.p[1] = NAN;
  expect(x, tau, 1e-3, {}, StepError::BadInput, Quantity::Angle, -1,
         "input pose of the floating base is not finite or its orientation is not a rotation");
  x = rest;
  x.v_b[4] = INFINITY;
  expect(x, tau, 1e-3, {}, StepError::BadInput, Quantity::Velocity, -1,
         "input velocity of the floating base is not finite");
  // an orientation that is no rotation: stretched, or a reflection
  x = rest;
  x.base.R(0, 0) = 3;
  expect(x, tau, 1e-3, {}, StepError::BadInput, Quantity::Angle, -1,
         "input pose of the floating base is not finite or its orientation is not a rotation");
  x = rest;
  x.base.R.col(2) *= -1;
  expect(x, tau, 1e-3, {}, StepError::BadInput, Quantity::Angle, -1,
         "input pose of the floating base is not finite or its orientation is not a rotation");
  Floating::JointVector bad = tau;
  bad[knee] = NAN;
  expect(rest, bad, 1e-3, {}, StepError::BadInput, Quantity::Torque, knee,
         "input torque of " + knee_name + " is not finite");
  // runaways, against tight limits so that only the quantity pushed runs past them: a joint spun past the
  // rate limit, the base flung past its speed limit, the base spun past the rate limit
  StepLimits<double> tight;
  tight.max_abs_qd = 10;
  tight.max_base_speed = 1;
  x = rest;
  x.qd[knee] = 20;
  expect(x, tau, 1e-3, tight, StepError::Runaway, Quantity::Velocity, knee,
         "the step made the velocity of " + knee_name + " run away");
  x = rest;
  x.v_b[3] = 2;
  expect(x, tau, 1e-3, tight, StepError::Runaway, Quantity::Velocity, -1,
         "the step made the velocity of the floating base run away");
  x = rest;
  x.v_b[2] = 20;
  expect(x, tau, 1e-3, tight, StepError::Runaway, Quantity::Velocity, -1,
         "the step made the velocity of the floating base run away");
  tight.max_abs_qd = 30;  // within the limits, the same spin steps
  EXPECT_TRUE(floating_step<Integrator::SemiImplicitEuler>(model, fd, x, tau, 1e-3, tight).ok());
  // a torque so large that the result overflows: non-finite, reported, the state kept
  bad = tau;
  bad[knee] = 1e308;
  const StepStatus s = floating_step<Integrator::SemiImplicitEuler>(model, fd, x = rest, bad, 1e-3);
  EXPECT_TRUE(s.error == StepError::NonFinite || s.error == StepError::Runaway) << describe(s, model);
  EXPECT_TRUE(same(x, rest));
}

// The per-call functions allocate nothing.
TEST(Floating, NoAllocation) {
  const Floating model = default_floating_model();
  FloatingData<Floating> fd(model);
  FloatingState<Floating> x(model);
  const auto s = random_states<Floating::JointVector>(model.size(), 1, 59);
  x.q = s[0].q;
  x.qd = s[0].qd;
  Eigen::internal::set_is_malloc_allowed(false);
  floating_rnea(model, fd, x.base, x.v_b, Vec6::Zero(), x.q, x.qd, s[0].qdd);
  floating_forward_dynamics(model, fd, x.base, x.v_b, x.q, x.qd, s[0].qdd);
  floating_forward_dynamics<FdMethod::Articulated>(model, fd, x.base, x.v_b, x.q, x.qd, s[0].qdd);
  const bool ok = floating_step<Integrator::RungeKutta4>(model, fd, x, s[0].qdd, 1e-3) &&
                  floating_step<Integrator::SemiImplicitEuler>(model, fd, x, s[0].qdd, 1e-3) &&
                  floating_step<Integrator::RungeKutta4, FdMethod::Articulated>(model, fd, x, s[0].qdd, 1e-3);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(ok);
}

}  // namespace

}  // namespace test_floating
