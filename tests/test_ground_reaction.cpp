// Inverse dynamics on a moving base (rnea with a BaseMotion) and the ground reaction
// (algorithm/ground_reaction.hpp), against KDL and against the laws of motion of the whole body.
//
// KDL has no moving base, so the base's motion is entered by hand: six massless virtual joints
// (translations along the world x, y, z, then rotations about z, y', x'') carry the base frame, and
// the body hangs from them. Their accelerations make the base accelerate; their torques are the
// wrench that holds the base: the ground reaction, force along the world axes and moment about the
// base origin along the three rotation axes.
#include "humandyn/humandyn.hpp"
#include "support/kdl_moving_base.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstring>

namespace test_ground_reaction {

namespace {

using namespace humandyn;
using humandyn::testing::base_motion_of;
using humandyn::testing::BaseJoints;
using humandyn::testing::JointState;
using humandyn::testing::KdlOnMovingBase;
using humandyn::testing::random_states;
using Body = HumanModel<double>;

constexpr int kStates = 1000;

using humandyn::testing::random_base_joints;

TEST(MovingBase, AtRestEqualsTheFixedBaseBitForBit) {
  const Body model = default_model();
  Data<Body> fixed(model), moving(model);
  const auto base = BaseMotion<double>::at_rest(model);
  const auto same = [](const Body::JointVector& a, const Body::JointVector& b) {
    return std::memcmp(a.data(), b.data(), sizeof(double) * std::size_t(a.size())) == 0;
  };
  double largest = 0;
  for (const auto& s : random_states<Body::JointVector>(model.size(), kStates, 41)) {
    EXPECT_TRUE(same(rnea(model, fixed, s.q, s.qd, s.qdd), rnea(model, moving, base, s.q, s.qd, s.qdd)));
    EXPECT_TRUE(same(rnea<Terms::NoCoriolis>(model, fixed, s.q, s.qd, s.qdd),
                     rnea<Terms::NoCoriolis>(model, moving, base, s.q, s.qd, s.qdd)));
    EXPECT_TRUE(
        same(gravity_torques(model, fixed, s.q), rnea<Terms::GravityOnly>(model, moving, base, s.q, s.qd, s.qdd)));
    largest = std::max(largest, fixed.tau.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(largest, 10.0);  // the states load the joints
}

// Terms::GravityOnly keeps only the base's pose: a base turning and accelerating gives the torques and
// the ground reaction of a base at rest in the same pose, bit for bit; the full terms feel the motion.
TEST(MovingBase, GravityOnlyKeepsThePoseAlone) {
  const Body model = default_model();
  Data<Body> moving(model), still(model);
  const auto bases = random_base_joints(100, 43);
  const auto states = random_states<Body::JointVector>(model.size(), 100, 44);
  double felt = 0;
  for (std::size_t k = 0; k < states.size(); ++k) {
    const auto& s = states[k];
    BaseMotion<double> base = base_motion_of(bases[k], model.base_pose().R), rest;
    rest.pose = base.pose;
    ASSERT_GT(base.a.norm() * base.wd.norm() * base.w.norm(), 0.0);
    const Body::JointVector tau = rnea<Terms::GravityOnly>(model, moving, base, s.q, s.qd, s.qdd);
    EXPECT_EQ(tau, rnea<Terms::GravityOnly>(model, still, rest, s.q, s.qd, s.qdd)) << k;
    const GroundReaction<double> a = ground_reaction<Terms::GravityOnly>(model, moving, base),
                                 b = ground_reaction<Terms::GravityOnly>(model, still, rest);
    EXPECT_EQ(a.force, b.force) << k;
    EXPECT_EQ(a.moment, b.moment) << k;
    felt = std::max(felt, (rnea(model, moving, base, s.q, s.qd, s.qdd) - rnea(model, still, rest, s.q, s.qd, s.qdd))
                              .cwiseAbs()
                              .maxCoeff());
  }
  EXPECT_GT(felt, 1.0);  // N m
}

// Torques and the ground reaction on a moving base equal KDL's with the base carried by virtual joints.
TEST(MovingBase, TorquesAndGroundReactionEqualKdlOnVirtualJoints) {
  const Body model = default_model();
  KdlOnMovingBase kdl(model.description());
  Data<Body> data(model);
  const auto states = random_states(model.size(), kStates, 42);
  const auto bases = random_base_joints(kStates, 43);
  double err_tau = 0, err_force = 0, err_moment = 0, largest_force = 0, largest_moment = 0;
  for (int k = 0; k < kStates; ++k) {
    const auto& s = states[std::size_t(k)];
    BaseJoints b = bases[std::size_t(k)];
    b.q.head<3>() += model.base_pose().p;
    const BaseMotion<double> base = base_motion_of(b, model.base_pose().R);
    const Eigen::VectorXd ref = kdl.torques(b, s);
    const Eigen::VectorXd tau = rnea(model, data, base, s.q, s.qd, s.qdd);
    err_tau = std::max(err_tau, (tau - ref.tail(model.size())).cwiseAbs().maxCoeff());

    const GroundReaction<double> r = ground_reaction(model, data, base);
    err_force = std::max(err_force, (r.force - ref.head<3>()).cwiseAbs().maxCoeff());
    const auto axes = humandyn::testing::rotation_axes(b);
    for (int a = 0; a < 3; ++a)
      err_moment = std::max(err_moment, std::abs(axes[std::size_t(a)].dot(r.moment) - ref[3 + a]));
    largest_force = std::max(largest_force, r.force.norm());
    largest_moment = std::max(largest_moment, r.moment.norm());
  }
  RecordProperty("max |tau - tau_KDL| (N m)", std::to_string(err_tau));
  EXPECT_LT(err_tau, 1e-9);
  EXPECT_LT(err_force, 1e-9 * largest_force);
  EXPECT_LT(err_moment, 1e-9 * largest_moment);
  EXPECT_GT(largest_force, 1000.0);
}

// Standing still: the ground carries the body's weight, under the centre of mass.
TEST(GroundReaction, StaticPoseWeightAndCentreOfPressureUnderTheCentreOfMass) {
  const Body model = default_model();
  Data<Body> data(model);
  const double g = -model.gravity().z();
  for (const auto& s : random_states(model.size(), 200, 44, 0.6)) {
    gravity_torques(model, data, s.q);
    const GroundReaction<double> r = ground_reaction<Terms::GravityOnly>(model, data);
    forward_kinematics(model, data, s.q);
    EXPECT_NEAR(r.force.z(), model.total_mass() * g, 1e-9 * model.total_mass() * g);
    EXPECT_NEAR(r.force.head<2>().norm(), 0.0, 1e-9 * model.total_mass() * g);
    const FootContact<double> c =
        foot_contact(r, model.base_pose(), sole_corners(model, de_leva_sole(1.741, anthropometry::Sex::Male)));
    EXPECT_NEAR(c.cop.x(), data.com.x(), 1e-12);
    EXPECT_NEAR(c.cop.y(), data.com.y(), 1e-12);
    EXPECT_NEAR(c.free_moment, 0.0, 1e-9);
    EXPECT_EQ(c.flags & (FootPulls | FootSlips), 0);
  }
}

// The whole body's momentum: along a smooth motion of base and joints, the reaction force equals
// m (c'' - g) and its moment about the centre of mass equals the rate of change of the angular
// momentum about it, both differentiated from forward kinematics alone (fourth-order differences).
TEST(GroundReaction, EqualsTheRateOfChangeOfMomentum) {
  const Body model = default_model();
  Data<Body> data(model), fk(model);
  const int n = model.size();
  const auto coeffs = random_states(n, 3, 45, 0.8, 2.0, 4.0);  // q(t) = q0 + v t + a t^2 / 2 + j t^3 / 6
  const auto base_coeffs = random_base_joints(2, 46);
  const auto joint_at = [&](double t) {
    JointState s;
    const auto& c = coeffs[0];
    s.q = c.q + c.qd * t + 0.5 * c.qdd * t * t + coeffs[1].q * t * t * t / 6;
    s.qd = c.qd + c.qdd * t + 0.5 * coeffs[1].q * t * t;
    s.qdd = c.qdd + coeffs[1].q * t;
    return s;
  };
  const auto base_at = [&](double t) {
    BaseJoints b;
    const auto& c = base_coeffs[0];
    b.q = c.q + c.qd * t + 0.5 * c.qdd * t * t + base_coeffs[1].qd * t * t * t / 6;
    b.qd = c.qd + c.qdd * t + 0.5 * base_coeffs[1].qd * t * t;
    b.qdd = c.qdd + base_coeffs[1].qd * t;
    b.q.head<3>() += model.base_pose().p;
    return b;
  };
  // every body's pose in the world at time t: the base's, then the links' carried by it
  struct Bodies {
    std::vector<Pose<double>> X;
    std::vector<RigidBodyInertia<double>> I;
  };
  const auto bodies_at = [&](double t) {
    const BaseMotion<double> base = base_motion_of(base_at(t), model.base_pose().R);
    forward_kinematics(model, fk, joint_at(t).q);
    const Pose<double> carry = base.pose * Pose<double>{model.base_pose().R.transpose(),
                                                        -(model.base_pose().R.transpose() * model.base_pose().p)};
    Bodies b;
    b.X.push_back(base.pose);
    b.I.push_back(model.description().base_body);
    for (int i = 0; i < n; ++i) {
      b.X.push_back(carry * fk.oMi[std::size_t(i)]);
      b.I.push_back(model.description().joints[std::size_t(i)].body);
    }
    return b;
  };
  const double m = model.total_mass();
  const auto com_at = [&](double t) {
    const Bodies b = bodies_at(t);
    Vec3<double> mc = Vec3<double>::Zero();
    for (std::size_t k = 0; k < b.X.size(); ++k) mc += b.I[k].mass * (b.X[k] * b.I[k].com);
    return Vec3<double>(mc / m);
  };
  const double h = 1e-3;
  const auto d4 = [&](auto f, double t) {  // fourth-order central difference, evaluated
    using V = decltype(f(t));
    const V d = (f(t - 2 * h) - 8 * f(t - h) + 8 * f(t + h) - f(t + 2 * h)) / (12 * h);
    return d;
  };
  // angular momentum about a fixed point P at time t: sum of I_c w + m (c - P) x c'
  const auto momentum_about = [&](const Vec3<double>& P, double t) {
    const Bodies b = bodies_at(t);
    Vec3<double> L = Vec3<double>::Zero();
    for (std::size_t k = 0; k < b.X.size(); ++k) {
      const auto pose_k = [&](double tt) { return bodies_at(tt).X[k]; };
      const auto R_of = [&](double tt) { return Mat3<double>(pose_k(tt).R); };
      const auto c_of = [&](double tt) {
        const Pose<double> X = pose_k(tt);
        return Vec3<double>(X * b.I[k].com);
      };
      const Mat3<double> W = d4(R_of, t) * b.X[k].R.transpose();  // [w]x
      const Vec3<double> w(W(2, 1), W(0, 2), W(1, 0));
      const Mat3<double> Iw = b.X[k].R * b.I[k].inertia * b.X[k].R.transpose();
      L += Iw * w + b.I[k].mass * (c_of(t) - P).cross(d4(c_of, t));
    }
    return L;
  };
  for (double t : {0.0, 0.3}) {
    const JointState s = joint_at(t);
    const BaseMotion<double> base = base_motion_of(base_at(t), model.base_pose().R);
    rnea(model, data, base, s.q, s.qd, s.qdd);
    const GroundReaction<double> r = ground_reaction(model, data, base);
    const Vec3<double> cdd = d4([&](double tt) { return Vec3<double>(d4(com_at, tt)); }, t);
    const Vec3<double> F = m * (cdd - model.gravity());
    EXPECT_LT((r.force - F).norm(), 1e-7 * F.norm()) << r.force.transpose() << " vs " << F.transpose();
    // about a fixed point P (the centre of mass at t): dL_P/dt = M_P + (c - P) x m g, and c = P
    const Vec3<double> P = com_at(t);
    const Vec3<double> Ld = d4([&](double tt) { return momentum_about(P, tt); }, t);
    const Vec3<double> M = r.moment_about(P);
    EXPECT_LT((M - Ld).norm(), 1e-6 * (M.norm() + 1.0)) << M.transpose() << " vs " << Ld.transpose();
    EXPECT_GT(M.norm(), 10.0);
  }
}

// The flags: a foot that would have to pull, a centre of pressure off the sole, friction beyond mu.
TEST(GroundReaction, FlagsWhatOneFootCannotDo) {
  const Body model = default_model();
  const auto corners = sole_corners(model, de_leva_sole(1.741, anthropometry::Sex::Male));
  const Pose<double> foot = model.base_pose();
  const double ground = foot.p.z() - anthropometry::ankle_height * 1.741;
  GroundReaction<double> r;
  r.origin = foot.p;
  r.force = Vec3<double>(0, 0, 700);
  r.moment = (Vec3<double>(foot.p.x() + 0.05, foot.p.y(), ground) - foot.p).cross(r.force);  // 5 cm ahead
  FootContact<double> c = foot_contact(r, foot, corners, 0.8, ground);
  EXPECT_EQ(c.flags, ContactOk);
  EXPECT_NEAR(c.cop.x(), foot.p.x() + 0.05, 1e-12);
  EXPECT_NEAR(c.cop.y(), foot.p.y(), 1e-12);
  // the sole reaches a quarter of the foot behind the ankle: 10 cm behind is off the heel
  r.moment = (Vec3<double>(foot.p.x() - 0.10, foot.p.y(), ground) - foot.p).cross(r.force);
  EXPECT_EQ(foot_contact(r, foot, corners, 0.8, ground).flags, CopOutsideSole);
  r.moment = (Vec3<double>(foot.p.x(), foot.p.y() + 0.06, ground) - foot.p).cross(r.force);  // off the side
  EXPECT_EQ(foot_contact(r, foot, corners, 0.8, ground).flags, CopOutsideSole);
  r.moment.setZero();
  r.force = Vec3<double>(500, 300, 700);  // tangential 583 N > 0.8 x 700 N
  EXPECT_EQ(foot_contact(r, foot, corners, 0.8, ground).flags & FootSlips, FootSlips);
  EXPECT_EQ(foot_contact(r, foot, corners, 0.9, ground).flags & FootSlips, 0);
  // a frictionless floor (mu = 0) under a body standing still: a tangential force of round-off is no slip,
  // one of a millionth of the weight is
  r.force = Vec3<double>(-5.68e-14, 0, 700);
  EXPECT_EQ(foot_contact(r, foot, corners, 0.0, ground).flags & FootSlips, 0);
  r.force = Vec3<double>(7e-4, 0, 700);
  EXPECT_EQ(foot_contact(r, foot, corners, 0.0, ground).flags & FootSlips, FootSlips);
  r.force = Vec3<double>(0, 0, -10);
  c = foot_contact(r, foot, corners, 0.8, ground);
  EXPECT_EQ(c.flags, FootPulls);  // (no horizontal force: no friction needed, none lacking)
  EXPECT_EQ(c.friction_ratio, 0.0);
  EXPECT_TRUE(std::isnan(c.cop.x()));
  r.force = Vec3<double>(1, 0, -10);
  c = foot_contact(r, foot, corners, 0.8, ground);
  EXPECT_EQ(c.flags, FootPulls | FootSlips);
  EXPECT_EQ(c.friction_ratio, std::numeric_limits<double>::infinity());
  // a foot that carries nothing (free fall, flight) needs neither a pull nor friction
  r.force.setZero();
  c = foot_contact(r, foot, corners, 0.8, ground);
  EXPECT_EQ(c.flags, ContactOk);
  EXPECT_EQ(c.friction_ratio, 0.0);
  EXPECT_TRUE(std::isnan(c.cop.x()));
  r.moment = Vec3<double>(0, 5, 0);  // a couple alone: pushed at one end, pulled at the other
  EXPECT_EQ(foot_contact(r, foot, corners, 0.8, ground).flags, FootPulls);
  r.moment.setZero();
  // a sole seen edge-on (the foot turned a quarter turn about its transverse axis): its outline is a segment,
  // and a centre of pressure on the segment's line is inside only between its ends
  Eigen::Matrix<double, 3, 4> flat;
  flat << 0.1, -0.1, -0.1, 0.1, 0.05, 0.05, -0.05, -0.05, 0, 0, 0, 0;
  Pose<double> edge_on;
  edge_on.R << 0, 0, 1, 0, 1, 0, -1, 0, 0;
  edge_on.p.setZero();
  r.origin.setZero();
  r.force = Vec3<double>(0, 0, 100);
  for (const auto& [y, flags] :
       {std::pair{3.0, CopOutsideSole}, std::pair{0.04, ContactOk}, std::pair{-0.06, CopOutsideSole}}) {
    r.moment = Vec3<double>(0, y, 0).cross(r.force);  // the centre of pressure at (0, y)
    c = foot_contact(r, edge_on, flat, 0.8, 0.0);
    EXPECT_NEAR(c.cop.y(), y, 1e-12);
    EXPECT_EQ(c.flags, flags) << y;
  }
  r.moment = Vec3<double>(0.01, 0, 0).cross(r.force);  // beside the segment
  EXPECT_EQ(foot_contact(r, edge_on, flat, 0.8, 0.0).flags, CopOutsideSole);
}

// A sole scaled from a stature needs one: zero, negative or not finite is an error, not a sole of no or
// negative size.
TEST(GroundReaction, DeLevaSoleNeedsAStature) {
  for (const double bad : {0.0, -1.7, std::nan(""), std::numeric_limits<double>::infinity()})
    EXPECT_THROW((void)de_leva_sole(bad, anthropometry::Sex::Female), ModelError) << bad;
  EXPECT_NEAR(de_leva_sole(1.741, anthropometry::Sex::Male).ankle_height, 0.039 * 1.741, 1e-15);
}

// A jump's take-off on a fixed foot: accelerating the body upward raises the normal force above the
// weight by m a; a base falling freely (a = g) leaves nothing for the ground to do.
TEST(GroundReaction, BaseAccelerationScalesTheLoad) {
  const Body model = default_model();
  Data<Body> data(model);
  const Body::JointVector zero = Body::JointVector::Zero();
  BaseMotion<double> base = BaseMotion<double>::at_rest(model);
  base.a = Vec3<double>(0, 0, 3.0);
  rnea(model, data, base, zero, zero, zero);
  const double m = model.total_mass();
  EXPECT_NEAR(ground_reaction(model, data, base).force.z(), m * (9.81 + 3.0), 1e-9 * m * 12.81);
  base.a = model.gravity();
  const Body::JointVector& tau = rnea(model, data, base, zero, zero, zero);
  EXPECT_LT(tau.cwiseAbs().maxCoeff(), 1e-12);
  EXPECT_LT(ground_reaction(model, data, base).force.norm(), 1e-12);
}

}  // namespace

namespace {

// The per-call functions allocate nothing, and compile and agree in float.
TEST(GroundReaction, NoAllocationAndFloat) {
  const Body model = default_model();
  const HumanModel<float> model_f = model.cast<float>();
  Data<Body> data(model);
  Data<HumanModel<float>> data_f(model_f);
  const auto corners = sole_corners(model, de_leva_sole(1.741, anthropometry::Sex::Male));
  for (const auto& s : random_states<Body::JointVector>(model.size(), 50, 47, 1.0, 3.0, 10.0)) {
    BaseMotion<double> base = BaseMotion<double>::at_rest(model);
    base.w = Vec3<double>(0.3, -0.2, 0.5);
    base.wd = Vec3<double>(1.0, 2.0, -1.5);
    base.a = Vec3<double>(0.5, 0.0, 1.0);
    BaseMotion<float> base_f;
    base_f.pose = base.pose.cast<float>();
    base_f.w = base.w.cast<float>();
    base_f.wd = base.wd.cast<float>();
    base_f.a = base.a.cast<float>();
    const HumanModel<float>::JointVector q = s.q.cast<float>(), qd = s.qd.cast<float>(), qdd = s.qdd.cast<float>();
    Eigen::internal::set_is_malloc_allowed(false);
    rnea(model, data, base, s.q, s.qd, s.qdd);
    const GroundReaction<double> r = ground_reaction(model, data, base);
    const FootContact<double> c = foot_contact(r, base.pose, corners);
    rnea(model_f, data_f, base_f, q, qd, qdd);
    const GroundReaction<float> r_f = ground_reaction(model_f, data_f, base_f);
    Eigen::internal::set_is_malloc_allowed(true);
    EXPECT_LT((data_f.tau.cast<double>() - data.tau).cwiseAbs().maxCoeff(),
              2e-5 * (1 + data.tau.cwiseAbs().maxCoeff()));
    EXPECT_LT((r_f.force.cast<double>() - r.force).norm(), 2e-5 * r.force.norm());
    EXPECT_TRUE(std::isfinite(c.normal));
  }
}

}  // namespace

}  // namespace test_ground_reaction
