// Anatomical angles: one name and one sign per joint whichever foot the body stands on. Proven by
// forward kinematics: each joint's positive anatomical angle moves its segment the anatomical way,
// measured from landmarks in the proximal segment's axes, in the right-stance, left-stance and
// floating forms; and one pose reads the same anatomical angles in all three.
#include "humandyn/anatomy.hpp"
#include "humandyn/floating.hpp"
#include "humandyn/motion/landmarks.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <string>

namespace test_anatomy {

using namespace humandyn;

namespace {

// Body-fixed points: the fit's landmarks (motion/landmarks.hpp), each on a link (by name) and where it stands
// at home (q = 0; every form stands in the same pose there, so the points are the same for all).
using enum motion::Landmark;
constexpr int num_points = int(motion::Landmark::count);
const char* const point_link[num_points] = {"pelvis",      "r_thigh",    "r_shank",     "r_shank",   "r_foot",
                                            "l_thigh",     "l_shank",    "l_shank",     "l_foot",    "pelvis",
                                            "upper_body",  "upper_body", "r_upper_arm", "r_forearm", "r_forearm",
                                            "l_upper_arm", "l_forearm",  "l_forearm"};

// The points, indexed by landmark.
struct Points {
  std::array<Eigen::Vector3d, num_points> at;
  Eigen::Vector3d& operator[](motion::Landmark l) { return at[std::size_t(l)]; }
  const Eigen::Vector3d& operator[](motion::Landmark l) const { return at[std::size_t(l)]; }
};

// The landmarks of the right-stance model at home: the joint centres, a toe ahead of each ankle on the
// sole, a lower-back point above the mid-hip point, a head point above the neck.
Points home_points(const SeedParameters& p) {
  const auto model = human_model(p);
  Data<HumanModel<double>> d(model);
  forward_kinematics(model, d, HumanModel<double>::JointVector::Zero());
  const auto o = [&](const char* link) { return d.oMi[std::size_t(seed_body.link_index(link))].p; };
  Points x;
  x[r_ankle] = model.base_pose().p;
  x[r_knee] = o("r_shank");
  x[r_hip] = o("r_thigh");
  x[pelvis] = o("pelvis");
  x[l_hip] = o("l_hip_link");
  x[l_knee] = o("l_thigh");
  x[l_ankle] = o("l_shank");
  x[r_toe] = x[r_ankle] + Eigen::Vector3d(0.15, 0, -p.a16);
  x[l_toe] = x[l_ankle] + Eigen::Vector3d(0.15, 0, -p.a16);
  x[lower_back] = x[pelvis] + Eigen::Vector3d(0, 0, 0.1);
  x[neck] = o("upper_body");
  x[head] = x[neck] + Eigen::Vector3d(0, 0, 0.2);
  x[r_shoulder] = o("r_shoulder_link");
  x[r_elbow] = o("r_upper_arm");
  x[r_wrist] = o("r_forearm");
  x[l_shoulder] = o("l_shoulder_link");
  x[l_elbow] = o("l_upper_arm");
  x[l_wrist] = o("l_forearm");
  return x;
}

// The points of a model at q: each carried by its link from home.
template <class Model>
Points points(const Model& model, const Points& home, const typename Model::JointVector& q) {
  Data<Model> d(model), d0(model);
  forward_kinematics(model, d, q);
  forward_kinematics(model, d0, Model::JointVector::Zero());
  const auto& desc = model.description();
  Points x;
  for (int i = 0; i < num_points; ++i) {
    Pose<double> now = model.base_pose(), then = model.base_pose();
    for (int k = 0; k < Model::nj; ++k)
      if (desc.joints[std::size_t(k)].link_name == point_link[i])
        now = d.oMi[std::size_t(k)], then = d0.oMi[std::size_t(k)];
    x.at[std::size_t(i)] = now * (then.inverse() * home.at[std::size_t(i)]);
  }
  return x;
}

// The anatomical angles measured from points, each in its proximal segment's axes (x forward, y left,
// z up at home): the pelvis's from the hips and the lower back, the trunk's from the shoulders and the
// neck. Exact for one joint moved from home.
std::map<std::string, double> measure(const Points& x) {
  const auto axes = [](const Eigen::Vector3d& left, const Eigen::Vector3d& up) {
    Eigen::Matrix3d A;
    const Eigen::Vector3d y = left.normalized(), z = (up - up.dot(y) * y).normalized();
    A << y.cross(z), y, z;
    return A;
  };
  const Eigen::Matrix3d pelvis_axes = axes(x[l_hip] - x[r_hip], x[lower_back] - x[pelvis]);
  const Eigen::Matrix3d trunk_axes = axes(x[l_shoulder] - x[r_shoulder], x[neck] - x[pelvis]);
  const auto in = [](const Eigen::Matrix3d& A, const Eigen::Vector3d& v) { return Eigen::Vector3d(A.transpose() * v); };
  // the signed angle from a to b about the axis n
  const auto turn = [](const Eigen::Vector3d& a, const Eigen::Vector3d& b, const Eigen::Vector3d& n) {
    return std::atan2(a.cross(b).dot(n), a.dot(b));
  };
  const Eigen::Vector3d y = pelvis_axes.col(1), yt = trunk_axes.col(1);
  std::map<std::string, double> m;
  for (const auto& [side, hip, knee, ankle, toe, s] :
       {std::tuple{"r", r_hip, r_knee, r_ankle, r_toe, -1.0}, std::tuple{"l", l_hip, l_knee, l_ankle, l_toe, 1.0}}) {
    const std::string n = side;
    const Eigen::Vector3d t = in(pelvis_axes, x[knee] - x[hip]);
    m[n + "_hip_flexion"] = std::atan2(t.x(), -t.z());
    m[n + "_hip_abduction"] = std::atan2(s * t.y(), -t.z());
    m[n + "_knee_flexion"] = turn(x[knee] - x[hip], x[ankle] - x[knee], y);
    // the angle between the shank (knee to ankle) and the foot (ankle to toe) opens as the toes come up
    const Eigen::Vector3d shank = x[ankle] - x[knee], foot = x[toe] - x[ankle];
    m[n + "_ankle_dorsiflexion"] = std::atan2(shank.cross(foot).norm(), shank.dot(foot));
  }
  const Eigen::Vector3d t = in(pelvis_axes, x[neck] - x[pelvis]), l = in(pelvis_axes, x[l_shoulder] - x[r_shoulder]);
  m["trunk_flexion"] = std::atan2(t.x(), t.z());
  m["trunk_rotation"] = std::atan2(-l.x(), l.y());
  for (const auto& [side, shoulder, elbow, wrist, s] :
       {std::tuple{"r", r_shoulder, r_elbow, r_wrist, -1.0}, std::tuple{"l", l_shoulder, l_elbow, l_wrist, 1.0}}) {
    const std::string n = side;
    const Eigen::Vector3d u = in(trunk_axes, x[elbow] - x[shoulder]);
    m[n + "_shoulder_flexion"] = std::atan2(u.x(), -u.z());
    m[n + "_shoulder_abduction"] = std::atan2(s * u.y(), -u.z());
    m[n + "_elbow_flexion"] = turn(x[elbow] - x[shoulder], x[wrist] - x[elbow], -yt);
  }
  return m;
}

}  // namespace

namespace {

struct Forms {
  SeedParameters p = default_parameters();
  HumanModel<double> right = human_model(p), left = left_stance_model(p);
  FloatingHumanModel<double> floating = floating_model(p);
  Points home = home_points(p);
};

// Sets one anatomical angle in a form, the others zero, and checks that the landmarks say exactly that.
template <class Model>
void check_each_joint(const Model& model, BodyForm form, const Points& home) {
  const auto m0 = measure(points(model, home, Model::JointVector::Zero()));
  for (int i = 0; i < 16; ++i)
    for (double angle : {0.3, -0.2, 0.7}) {
      std::array<double, 16> a{};
      a[std::size_t(i)] = angle;
      typename Model::JointVector q = Model::JointVector::Zero();
      dh_angles(form, a, q);
      const auto m = measure(points(model, home, q));
      for (const auto& j : anatomical_joints) {
        const double want = j.name == std::string(anatomical_joints[std::size_t(i)].name) ? angle : 0.0;
        EXPECT_NEAR(m.at(j.name) - m0.at(j.name), want, 1e-12)
            << "form " << int(form) << ", " << anatomical_joints[std::size_t(i)].name << " = " << angle << ": "
            << j.name << " (" << j.positive << ")";
      }
    }
}

}  // namespace

TEST(Anatomy, EachPositiveAngleMovesItsSegmentTheAnatomicalWayInEveryForm) {
  const Forms f;
  check_each_joint(f.right, BodyForm::RightStance, f.home);
  check_each_joint(f.left, BodyForm::LeftStance, f.home);
  check_each_joint(f.floating, BodyForm::Floating, f.home);
}

TEST(Anatomy, OnePoseReadsTheSameAnglesWhicheverFootCarriesIt) {
  // a pose of the right-stance form, carried to the left-stance and floating forms by the exact state
  // maps: every anatomical angle is the same number (mod 2 pi)
  const Forms f;
  const StanceSwitch<HumanModel<double>, HumanModel<double>> to_left(f.right, f.left);
  const StanceSwitch<HumanModel<double>, FloatingHumanModel<double>> to_floating(f.right, f.floating);
  for (int n = 0; n < 200; ++n) {
    HumanModel<double>::JointVector q;
    for (int k = 0; k < 16; ++k) q[k] = 1.2 * std::sin(0.37 * n * (k + 1) + 0.5 * k);
    const auto zero = HumanModel<double>::JointVector::Zero();
    StanceState<HumanModel<double>> l;
    StanceState<FloatingHumanModel<double>> fl;
    to_left(f.right, f.left, q, zero, l);
    to_floating(f.right, f.floating, q, zero, fl);
    std::array<double, 16> a, b, c;
    anatomical_angles(BodyForm::RightStance, q, a);
    anatomical_angles(BodyForm::LeftStance, l.q, b);
    anatomical_angles(BodyForm::Floating, fl.q, c);
    for (int i = 0; i < 16; ++i) {
      EXPECT_NEAR(std::remainder(b[std::size_t(i)] - a[std::size_t(i)], 2 * M_PI), 0, 1e-12)
          << anatomical_joints[std::size_t(i)].name;
      EXPECT_NEAR(std::remainder(c[std::size_t(i)] - a[std::size_t(i)], 2 * M_PI), 0, 1e-12)
          << anatomical_joints[std::size_t(i)].name;
    }
  }
}

TEST(Anatomy, TheStanceKneeAndTheSwingKneeTurnOppositeWays) {
  // in the right-stance form a bent right (stance) knee has a negative DH angle, a bent left (swing)
  // knee a positive one; standing on the left foot, the other way round
  const AnatomicalMap r = anatomical_map(BodyForm::RightStance), l = anatomical_map(BodyForm::LeftStance);
  const int rk = 1, lk = 14;  // anatomical_joints: r_knee_flexion, l_knee_flexion
  EXPECT_EQ(r.sign[rk], -1);
  EXPECT_EQ(r.sign[lk], 1);
  EXPECT_EQ(l.sign[rk], 1);
  EXPECT_EQ(l.sign[lk], -1);
  // and every map is a signed permutation: anatomical -> DH -> anatomical is the identity
  for (BodyForm form : {BodyForm::RightStance, BodyForm::LeftStance, BodyForm::Floating}) {
    std::array<double, 16> a, back;
    for (int i = 0; i < 16; ++i) a[std::size_t(i)] = 0.1 * i - 0.7;
    Eigen::Matrix<double, 16, 1> q;
    dh_angles(form, a, q);
    anatomical_angles(form, q, back);
    EXPECT_EQ(a, back);
  }
}

}  // namespace test_anatomy
