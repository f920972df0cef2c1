// Statics by hand: the torques that hold a pose against gravity, computed in the test from the
// links' masses and the positions of their centres of mass (moment balance of each subtree), and
// compared with the inverse dynamics; the seed paper's zero entries; de Leva's arm torques; the
// whole-body centre of mass.
#include "humandyn/humandyn.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <kdl/treefksolverpos_recursive.hpp>

#include <cmath>
#include <vector>

namespace test_statics {

namespace {

using namespace humandyn;
using humandyn::testing::random_states;

constexpr double kPi = 3.14159265358979323846;
constexpr double kG = 9.81;
using Q16 = Eigen::Matrix<double, 16, 1>;

// Zero torques are zero up to round-off: the terms that cancel are of the order of the pose's
// largest torques (about 100 N m), and double round-off on them is below 1e-13 N m; 1e-12 N m leaves
// a margin of ten while any modelling error (a centre of mass a micrometre off the axis) shows above it.
constexpr double kZero = 1e-12;

// The joints in the subtree of joint i (i included), from the parent array alone.
std::vector<int> subtree(const ModelDescription<double>& d, int i) {
  std::vector<int> out{i};
  for (int k = i + 1; k < int(d.joints.size()); ++k)
    for (int p = d.joints[std::size_t(k)].parent; p >= 0; p = d.joints[std::size_t(p)].parent)
      if (p == i) {
        out.push_back(k);
        break;
      }
  return out;
}

class Statics : public ::testing::Test {
 protected:
  SeedParameters params{default_parameters()};
  HumanModel<double> model{human_model<double>(params)};
  Data<HumanModel<double>> data{model};

  // The static torque of joint i by moment balance: the joint holds the weight of everything beyond
  // it, tau_i = -axis_i . sum_k (c_k - o_i) x m_k g, with o_i and axis_i the origin and z axis of the
  // parent's frame and c_k the links' centres of mass from forward kinematics.
  double by_hand(int i) const {
    const auto& d = model.description();
    const int parent = d.joints[std::size_t(i)].parent;
    const Pose<double>& P = parent < 0 ? model.base_pose() : data.oMi[std::size_t(parent)];
    Eigen::Vector3d moment = Eigen::Vector3d::Zero();
    for (int k : subtree(d, i))
      moment += (data.com_world[std::size_t(k)] - P.p).cross(d.joints[std::size_t(k)].body.mass * d.gravity);
    return -P.R.col(2).dot(moment);
  }
  Eigen::Vector3d axis(int i) const {
    const int parent = model.joint(i).parent;
    return (parent < 0 ? model.base_pose() : data.oMi[std::size_t(parent)]).R.col(2);
  }
  Eigen::Vector3d origin(int i) const {
    const int parent = model.joint(i).parent;
    return (parent < 0 ? model.base_pose() : data.oMi[std::size_t(parent)]).p;
  }
  Q16 hold(const Q16& q) {
    forward_kinematics(model, data, q);
    return gravity_torques(model, data, q);
  }
};

// Standing upright: every lateral-axis joint (ankles, knees, hip pitches, waist, shoulders, elbows)
// carries exactly what the fore-aft offsets of the centres of mass beyond it predict: with the axis
// along s y (s = +1 or -1), tau = -s g sum m_k (x_k - x_joint). Every segment hangs plumb from its
// joint, so the only offset is the free foot's (its centre of mass ahead of the ankle): the left-leg
// and stance-leg joints carry it, the waist and arms carry nothing.
TEST_F(Statics, StandingLateralAxesCarryTheForeAftOffsets) {
  const Q16 tau = hold(Q16::Zero());
  const auto& d = model.description();
  int lateral = 0;
  for (int i = 0; i < 16; ++i) {
    const Eigen::Vector3d a = axis(i);
    if (std::abs(std::abs(a.y()) - 1) > 1e-12) continue;
    ++lateral;
    double offsets = 0;  // sum m_k (x_k - x_joint)
    for (int k : subtree(d, i))
      offsets += d.joints[std::size_t(k)].body.mass * (data.com_world[std::size_t(k)].x() - origin(i).x());
    const double expected = -std::copysign(1.0, a.y()) * kG * offsets;
    EXPECT_NEAR(tau[i], expected, kZero) << "joint " << i + 1 << " " << seed_joint_names[std::size_t(i)];
    EXPECT_NEAR(tau[i], by_hand(i), kZero);
  }
  EXPECT_EQ(lateral, 11);

  // and the free foot's offset, from the segment table: de Leva's foot centre of mass at 44.15 % of
  // the heel-to-toe length, the ankle at 25 % of it
  const double foot_moment = params.foot.mass * kG * (0.4415 - 0.25) * 0.2581;
  EXPECT_NEAR(std::abs(tau[0]), foot_moment, 1e-12);   // right ankle
  EXPECT_NEAR(std::abs(tau[15]), foot_moment, 1e-12);  // left ankle
  EXPECT_NEAR(std::abs(tau[4]), 0.0, kZero);           // waist pitch
  EXPECT_NEAR(std::abs(tau[6]), 0.0, kZero);           // left shoulder pitch
}

// Standing, the stance hip roll (joint 3, about the forward axis through the right hip) carries the
// mass above it (everything but the stance foot, shank and thigh) times g times its lateral offset
// from the right hip. By hand from the segments: pelvis, upper body and both arms centre on the pelvis,
// d4 to the left of the right hip; the whole left leg hangs 2 d4 to the left.
TEST_F(Statics, StandingStanceHipRollCarriesTheMassAbove) {
  const Q16 tau = hold(Q16::Zero());
  const auto& d = model.description();
  double mass_above = 0, first_moment = 0;
  for (int k : subtree(d, 2)) {
    mass_above += d.joints[std::size_t(k)].body.mass;
    first_moment += d.joints[std::size_t(k)].body.mass * data.com_world[std::size_t(k)].y();
  }
  const double lateral_offset = first_moment / mass_above - origin(2).y();
  // the axis points backwards (-x): the weight to the left of it loads it negatively
  ASSERT_LE((axis(2) - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-12);
  EXPECT_NEAR(tau[2], -mass_above * kG * lateral_offset, 1e-12);
  EXPECT_NEAR(tau[2], by_hand(2), 1e-12);

  const SeedParameters& p = params;
  const double centred = p.pelvis.mass + p.upper_body.mass + 2 * p.upper_arm.mass + 2 * p.forearm.mass;
  const double left_leg = p.thigh.mass + p.shank.mass + p.foot.mass;
  EXPECT_NEAR(mass_above, centred + left_leg, 1e-12);
  EXPECT_NEAR(tau[2], -kG * p.d4 * (centred + 2 * left_leg), 1e-12);
  EXPECT_GT(std::abs(tau[2]), 50.0);
}

// Any pose: every joint's static torque equals its moment balance.
TEST_F(Statics, EveryJointAtRandomPosesByMomentBalance) {
  double worst = 0;
  for (const auto& s : random_states(16, 200, 31)) {
    const Q16 q = s.q;
    const Q16 tau = hold(q);
    for (int i = 0; i < 16; ++i) worst = std::max(worst, std::abs(tau[i] - by_hand(i)));
  }
  EXPECT_LE(worst, 1e-11);
}

// The paper's zero entries. Waist yaw (joint 6) turns about the vertical: weight has no moment about
// it, whatever the arms do, as long as the trunk stands upright.
TEST_F(Statics, WaistYawCarriesNothing) {
  for (const auto& s : random_states(16, 100, 32)) {
    Q16 q = s.q;
    q.head<5>().setZero();  // right leg and waist pitch upright: the yaw axis vertical
    EXPECT_LE(std::abs(hold(q)[5]), kZero);
  }
}

// Shoulder roll (joint 8) with the arm raised forward: the arm lies along the roll axis. More
// generally, with the trunk upright and no roll, the arm swings in the sagittal plane through the
// shoulder, which contains the roll axis: zero for any shoulder pitch and elbow angle.
TEST_F(Statics, ShoulderRollCarriesNothingWithTheArmInItsPlane) {
  Q16 q = Q16::Zero();
  q[6] = -kPi / 2;  // left arm forward
  const Q16 tau = hold(q);
  ASSERT_GT(data.oMi[8].p.x() - origin(6).x(), 0.5) << "the left arm points forward";
  EXPECT_LE(std::abs(tau[7]), kZero);
  EXPECT_LE(std::abs(tau[5]), kZero);  // and the waist yaw
  for (const auto& s : random_states(16, 100, 33)) {
    Q16 r = Q16::Zero();
    r[6] = s.q[6];
    r[8] = s.q[8];
    r[9] = s.q[9];
    r[11] = s.q[11];
    const Q16 t = hold(r);
    EXPECT_LE(std::abs(t[7]), kZero);
    EXPECT_LE(std::abs(t[10]), kZero);
  }
}

// The free leg's hip roll (joint 14): the leg hangs, or swings in its sagittal plane (any hip pitch,
// knee and ankle), and the roll axis lies in that plane.
TEST_F(Statics, FreeHipRollCarriesNothing) {
  EXPECT_LE(std::abs(hold(Q16::Zero())[13]), kZero);
  for (const auto& s : random_states(16, 100, 34)) {
    Q16 q = s.q;
    q.head<5>().setZero();
    q[13] = 0;
    EXPECT_LE(std::abs(hold(q)[13]), kZero);
  }
}

// The seed's scenarios themselves, on every built-in model and with every choice of terms: the zero
// entries of the paper (waist yaw; shoulder roll with the arm forward; the free leg's hip roll) come
// out exactly 0.0. At these poses every joint angle plus its DH offset is a quarter turn, whose
// cosine and sine are exact, so the lever arms that would have to cancel are exactly zero.
TEST(PaperScenarios, ZeroEntriesAreExactlyZero) {
  for (auto make : {default_parameters, female_parameters, paper_parameters}) {
    const auto model = human_model<double>(make());
    SCOPED_TRACE(model.description().name);
    Data<HumanModel<double>> data(model);
    const Q16 zero = Q16::Zero();
    for (double arm : {0.0, -kPi / 2}) {  // standing; the left arm raised forward
      Q16 q = zero;
      q[6] = arm;
      for (const Q16& tau : {Q16(rnea<Terms::Full>(model, data, q, zero, zero)),
                             Q16(rnea<Terms::NoCoriolis>(model, data, q, zero, zero)),
                             Q16(rnea<Terms::GravityOnly>(model, data, q, zero, zero))}) {
        EXPECT_EQ(tau[5], 0.0) << "waist yaw, arm " << arm;
        EXPECT_EQ(tau[7], 0.0) << "left shoulder roll, arm " << arm;
        EXPECT_EQ(tau[10], 0.0) << "right shoulder roll, arm " << arm;
        EXPECT_EQ(tau[13], 0.0) << "free hip roll, arm " << arm;
        EXPECT_NE(tau[2], 0.0) << "the stance hip roll is loaded";
      }
    }
  }
}

// de Leva's reference male: a straight arm held horizontally forward loads the shoulder with
// 10.55 N m, the forearm and hand held forward (upper arm hanging) load the elbow with 2.90 N m.
// From the segment table: upper arm 2.71 % of 73 kg, centre of mass at 57.72 % of 0.2817 m;
// forearm 1.62 %, at 45.74 % of 0.2689 m; hand 0.61 %, at 79.00 % of 0.0862 m beyond the wrist.
TEST_F(Statics, DeLevaArmTorques) {
  const double M = 73.0;
  const double upper_arm = 0.0271 * M * 0.5772 * 0.2817;
  const double forearm_about_elbow = 0.0162 * M * 0.4574 * 0.2689 + 0.0061 * M * (0.2689 + 0.7900 * 0.0862);
  const double elbow = kG * forearm_about_elbow;
  const double shoulder = kG * (upper_arm + (0.0162 + 0.0061) * M * 0.2817 + forearm_about_elbow);

  Q16 q = Q16::Zero();
  q[6] = -kPi / 2;  // left arm straight, forward
  Q16 tau = hold(q);
  ASSERT_NEAR(data.oMi[8].p.z(), origin(6).z(), 1e-12) << "the arm is horizontal";
  EXPECT_NEAR(std::abs(tau[6]), 10.55, 0.01 * 10.55);
  EXPECT_NEAR(std::abs(tau[6]), shoulder, 1e-12);
  EXPECT_LT(tau[6], 0);  // holding the arm up forward is a negative (backwards) pitch torque

  q = Q16::Zero();
  q[8] = -kPi / 2;  // left forearm forward, upper arm hanging
  tau = hold(q);
  ASSERT_NEAR(data.oMi[8].p.z(), origin(8).z(), 1e-12) << "the forearm is horizontal";
  ASSERT_GT(data.oMi[8].p.x(), origin(8).x());
  EXPECT_NEAR(std::abs(tau[8]), 2.90, 0.01 * 2.90);
  EXPECT_NEAR(std::abs(tau[8]), elbow, 1e-12);
  // the shoulder then carries the same moment (the upper arm hangs plumb)
  EXPECT_NEAR(tau[6], tau[8], 1e-12);

  std::printf("  shoulder, straight arm forward: %.4f N m; elbow, forearm forward: %.4f N m\n", shoulder, elbow);
}

// Whole-body centre of mass: forward kinematics against a sum over KDL's link frames, and at the
// home pose by hand.
TEST_F(Statics, WholeBodyCentreOfMass) {
  const auto& d = model.description();
  const KDL::Tree tree = humandyn::testing::kdl_tree(d);
  KDL::TreeFkSolverPos_recursive kdl(tree);
  double worst = 0;
  for (const auto& s : random_states(16, 100, 35)) {
    const Q16 q = s.q;
    forward_kinematics(model, data, q);
    Eigen::Vector3d first_moment = d.base_body.mass * (d.base_pose * d.base_body.com);
    double mass = d.base_body.mass;
    for (int i = 0; i < 16; ++i) {
      KDL::Frame F;
      ASSERT_GE(kdl.JntToCart(humandyn::testing::to_jnt(s.q), F, humandyn::testing::kdl_segment_name(d, i)), 0);
      const KDL::Vector c = F * humandyn::testing::to_kdl(d.joints[std::size_t(i)].body.com);
      first_moment += d.joints[std::size_t(i)].body.mass * (d.base_pose * Eigen::Vector3d(c.x(), c.y(), c.z()));
      mass += d.joints[std::size_t(i)].body.mass;
    }
    worst = std::max(worst, (data.com - first_moment / mass).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(worst, 1e-12);

  // home pose: left-right symmetric about the pelvis (y = 0); ahead of the ankles only by the two
  // feet's offsets
  forward_kinematics(model, data, Q16::Zero());
  EXPECT_NEAR(data.com.y(), 0.0, 1e-12);
  const double foot_x = (0.4415 - 0.25) * 0.2581;
  EXPECT_NEAR(data.com.x(), 2 * params.foot.mass * foot_x / model.total_mass(), 1e-12);
}

}  // namespace

}  // namespace test_statics
