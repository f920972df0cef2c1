// Stance switching (stance.hpp): each stance model against KDL on its own tree, mirror symmetry of the
// left-stance model, and the switch itself: every link's world pose and velocity, and the whole-body
// centre of mass, the same before and after; no allocation.
#include "humandyn/humandyn.hpp"
#include "humandyn/scene.hpp"
#include "humandyn/stance.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <kdl/jntarray.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <Eigen/LU>

#include <string>
#include <vector>

namespace test_stance {

namespace {

using namespace humandyn;
using Vec16 = Eigen::Matrix<double, 16, 1>;
using Model = HumanModel<double>;

constexpr double kTolerance = 1e-10;

using Motion = humandyn::testing::FixedJointState<16>;

// Reproducible random motions: |q| <= q_max, |qd| <= 5 rad/s, |qdd| <= 20 rad/s^2.
std::vector<Motion> random_motions(int n, unsigned seed, double q_max = 3.14159) {
  return humandyn::testing::random_states<Vec16>(16, n, seed, q_max, 5.0, 20.0);
}

double scaled_error(const Vec16& a, const Vec16& b) {
  return ((a - b).array().abs() / b.array().abs().max(1.0)).maxCoeff();
}

// Every body of a model (0: the base, k + 1: link k) in the world, described by what belongs to the
// body and not to a model's choice of frames: its centre of mass, its inertia tensor about it in world
// axes, its angular velocity and the velocity of its centre of mass (the base at rest). Written out here,
// apart from the code under test: w_k = w_p + z qd, v_k = v_p + w_p x (o_k - o_p) + qd z x (o_k - b) for
// the frame origins o, with z and b the joint's axis and a point on it.
struct BodyMotion {
  std::string name;
  double mass;
  Eigen::Vector3d com;
  Eigen::Matrix3d inertia;
  Eigen::Vector3d w, v_com;
};

std::vector<BodyMotion> body_motions(const Model& model, const Vec16& q, const Vec16& qd) {
  Data<Model> data(model);
  forward_kinematics(model, data, q);
  const auto& d = model.description();
  const auto body = [](const std::string& name, const RigidBodyInertia<double>& b, const Pose<double>& X,
                       const Eigen::Vector3d& w, const Eigen::Vector3d& v_origin) {
    const Eigen::Vector3d c = X * b.com;
    return BodyMotion{name, b.mass, c, X.R * b.inertia * X.R.transpose(), w, v_origin + w.cross(c - X.p)};
  };
  std::vector<Pose<double>> X{model.base_pose()};
  std::vector<Eigen::Vector3d> w{Eigen::Vector3d::Zero()}, v{Eigen::Vector3d::Zero()};
  std::vector<BodyMotion> out{body(d.base_link_name, d.base_body, X[0], w[0], v[0])};
  for (int k = 0; k < 16; ++k) {
    const auto& j = d.joints[std::size_t(k)];
    const auto p = std::size_t(j.parent + 1);
    const Pose<double> P = j.mounted ? X[p] * j.mount : X[p];
    const Eigen::Vector3d z = P.R.col(2), o = data.oMi[std::size_t(k)].p;
    X.push_back(data.oMi[std::size_t(k)]);
    w.push_back(w[p] + z * qd[k]);
    v.push_back(v[p] + w[p].cross(o - X[p].p) + qd[k] * z.cross(o - P.p));
    out.push_back(body(j.link_name, j.body, X.back(), w.back(), v.back()));
  }
  return out;
}

const BodyMotion& find(const std::vector<BodyMotion>& bodies, const std::string& name) {
  for (const auto& b : bodies)
    if (b.name == name) return b;
  throw std::runtime_error("no body " + name);
}

// Largest difference over all bodies, matched by name, of centre of mass, world inertia, angular
// velocity and centre-of-mass velocity (massless bodies: angular velocity only); the velocities taken
// relative to the body `relative_to` (its own motion subtracted as a rigid motion).
double max_difference(const std::vector<BodyMotion>& a, const std::vector<BodyMotion>& b,
                      const std::string& relative_to) {
  const BodyMotion& ra = find(a, relative_to);
  const BodyMotion& rb = find(b, relative_to);
  double e = 0;
  for (const auto& x : a) {
    const BodyMotion& y = find(b, x.name);
    e = std::max(e, ((x.w - ra.w) - (y.w - rb.w)).cwiseAbs().maxCoeff());
    if (x.mass == 0) continue;
    e = std::max(e, (x.com - y.com).cwiseAbs().maxCoeff());
    e = std::max(e, (x.inertia - y.inertia).cwiseAbs().maxCoeff());
    e = std::max(e,
                 ((x.v_com - ra.v_com - ra.w.cross(x.com - ra.com)) - (y.v_com - rb.v_com - rb.w.cross(y.com - rb.com)))
                     .cwiseAbs()
                     .maxCoeff());
  }
  return e;
}

// --- each stance model against KDL --------------------------------------------------------------

void check_against_kdl(const ModelDescription<double>& desc) {
  const KDL::Tree tree = humandyn::testing::kdl_tree(desc);
  KDL::TreeIdSolver_RNE solver(tree, humandyn::testing::kdl_gravity(desc));
  const Model model(desc);
  Data<Model> data(model);
  double max_error = 0, max_torque = 0;
  for (const Motion& m : random_motions(300, 3)) {
    KDL::JntArray q(16), qd(16), qdd(16), tau(16);
    q.data = m.q;
    qd.data = m.qd;
    qdd.data = m.qdd;
    ASSERT_EQ(solver.CartToJnt(q, qd, qdd, KDL::WrenchMap{}, tau), 0);
    const Vec16 expected = tau.data;
    max_error = std::max(max_error, scaled_error(rnea(model, data, m.q, m.qd, m.qdd), expected));
    max_torque = std::max(max_torque, expected.cwiseAbs().maxCoeff());
  }
  EXPECT_LE(max_error, kTolerance) << desc.name;
  EXPECT_GT(max_torque, 10.0);
}

TEST(StanceModels, RightStanceMatchesKdl) { check_against_kdl(human_description(default_parameters())); }
TEST(StanceModels, LeftStanceMatchesKdl) {
  check_against_kdl(left_stance_description(default_parameters()));
  check_against_kdl(left_stance_description(paper_parameters()));
}

TEST(StanceModels, LeftStanceIsRootedAtTheLeftAnkle) {
  const Model left = left_stance_model(default_parameters());
  EXPECT_EQ(left.description().base_link_name, "l_foot");
  EXPECT_EQ(left.joint_name(0), "l_ankle_pitch");
  EXPECT_EQ(left.joint_name(6), "r_shoulder_pitch");
  EXPECT_EQ(left.joint_name(15), "r_ankle_pitch");
  EXPECT_GT(left.base_pose().p.y(), 0.05) << "the left ankle stands on the left (+y)";
  EXPECT_NEAR(left.total_mass(), default_model().total_mass(), 1e-12);
}

// --- mirror symmetry ------------------------------------------------------------------------------

TEST(MirrorSymmetry, MirroredMotionGivesMirroredTorquesAndFrames) {
  // The mirror image of a right-stance motion, in the left-stance model, has the same joint numbers;
  // every frame is the mirror of its partner's and the torques are the same (mirror_description).
  for (const auto& params : {default_parameters(), female_parameters(), paper_parameters()}) {
    const Model right = human_model(params), left = left_stance_model(params);
    Data<Model> dr(right), dl(left);
    // the body's mid-plane y = c, half-way between the ankles at q = 0: mirror in y = 0, then shift by 2c
    forward_kinematics(right, dr, Vec16::Zero());
    const double c = 0.5 * (right.base_pose().p.y() + dr.oMi[14].p.y());
    const auto mirrored = [&](const Pose<double>& X) {
      Pose<double> Y = mirror_pose(X);
      Y.p.y() += 2 * c;
      return Y;
    };
    double torque_error = 0, frame_error = 0, max_torque = 0;
    for (const Motion& m : random_motions(200, 5)) {
      const Vec16 tr = rnea(right, dr, m.q, m.qd, m.qdd);
      const Vec16 tl = rnea(left, dl, m.q, m.qd, m.qdd);
      torque_error = std::max(torque_error, scaled_error(tl, tr));
      max_torque = std::max(max_torque, tr.cwiseAbs().maxCoeff());
      forward_kinematics(right, dr, m.q);
      forward_kinematics(left, dl, m.q);
      for (int k = 0; k < 16; ++k) {
        const Pose<double> X = mirrored(dr.oMi[std::size_t(k)]);
        frame_error = std::max(frame_error, (X.R - dl.oMi[std::size_t(k)].R).cwiseAbs().maxCoeff() +
                                                (X.p - dl.oMi[std::size_t(k)].p).cwiseAbs().maxCoeff());
      }
      const Eigen::Vector3d com_mirrored(dr.com.x(), 2 * c - dr.com.y(), dr.com.z());
      frame_error = std::max(frame_error, (com_mirrored - dl.com).cwiseAbs().maxCoeff());
    }
    EXPECT_LE(torque_error, kTolerance) << params.name;
    EXPECT_LE(frame_error, 1e-12) << params.name;
    EXPECT_GT(max_torque, 10.0);
  }
}

TEST(MirrorSymmetry, AtHomeBothModelsStandInOnePose) {
  // At q = 0 both models stand in the same pose: every segment's centre of mass, found by name, is at
  // the same place in both, and the whole body's is on the mid-plane.
  const Model right = default_model(), left = left_stance_model(default_parameters());
  Data<Model> dr(right), dl(left);
  forward_kinematics(right, dr, Vec16::Zero());
  forward_kinematics(left, dl, Vec16::Zero());
  EXPECT_NEAR(dr.com.y(), 0.0, 1e-12);
  EXPECT_LE((dr.com - dl.com).norm(), 1e-12);
  const auto com_of = [](const Model& model, const Data<Model>& data, const std::string& link) -> Eigen::Vector3d {
    const auto& d = model.description();
    if (d.base_link_name == link) return model.base_pose() * d.base_body.com;
    return data.com_world[std::size_t([&] {
      for (int k = 0; k < 16; ++k)
        if (d.joints[std::size_t(k)].link_name == link) return k;
      return -1;
    }())];
  };
  int compared = 0;
  for (const auto& j : right.description().joints) {
    if (j.body.mass == 0) continue;
    EXPECT_LE((com_of(right, dr, j.link_name) - com_of(left, dl, j.link_name)).norm(), 1e-12) << j.link_name;
    ++compared;
  }
  EXPECT_LE((com_of(right, dr, "r_foot") - com_of(left, dl, "r_foot")).norm(), 1e-12);
  EXPECT_LE((com_of(right, dr, "l_foot") - com_of(left, dl, "l_foot")).norm(), 1e-12);
  EXPECT_GE(compared, 10);  // every segment with mass
}

// A body whose base pose is turned (about the vertical, or lying on its side as a URDF with z along the
// ankle axis puts it) is the same body turned: each link's inertia in its own frame is the upright
// body's, and its left-stance model stands where it stands, in the same world (gravity unchanged).
TEST(MirrorSymmetry, ATurnedBodyKeepsItsInertiasAndItsLeftStance) {
  const ModelDescription<double> upright = human_description(default_parameters());
  const Pose<double> yaw{Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()).toRotationMatrix(), Eigen::Vector3d(1, 2, 0)};
  for (const Pose<double>& turn : {yaw, Pose<double>{upright.base_pose.R.transpose(), Eigen::Vector3d::Zero()}}) {
    SeedParameters p = default_parameters();
    p.base_pose = turn * p.base_pose;
    const ModelDescription<double> turned = human_description(p);
    const auto same = [](const RigidBodyInertia<double>& a, const RigidBodyInertia<double>& b) {
      return std::abs(a.mass - b.mass) <= 1e-13 && (a.com - b.com).norm() <= 1e-13 &&
             (a.inertia - b.inertia).norm() <= 1e-13 * std::max(1.0, b.inertia.norm());
    };
    EXPECT_TRUE(same(turned.base_body, upright.base_body));
    for (std::size_t k = 0; k < 16; ++k)
      EXPECT_TRUE(same(turned.joints[k].body, upright.joints[k].body)) << turned.joints[k].link_name;

    const Model right(turned), left(left_stance_description(turned));
    EXPECT_EQ(left.description().gravity, turned.gravity);
    Data<Model> dr(right), dl(left);
    forward_kinematics(right, dr, Vec16::Zero());
    forward_kinematics(left, dl, Vec16::Zero());
    EXPECT_LE((dr.com - dl.com).norm(), 1e-12);
    // the stance switch's own check: every link where it was
    const StanceSwitch<Model, Model> to_left(right, left);
    StanceState<Model> s;
    to_left(right, left, Vec16::Zero(), Vec16::Zero(), s);
    EXPECT_LE(s.q.cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(MirrorSymmetry, MountsAndRuntimeShapesMirrorToo) {
  // a body with mounts (the seed with joints locked mid-chain, as a runtime shape) and its mirror image:
  // the same torques, mirrored frames
  const auto desc = human_description(default_parameters());
  std::vector<bool> locked(16, false);
  for (int i : {1, 5, 8, 14}) locked[std::size_t(i)] = true;
  Eigen::VectorXd q_lock(16);
  for (int i = 0; i < 16; ++i) q_lock[i] = 0.3 * std::sin(2.0 * i + 1.0);
  const AnyModel<double> model(lock_joints(desc, locked, q_lock));
  const AnyModel<double> mirror(mirror_description(model.description()));
  int mounted = 0;
  for (const auto& j : model.description().joints) mounted += j.mounted ? 1 : 0;
  ASSERT_EQ(mounted, 4);
  Data<AnyModel<double>> d(model), dm(mirror);
  double torque_error = 0, frame_error = 0;
  for (const Motion& m : random_motions(50, 17)) {
    const Eigen::VectorXd q = m.q.head(12), qd = m.qd.head(12), qdd = m.qdd.head(12);
    const Eigen::VectorXd t = rnea(model, d, q, qd, qdd);
    const Eigen::VectorXd tm = rnea(mirror, dm, q, qd, qdd);
    torque_error = std::max(torque_error, ((t - tm).array().abs() / t.array().abs().max(1.0)).maxCoeff());
    forward_kinematics(model, d, q);
    forward_kinematics(mirror, dm, q);
    for (int k = 0; k < 12; ++k) {
      const Pose<double> X = mirror_pose(d.oMi[std::size_t(k)]);
      frame_error = std::max(frame_error, (X.R - dm.oMi[std::size_t(k)].R).cwiseAbs().maxCoeff() +
                                              (X.p - dm.oMi[std::size_t(k)].p).cwiseAbs().maxCoeff());
    }
  }
  EXPECT_LE(torque_error, kTolerance);
  EXPECT_LE(frame_error, 1e-12);
}

// --- the switch -----------------------------------------------------------------------------------

TEST(StanceSwitch, RightToLeftKeepsEveryLinkWhereItIsAndMovingAsItDoes) {
  const SeedParameters params = default_parameters();
  const Model right = human_model(params), left = left_stance_model(params);
  const StanceSwitch<Model, Model> to_left(right, left);
  StanceState<Model> s;
  double pose_error = 0, com_error = 0;
  for (const Motion& m : random_motions(100, 7)) {
    to_left(right, left, m.q, m.qd, s);
    const Model left_here = rebase(left, s.base_pose);
    const auto before = body_motions(right, m.q, m.qd);
    const auto after = body_motions(left_here, s.q, s.qd);
    // world poses; velocities relative to the new stance foot (the left model holds it still)
    pose_error = std::max(pose_error, max_difference(before, after, "l_foot"));
    Data<Model> dr(right), dl(left_here);
    forward_kinematics(right, dr, m.q);
    forward_kinematics(left_here, dl, s.q);
    com_error = std::max(com_error, (dr.com - dl.com).norm());
    EXPECT_LE(s.q.cwiseAbs().maxCoeff(), 3.14159265358979323846 + 1e-15);
  }
  EXPECT_LE(pose_error, 1e-10);
  EXPECT_LE(com_error, 1e-12);
}

// The left-stance model's base rides on the right model's left-foot link (l_ankle_pitch's): its pose is that
// link's pose times the switch's base offset in every state, the offset the two models' homes give.
TEST(StanceSwitch, TheNewBaseRidesOnItsBodyAtTheBaseOffset) {
  const SeedParameters params = default_parameters();
  const Model right = human_model(params), left = left_stance_model(params);
  const StanceSwitch<Model, Model> to_left(right, left);
  ASSERT_EQ(to_left.base_body(), right.joint_index("l_ankle_pitch") + 1);
  const int foot = to_left.base_body() - 1;
  Data<Model> home(right);
  forward_kinematics(right, home, Model::JointVector::Zero());
  const Pose<double> offset = home.oMi[std::size_t(foot)].inverse() * left.base_pose();
  EXPECT_LE((to_left.base_offset().R - offset.R).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LE((to_left.base_offset().p - offset.p).cwiseAbs().maxCoeff(), 1e-15);
  StanceState<Model> s;
  Data<Model> dr(right);
  double error = 0;
  for (const Motion& m : random_motions(100, 11)) {
    to_left(right, left, m.q, m.qd, s);
    forward_kinematics(right, dr, m.q);
    const Pose<double> base = dr.oMi[std::size_t(foot)] * to_left.base_offset();
    error = std::max(
        {error, (base.R - s.base_pose.R).cwiseAbs().maxCoeff(), (base.p - s.base_pose.p).cwiseAbs().maxCoeff()});
  }
  EXPECT_LE(error, 1e-14);
}

TEST(StanceSwitch, AtHeelStrikeWorldVelocitiesAreUnchanged) {
  // the landing foot at rest: joint rates in the null space of its 6 x 16 Jacobian (both feet still)
  const SeedParameters params = female_parameters();
  const Model right = human_model(params), left = left_stance_model(params);
  const StanceSwitch<Model, Model> to_left(right, left);
  StanceState<Model> s;
  double error = 0, foot_speed = 0, max_speed = 0;
  for (const Motion& m : random_motions(30, 9, 0.8)) {
    Eigen::Matrix<double, 6, 16> J;
    for (int i = 0; i < 16; ++i) {
      const auto b = find(body_motions(right, m.q, Vec16::Unit(i)), "l_foot");
      J.col(i) << b.w, b.v_com;
    }
    const Eigen::MatrixXd K = Eigen::FullPivLU<Eigen::MatrixXd>(J).kernel();
    ASSERT_EQ(K.cols(), 10);
    const Vec16 qd = K * (m.qd.head(10) * 3.0);
    const auto before = body_motions(right, m.q, qd);
    foot_speed = std::max(foot_speed, find(before, "l_foot").v_com.norm() + find(before, "l_foot").w.norm());
    to_left(right, left, m.q, qd, s);
    const auto after = body_motions(rebase(left, s.base_pose), s.q, s.qd);
    for (const auto& x : before) {
      const auto& y = find(after, x.name);
      error = std::max(error, (x.w - y.w).cwiseAbs().maxCoeff() + (x.v_com - y.v_com).cwiseAbs().maxCoeff());
      max_speed = std::max(max_speed, x.v_com.norm());
    }
  }
  EXPECT_LE(foot_speed, 1e-10);
  EXPECT_LE(error, 1e-10);
  EXPECT_GT(max_speed, 0.5) << "the bodies must actually move";
}

TEST(StanceSwitch, SwitchingBackRestoresTheState) {
  const SeedParameters params = paper_parameters();
  const Model right = human_model(params), left = left_stance_model(params);
  const StanceSwitch<Model, Model> to_left(right, left), to_right(left, right);
  StanceState<Model> l, r;
  for (const Motion& m : random_motions(50, 11, 3.0)) {
    to_left(right, left, m.q, m.qd, l);
    to_right(rebase(left, l.base_pose), right, l.q, l.qd, r);
    EXPECT_LE((r.q - m.q).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LE((r.qd - m.qd).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LE((r.base_pose.p - right.base_pose().p).norm() + (r.base_pose.R - right.base_pose().R).norm(), 1e-12);
  }
}

// Every angle comes out in (-pi, pi], a half turn as +pi (std::remainder alone gives -pi for some).
TEST(StanceSwitch, AHalfTurnComesOutAsPlusPi) {
  const SeedParameters params = default_parameters();
  const Model right = human_model(params), left = left_stance_model(params);
  const StanceSwitch<Model, Model> to_left(right, left), to_right(left, right);
  StanceState<Model> l, r;
  Vec16 hip = Vec16::Zero();
  hip[3] = M_PI;  // the right hip pitch, a half turn
  for (const Vec16& q : std::vector<Vec16>{hip, Vec16::Constant(M_PI), Vec16::Constant(-M_PI)}) {
    to_left(right, left, q, Vec16::Zero(), l);
    to_right(rebase(left, l.base_pose), right, l.q, l.qd, r);
    for (const auto* x : {&l.q, &r.q})
      for (int k = 0; k < 16; ++k) {
        EXPECT_GT((*x)[k], -M_PI) << k;
        EXPECT_LE((*x)[k], M_PI) << k;
      }
    for (int k = 0; k < 16; ++k) EXPECT_LE(std::abs(std::remainder(r.q[k] - q[k], 2 * M_PI)), 1e-9) << k;
  }
}

TEST(StanceSwitch, UpperBodyTorquesDoNotDependOnTheStanceFoot) {
  // With the legs locked, the pelvis is fixed: the upper-body scene of the right-stance model and that
  // of the left-stance model after a switch see the same upper body moving the same way, so each
  // upper-body joint has the same torque (its axis may point the other way in the mirrored model: the
  // sign s_i = +-1 is read from the switch, which maps a unit rate of joint i to s_i).
  using Upper = scenes::UpperBody;
  const SeedParameters params = default_parameters();
  const Model right = human_model(params), left = left_stance_model(params);
  const StanceSwitch<Model, Model> to_left(right, left);
  StanceState<Model> s;
  double error = 0, max_torque = 0;
  for (const Motion& m : random_motions(30, 19, 1.2)) {
    Vec16 qd = m.qd, qdd = m.qdd;
    for (int i : {0, 1, 2, 3, 12, 13, 14, 15}) qd[i] = qdd[i] = 0;  // legs held
    // where each joint of the right model sits in the left one, and with which sign
    std::array<int, 16> index{};
    std::array<double, 16> sign{};
    for (int i = 0; i < 16; ++i) {
      index[std::size_t(i)] = left.joint_index(right.joint_name(i));  // the same physical joint
      to_left(right, left, m.q, Vec16::Unit(i), s);
      sign[std::size_t(i)] = s.qd[index[std::size_t(i)]];
      ASSERT_NEAR(std::abs(sign[std::size_t(i)]), 1.0, 1e-12) << right.joint_name(i);
    }
    to_left(right, left, m.q, qd, s);
    Vec16 qdd_left = Vec16::Zero();
    for (int i = 0; i < 16; ++i) qdd_left[index[std::size_t(i)]] = sign[std::size_t(i)] * qdd[i];
    const Model left_here = rebase(left, s.base_pose);
    const auto ur = Upper::model<double>(right.description(), Eigen::VectorXd(m.q));
    const auto ul = Upper::model<double>(left_here.description(), Eigen::VectorXd(s.q));
    Data<Upper::model_type<double>> dr(ur), dl(ul);
    const Vec16 tr =
        Upper::expand(scene_rnea<Upper>(ur, dr, Upper::reduce(m.q), Upper::reduce(qd), Upper::reduce(qdd)));
    const Vec16 tl =
        Upper::expand(scene_rnea<Upper>(ul, dl, Upper::reduce(s.q), Upper::reduce(s.qd), Upper::reduce(qdd_left)));
    for (int i = 4; i < 12; ++i) {
      const double expected = tr[i], got = sign[std::size_t(i)] * tl[index[std::size_t(i)]];
      error = std::max(error, std::abs(got - expected) / std::max(1.0, std::abs(expected)));
      max_torque = std::max(max_torque, std::abs(expected));
    }
  }
  EXPECT_LE(error, kTolerance);
  EXPECT_GT(max_torque, 10.0);
}

TEST(StanceSwitch, RefusesModelsOfDifferentBodies) {
  const Model right = human_model(default_parameters());
  const Model other_left = left_stance_model(paper_parameters());
  EXPECT_THROW((StanceSwitch<Model, Model>(right, other_left)), ModelError);
  // a body a nanometre longer in the thigh is another body, and the message shows by how much
  SeedParameters longer = default_parameters();
  longer.a2 += 1e-9;
  try {
    StanceSwitch<Model, Model> s(right, left_stance_model(longer));
    FAIL() << "a thigh 1 nm longer must be refused";
  } catch (const ModelError& e) {
    const std::string what = e.what(), by = "misses its place by ";
    ASSERT_NE(what.find(by), std::string::npos) << what;
    const double misfit = std::stod(what.substr(what.find(by) + by.size()));  // (a sub-nanometre misfit)
    EXPECT_GT(misfit, 1e-11) << what;
    EXPECT_LT(misfit, 1e-8) << what;
  }
  auto renamed = left_stance_description(default_parameters());
  renamed.joints[3].link_name = "hip";
  try {
    StanceSwitch<Model, Model> s(right, Model(renamed));
    FAIL() << "a link missing from the source model must be refused";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("'hip'"), std::string::npos) << e.what();
  }
}

TEST(StanceSwitch, NeverAllocatesAndWorksInFloat) {
  const SeedParameters params = default_parameters();
  const Model right = human_model(params), left = left_stance_model(params);
  const StanceSwitch<Model, Model> to_left(right, left);
  StanceState<Model> s;
  const Motion m = random_motions(1, 13)[0];
  Eigen::internal::set_is_malloc_allowed(false);
  to_left(right, left, m.q, m.qd, s);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(s.q.allFinite() && s.qd.allFinite());

  using ModelF = HumanModel<float>;
  const ModelF rf = human_model<float>(params), lf = left_stance_model<float>(params);
  const StanceSwitch<ModelF, ModelF> to_left_f(rf, lf);
  StanceState<ModelF> sf;
  to_left_f(rf, lf, m.q.cast<float>(), m.qd.cast<float>(), sf);
  EXPECT_LE((sf.q.cast<double>() - s.q).cwiseAbs().maxCoeff(), 1e-4);
  EXPECT_LE((sf.qd.cast<double>() - s.qd).cwiseAbs().maxCoeff(), 1e-3);
}

}  // namespace

}  // namespace test_stance
