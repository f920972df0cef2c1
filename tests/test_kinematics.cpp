// Forward kinematics (algorithm/kinematics.hpp) against KDL's tree solver, and the home pose of the
// seed's Table 1 read as standard DH.
#include "humandyn/humandyn.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <kdl/treefksolverpos_recursive.hpp>

#include <Eigen/Geometry>

namespace test_kinematics {

namespace {

using namespace humandyn;
using humandyn::testing::kdl_segment_name;
using humandyn::testing::random_states;
using humandyn::testing::to_jnt;

constexpr double kPi = 3.14159265358979323846;

Pose<double> from_kdl(const KDL::Frame& F) {
  Pose<double> X;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c) X.R(r, c) = F.M(r, c);
  X.p = Eigen::Vector3d(F.p.x(), F.p.y(), F.p.z());
  return X;
}

struct FkError {
  double position = 0, rotation = 0;
};

// Every link frame of `model` against KDL's, over random configurations. KDL gives frames in the
// base frame; the model gives them in the world, base_pose apart.
template <class M>
FkError compare_with_kdl(const M& model, const ModelDescription<double>& desc, int configurations, unsigned seed) {
  const KDL::Tree tree = humandyn::testing::kdl_tree(desc);
  KDL::TreeFkSolverPos_recursive kdl(tree);
  Data<M> data(model);
  FkError e;
  for (const auto& s : random_states(model.size(), configurations, seed)) {
    forward_kinematics(model, data, s.q);
    for (int i = 0; i < model.size(); ++i) {
      KDL::Frame F;
      EXPECT_GE(kdl.JntToCart(to_jnt(s.q), F, kdl_segment_name(desc, i)), 0);
      const Pose<double> expected = desc.base_pose * from_kdl(F);
      const auto& X = data.oMi[std::size_t(i)];
      e.position = std::max(e.position, (X.p - expected.p).cwiseAbs().maxCoeff());
      e.rotation = std::max(e.rotation, (X.R - expected.R).cwiseAbs().maxCoeff());
      // each link's centre of mass is its body's, carried by the link frame
      const Eigen::Vector3d com = expected * desc.joints[std::size_t(i)].body.com;
      e.position = std::max(e.position, (data.com_world[std::size_t(i)] - com).cwiseAbs().maxCoeff());
    }
  }
  return e;
}

TEST(ForwardKinematicsVsKdl, EveryLinkOfTheBuiltInModels) {
  for (auto make : {default_parameters, female_parameters, paper_parameters}) {
    const ModelDescription<double> desc = human_description(make());
    SCOPED_TRACE(desc.name);
    const FkError s = compare_with_kdl(HumanModel<double>(desc), desc, 100, 21);
    EXPECT_LE(s.position, 1e-12);
    EXPECT_LE(s.rotation, 1e-12);
    const FkError d = compare_with_kdl(AnyModel<double>(desc), desc, 100, 22);
    EXPECT_LE(d.position, 1e-12);
    EXPECT_LE(d.rotation, 1e-12);
  }
}

TEST(ForwardKinematicsVsKdl, MountsAndEveryTwistClass) {
  ModelDescription<double> desc = human_description(default_parameters());
  desc.joints[8].dh.alpha = kPi;   // Pi
  desc.joints[7].dh.alpha = 0.7;   // general
  desc.joints[3].dh.alpha = -2.3;  // general
  for (int i : {0, 4, 9, 12}) {
    auto& j = desc.joints[std::size_t(i)];
    j.mounted = true;
    j.mount.R = Eigen::AngleAxisd(0.2 + 0.1 * i, Eigen::Vector3d(1, -i, 2).normalized()).toRotationMatrix();
    j.mount.p = Eigen::Vector3d(0.01 * i, -0.02, 0.03);
  }
  desc.base_pose.R =
      Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()).toRotationMatrix() * desc.base_pose.R;
  desc.base_pose.p = Eigen::Vector3d(0.3, -0.2, 0.1);
  const FkError e = compare_with_kdl(AnyModel<double>(desc), desc, 100, 23);
  EXPECT_LE(e.position, 1e-12);
  EXPECT_LE(e.rotation, 1e-12);
}

TEST(ForwardKinematics, FloatAgreesWithDouble) {
  const auto md = default_model<double>();
  const auto mf = default_model<float>();
  Data<HumanModel<double>> dd(md);
  Data<HumanModel<float>> df(mf);
  double worst = 0;
  for (const auto& s : random_states(16, 100, 24)) {
    const Eigen::VectorXf q = s.q.cast<float>();
    forward_kinematics(mf, df, q);
    forward_kinematics(md, dd, q.cast<double>());
    for (int i = 0; i < 16; ++i)
      worst =
          std::max(worst, (df.oMi[std::size_t(i)].p.cast<double>() - dd.oMi[std::size_t(i)].p).cwiseAbs().maxCoeff());
    worst = std::max(worst, (df.com.cast<double>() - dd.com).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(worst, 2e-6);  // metres: float's rounding of lengths near 2 m, accumulated over 16 links
}

// The home pose of the paper model (Table 1 with a1 = a2 = 0.43, d4 = 0.09, d6 = 0.5, d7 = 0.19,
// a8 = 0.28, a9 = 0.27 m, the right ankle at the world origin), worked out by hand from the DH rows.
class PaperHomePose : public ::testing::Test {
 protected:
  HumanModel<double> model{human_model<double>(paper_parameters())};
  Data<HumanModel<double>> data{model};
  void SetUp() override { forward_kinematics(model, data, Eigen::Matrix<double, 16, 1>::Zero()); }
  // origin of frame k (1-based, as in the paper); frame 0 is the base
  Eigen::Vector3d origin(int k) const { return k == 0 ? model.base_pose().p : data.oMi[std::size_t(k - 1)].p; }
  // the axis of joint k (1-based): z of its parent's frame
  Eigen::Vector3d axis(int k) const {
    const int parent = model.joint(k - 1).parent;
    return (parent < 0 ? model.base_pose() : data.oMi[std::size_t(parent)]).R.col(2);
  }
};

TEST_F(PaperHomePose, PositionsOfSeedNotes) {
  const auto near = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
    return (a - b).cwiseAbs().maxCoeff() <= 1e-12;
  };
  EXPECT_TRUE(near(origin(0), {0, 0, 0})) << "right ankle " << origin(0).transpose();
  EXPECT_TRUE(near(origin(2), {0, 0, 0.86})) << "right hip " << origin(2).transpose();
  EXPECT_TRUE(near(origin(4), {0, 0.09, 0.86})) << "pelvis centre " << origin(4).transpose();
  EXPECT_TRUE(near(origin(13), {0, 0.18, 0.86})) << "left hip " << origin(13).transpose();
  EXPECT_TRUE(near(origin(15), {0, 0.18, 0})) << "left ankle " << origin(15).transpose();
  EXPECT_TRUE(near(origin(7), {0, 0.28, 1.36})) << "left shoulder " << origin(7).transpose();
  EXPECT_TRUE(near(origin(10), {0, -0.10, 1.36})) << "right shoulder " << origin(10).transpose();
  // the arms hang: elbows a8 and wrists a8 + a9 below the shoulders
  EXPECT_TRUE(near(origin(8), {0, 0.28, 1.36 - 0.28})) << "left elbow " << origin(8).transpose();
  EXPECT_TRUE(near(origin(9), {0, 0.28, 1.36 - 0.55})) << "left wrist " << origin(9).transpose();
  EXPECT_TRUE(near(origin(12), {0, -0.10, 1.36 - 0.55})) << "right wrist " << origin(12).transpose();
}

// The joint axes at the home pose. A reading of Table 1 by its labels gives each axis as a direction without sign
// (lateral, forward, vertical); the DH rows fix the sign, and this is what they give (world: x
// forward, y left, z up):
//   +y (lateral, pointing left): joints 1, 2, 4, 5, 7, 9, 10, 12, 13, 15, 16 (ankle, knee, hip,
//      waist, shoulder and elbow pitch);
//   -x (forward axis, pointing backwards): joints 3, 8, 11, 14 (Table 1's hip "yaw" and shoulder
//      "yaw", which are roll joints, ab-adduction);
//   +z (vertical, up): joint 6 (Table 1's waist "roll", a twist of the waist).
// So pitch angles turn about the left-pointing axis: raising an arm forward is a negative shoulder
// pitch (q7 = -90 degrees), bending the trunk forward a positive waist pitch.
TEST_F(PaperHomePose, JointAxesOfTable1) {
  const Eigen::Vector3d left(0, 1, 0), backwards(-1, 0, 0), up(0, 0, 1);
  const std::array<Eigen::Vector3d, 16> table{
      left, left,      backwards, left,   // 1-4 right leg: ankle, knee, hip roll, hip pitch
      left, up,                           // 5-6 waist: pitch, yaw
      left, backwards, left,              // 7-9 left arm: shoulder pitch, shoulder roll, elbow
      left, backwards, left,              // 10-12 right arm
      left, backwards, left,      left};  // 13-16 left leg: hip pitch, hip roll, knee, ankle
  for (int k = 1; k <= 16; ++k)
    EXPECT_LE((axis(k) - table[std::size_t(k - 1)]).cwiseAbs().maxCoeff(), 1e-12)
        << "joint " << k << " (" << seed_joint_names[std::size_t(k - 1)] << ") axis " << axis(k).transpose();
}

// The waist pitch (joint 5) is coaxial with both hip pitch axes (joints 4 and 13), at every pose of
// the right leg: the same direction, and each axis line passes through the others' points.
TEST_F(PaperHomePose, WaistPitchCoaxialWithBothHipPitches) {
  for (const auto& s : random_states(16, 50, 25)) {
    forward_kinematics(model, data, s.q);
    const Eigen::Vector3d a4 = axis(4), a5 = axis(5), a13 = axis(13);
    const Eigen::Vector3d o4 = origin(3), o5 = origin(4), o13 = origin(4);  // a joint sits at its parent frame's origin
    EXPECT_LE(a4.cross(a5).norm(), 1e-12);
    EXPECT_LE(a4.cross(a13).norm(), 1e-12);
    EXPECT_LE(a4.cross(o5 - o4).norm(), 1e-12);
    EXPECT_LE(a4.cross(o13 - o4).norm(), 1e-12);
    EXPECT_NEAR((o5 - o4).norm(), 0.09, 1e-12);  // d4 apart along the axis
  }
}

}  // namespace

}  // namespace test_kinematics
