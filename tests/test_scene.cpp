// Scenes (scene.hpp): every named scene against the full model on motions that respect it, locked-joint
// merging against the full model with those joints still and against KDL trees with fixed joints, the
// compile-time shapes, output pruning, float, and no allocation.
#include "humandyn/humandyn.hpp"
#include "humandyn/scene.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <kdl/jntarray.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <random>
#include <string>
#include <vector>

namespace test_scene {

namespace {

using namespace humandyn;
using Vec16 = Eigen::Matrix<double, 16, 1>;

constexpr double kTolerance = 1e-10;  // N m, relative to max(1, |tau|)

using Motion = humandyn::testing::FixedJointState<16>;

// Reproducible random motions: |q| <= pi, |qd| <= 5 rad/s, |qdd| <= 20 rad/s^2.
std::vector<Motion> random_motions(int n, unsigned seed) {
  return humandyn::testing::random_states<Vec16>(16, n, seed, 3.14159, 5.0, 20.0);
}

Eigen::VectorXd random_lock_angles(unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.5, 1.5);
  Eigen::VectorXd q(16);
  for (int i = 0; i < 16; ++i) q[i] = u(rng);
  return q;
}

// A scene's name for messages (custom scenes have none).
template <class SceneT>
std::string label() {
  if constexpr (requires { SceneT::name; })
    return std::string(SceneT::name);
  else
    return "custom scene";
}

double scaled_error(double a, double b) { return std::abs(a - b) / std::max(1.0, std::abs(b)); }

// The scene's torques for a full-size motion, as a full-size vector (zero where not an output).
template <class SceneT, class M>
Vec16 scene_torques(const M& model, Data<M>& data, const Motion& m) {
  const auto tau = scene_rnea<SceneT>(model, data, SceneT::reduce(m.q), SceneT::reduce(m.qd), SceneT::reduce(m.qdd));
  return SceneT::expand(tau);
}

// Largest scaled error between a scene's outputs and the full model's torques over `motions`
// (constrained to the scene first when `constrain`), and the largest full torque compared.
struct Comparison {
  double max_error = 0, max_torque = 0;
  int outputs_compared = 0;
};

template <class SceneT>
Comparison compare_scene(const ModelDescription<double>& desc, const Eigen::VectorXd& q_lock,
                         const std::vector<Motion>& motions, bool constrain) {
  const HumanModel<double> full(desc);
  Data<HumanModel<double>> full_data(full);
  const auto model = SceneT::template model<double>(desc, q_lock);
  Data<std::decay_t<decltype(model)>> data(model);
  Comparison c;
  for (Motion m : motions) {
    if (constrain) SceneT::constrain(q_lock, m.q, m.qd, m.qdd);
    const Vec16 expected = rnea(full, full_data, m.q, m.qd, m.qdd);
    const Vec16 got = scene_torques<SceneT>(model, data, m);
    for (int i = 0; i < 16; ++i) {
      if (!SceneT::outputs(i)) {
        EXPECT_EQ(got[i], 0.0) << label<SceneT>() << ": joint " << i + 1 << " is not an output";
        continue;
      }
      c.max_error = std::max(c.max_error, scaled_error(got[i], expected[i]));
      c.max_torque = std::max(c.max_torque, std::abs(expected[i]));
      ++c.outputs_compared;
    }
  }
  return c;
}

// --- compile-time shapes -------------------------------------------------------------------------

// The named locked scenes need no mounts: their base moves to the pelvis / the upper body.
static_assert(scenes::UpperBody::nj == 8 && scenes::UpperBody::shape::num_chains == 3);
static_assert(scenes::UpperBody::shape::reduction.base_link == 3, "upper body: base on the pelvis (link 4)");
static_assert(scenes::UpperBody::shape::spec.parent == std::array<int, 8>{-1, 0, 1, 2, 3, 1, 5, 6});
static_assert(scenes::UpperBody::shape::spec.mounted == std::array<bool, 8>{});
static_assert(scenes::ArmsOnly::nj == 6 && scenes::ArmsOnly::shape::num_chains == 2);
static_assert(scenes::ArmsOnly::shape::reduction.base_link == 5, "arms only: base on the upper body (link 6)");
static_assert(scenes::ArmsOnly::shape::spec.parent == std::array<int, 6>{-1, 0, 1, -1, 3, 4});
// waist pitch (massless in the seed) carries nothing locked: still massless; no locked link joins another
static_assert(scenes::UpperBody::shape::spec.massless[0]);
// no locks: the scene runs on the seed shape itself, so its model is a HumanModel
static_assert(std::is_same_v<scenes::Full::model_type<double>, HumanModel<double>>);
static_assert(std::is_same_v<scenes::NoCoriolis::shape, SeedShape>);
// output pruning: the arm torques need the arms' forward and backward steps, the legs and waist only
// carry motion, the left leg (13-16) is skipped
static_assert(scenes::ArmTorques::prunes_outputs && !scenes::Full::prunes_outputs);
static_assert(scenes::ArmTorques::forward_steps == 12 && scenes::ArmTorques::backward_steps == 6);
static_assert(scenes::Full::forward_steps == 16 && scenes::Full::backward_steps == 16);

// A scene that locks joints inside chains: right knee (2), waist yaw (6), left elbow (9), left knee (15).
using MidChainLocks = Scene<SceneSpec<16>{.locked = joint_set<16>({1, 5, 8, 14})}>;
static_assert(MidChainLocks::nj == 12);
static_assert(MidChainLocks::shape::reduction.base_link == -1, "the right ankle still moves");
// right hip roll hangs from the shank through the locked knee; both shoulders from the waist-pitch link
// through the locked waist yaw; the left ankle from the thigh through the locked knee
static_assert(MidChainLocks::shape::spec.mounted ==
              std::array<bool, 12>{false, true, false, false, true, false, true, false, false, false, false, true});
// the massless waist-pitch link now carries the upper body; the right shoulder pitch link stays massless
static_assert(!MidChainLocks::shape::spec.massless[3] && MidChainLocks::shape::spec.massless[6]);

// The stance ankle locked: the base moves up to the shank, and the knee needs no mount.
using AnkleLocked = Scene<SceneSpec<16>{.locked = joint_set<16>({0})}>;
static_assert(AnkleLocked::shape::reduction.base_link == 0 &&
              AnkleLocked::shape::spec.mounted == std::array<bool, 15>{});

// Locks and pruning together, with the velocity terms dropped: right arm torques, legs locked.
using RightArmOfUpperBody =
    Scene<SceneSpec<16>{.terms = Terms::NoCoriolis, .locked = scenes::seed_legs, .wanted = joint_set<16>({9, 10, 11})}>;
static_assert(RightArmOfUpperBody::nj == 8 && RightArmOfUpperBody::forward_steps == 5 &&
              RightArmOfUpperBody::backward_steps == 3);

// --- named scenes against the full model -------------------------------------------------------

TEST(NamedScenes, EqualTheFullModelOnMotionsTheyDescribeExactly) {
  const auto desc = human_description(default_parameters());
  const auto motions = random_motions(200, 11);
  const Eigen::VectorXd q_lock = random_lock_angles(12);
  int scenes_seen = 0;
  for_each_named_scene([&](auto scene) {
    using SceneT = decltype(scene);
    const Comparison c = compare_scene<SceneT>(desc, q_lock, motions, true);
    EXPECT_LE(c.max_error, kTolerance) << SceneT::name;
    EXPECT_GT(c.max_torque, 1.0) << SceneT::name << ": the comparison must involve real torques";
    EXPECT_GT(c.outputs_compared, 0) << SceneT::name;
    ++scenes_seen;
  });
  EXPECT_EQ(scenes_seen, 6);
}

TEST(NamedScenes, DifferFromTheFullModelWhereTheyClaimNoExactness) {
  // on motions that break their assumptions, the pruned scenes give other torques: the check above can fail
  const auto desc = human_description(default_parameters());
  const auto motions = random_motions(20, 13);
  const Eigen::VectorXd q_lock = random_lock_angles(14);
  for_each_named_scene([&](auto scene) {
    using SceneT = decltype(scene);
    const Comparison c = compare_scene<SceneT>(desc, q_lock, motions, false);
    if (SceneT::name == "full" || SceneT::name == "arm_torques")
      EXPECT_LE(c.max_error, kTolerance) << SceneT::name << " is exact on every motion";
    else
      EXPECT_GT(c.max_error, 1e-3) << SceneT::name;
  });
}

TEST(NamedScenes, NamesAreUniqueAndFound) {
  EXPECT_EQ(named_scene_list(), "full|no_coriolis|static_pose|upper_body|arms_only|arm_torques");
  int nj = 0;
  EXPECT_TRUE(with_named_scene("arms_only", [&](auto s) { nj = decltype(s)::nj; }));
  EXPECT_EQ(nj, 6);
  EXPECT_FALSE(with_named_scene("legs_only", [&](auto) { FAIL(); }));
}

// --- locked-joint merging ------------------------------------------------------------------------

// The description as a KDL tree in which the locked joints are fixed joints at their lock angles; its
// joints (KDL numbers the movable ones in the order added) are the scene's joints.
KDL::Tree kdl_locked_tree(const ModelDescription<double>& d, const JointSet<16>& locked,
                          const Eigen::VectorXd& q_lock) {
  using humandyn::testing::kdl_segment_name;
  using humandyn::testing::to_kdl;
  KDL::Tree tree("root");
  for (int i = 0; i < 16; ++i) {
    const auto& j = d.joints[std::size_t(i)];
    std::string parent = j.parent < 0 ? std::string("root") : kdl_segment_name(d, j.parent);
    if (j.mounted) {
      const std::string mount = kdl_segment_name(d, i) + "_mount";
      EXPECT_TRUE(tree.addSegment(KDL::Segment(mount, KDL::Joint(mount + "_fixed", KDL::Joint::Fixed), to_kdl(j.mount)),
                                  parent));
      parent = mount;
    }
    const bool fixed = locked[std::size_t(i)];
    const KDL::Segment segment(kdl_segment_name(d, i), KDL::Joint(j.name, fixed ? KDL::Joint::Fixed : KDL::Joint::RotZ),
                               KDL::Frame::DH(j.dh.a, j.dh.alpha, j.dh.d, j.dh.theta + (fixed ? q_lock[i] : 0.0)),
                               to_kdl(j.body));
    EXPECT_TRUE(tree.addSegment(segment, parent));
  }
  return tree;
}

template <class SceneT>
void check_locked_scene(const ModelDescription<double>& desc, unsigned seed) {
  const Eigen::VectorXd q_lock = random_lock_angles(seed);
  const auto motions = random_motions(100, seed + 1);

  // against the full model with the locked joints still at their lock angles
  const Comparison c = compare_scene<SceneT>(desc, q_lock, motions, true);
  EXPECT_LE(c.max_error, kTolerance);
  EXPECT_GT(c.max_torque, 1.0);

  // against KDL on a tree with fixed joints
  const KDL::Tree tree = kdl_locked_tree(desc, SceneT::spec.locked, q_lock);
  ASSERT_EQ(int(tree.getNrOfJoints()), SceneT::nj);
  KDL::TreeIdSolver_RNE solver(tree, humandyn::testing::kdl_gravity(desc));
  const auto model = SceneT::template model<double>(desc, q_lock);
  Data<std::decay_t<decltype(model)>> data(model);
  double max_error = 0;
  for (const Motion& m : motions) {
    constexpr auto n = static_cast<unsigned>(SceneT::nj);
    KDL::JntArray q(n), qd(n), qdd(n), tau(n);
    q.data = SceneT::reduce(m.q);
    qd.data = SceneT::reduce(m.qd);
    qdd.data = SceneT::reduce(m.qdd);
    if constexpr (SceneT::terms != Terms::Full) qd.data.setZero();
    if constexpr (SceneT::terms == Terms::GravityOnly) qdd.data.setZero();
    ASSERT_EQ(solver.CartToJnt(q, qd, qdd, KDL::WrenchMap{}, tau), 0);
    const auto got = scene_rnea<SceneT>(model, data, SceneT::reduce(m.q), SceneT::reduce(m.qd), SceneT::reduce(m.qdd));
    for (int k = 0; k < SceneT::nj; ++k)
      if (SceneT::requested[std::size_t(k)]) max_error = std::max(max_error, scaled_error(got[k], tau(unsigned(k))));
  }
  EXPECT_LE(max_error, kTolerance);

  // the merged bodies keep the whole body's mass and centre of mass
  const HumanModel<double> full(desc);
  Data<HumanModel<double>> full_data(full);
  Vec16 q_full = motions[0].q;
  for (int i = 0; i < 16; ++i)
    if (SceneT::spec.locked[std::size_t(i)]) q_full[i] = q_lock[i];
  forward_kinematics(full, full_data, q_full);
  forward_kinematics(model, data, SceneT::reduce(q_full));
  EXPECT_NEAR(model.total_mass(), full.total_mass(), 1e-12);
  EXPECT_LE((data.com - full_data.com).norm(), 1e-12);
  // ... and every link that still moves sits where it did
  for (int k = 0; k < SceneT::nj; ++k) {
    const auto& X = data.oMi[std::size_t(k)];
    const auto& Y = full_data.oMi[std::size_t(SceneT::full_index[std::size_t(k)])];
    EXPECT_LE((X.R - Y.R).cwiseAbs().maxCoeff() + (X.p - Y.p).cwiseAbs().maxCoeff(), 1e-12) << "joint " << k;
  }
}

TEST(LockedJoints, UpperBodyEqualsFullModelAndKdl) {
  check_locked_scene<scenes::UpperBody>(human_description(default_parameters()), 21);
}
TEST(LockedJoints, ArmsOnlyEqualsFullModelAndKdl) {
  check_locked_scene<scenes::ArmsOnly>(human_description(female_parameters()), 23);
}
TEST(LockedJoints, MidChainLocksWithMountsEqualFullModelAndKdl) {
  check_locked_scene<MidChainLocks>(human_description(paper_parameters()), 25);
}
TEST(LockedJoints, LockedStanceAnkleMovesTheBase) {
  check_locked_scene<AnkleLocked>(human_description(default_parameters()), 27);
}
TEST(LockedJoints, LocksWithPrunedOutputsAndNoCoriolis) {
  check_locked_scene<RightArmOfUpperBody>(human_description(default_parameters()), 29);
}

// Scenes that lock as many joints, or ask for as many torques, but not the same ones are different
// scenes (a joint set is its members, however it was built: the left arm's {6, 7, 8} filled in from a
// zero start is not the right arm's {9, 10, 11}), and each one equals the full model and KDL.
using LeftArmLocked = Scene<SceneSpec<16>{.locked = joint_set<16>({6, 7, 8})}>;
using RightArmLocked = Scene<SceneSpec<16>{.locked = joint_set<16>({9, 10, 11})}>;
using RightArmLockedFromFlags = Scene<SceneSpec<16>{.locked = [] {
  std::array<bool, 16> flags{};
  flags[9] = flags[10] = flags[11] = true;
  return flags;
}()}>;
using LeftArmTorques = Scene<SceneSpec<16>{.wanted = joint_set<16>({6, 7, 8})}>;
static_assert(!std::is_same_v<LeftArmLocked, RightArmLocked> &&
              std::is_same_v<RightArmLocked, RightArmLockedFromFlags>);
static_assert(!std::is_same_v<LeftArmLocked::shape, RightArmLocked::shape>);
static_assert(RightArmLocked::spec.locked[9] && !RightArmLocked::spec.locked[6] && LeftArmLocked::spec.locked[6]);
static_assert(!std::is_same_v<LeftArmTorques, Scene<scenes::ArmTorques::spec>> &&
              std::is_same_v<Scene<SceneSpec<16>{.wanted = joint_set<16>({6, 7, 8})}>, LeftArmTorques> &&
              LeftArmTorques::requested[6] && !LeftArmTorques::requested[9]);
// A joint set takes joints in [0, N), each once: N flags written as 0s and 1s in a list (which would read as
// joints 0 and 1) and a joint beyond the shape are errors, at compile time in a constant, here at run time.
TEST(LockedJoints, AJointSetRefusesRepeatsAndJointsBeyondTheShape) {
  EXPECT_THROW((void)JointSet<16>({0, 0, 1, 1, 0}), std::invalid_argument);
  EXPECT_THROW((void)JointSet<16>({16}), std::out_of_range);
  EXPECT_THROW((void)JointSet<16>({-1}), std::out_of_range);
  JointSet<16> s;
  EXPECT_THROW(s.set(16), std::out_of_range);
  EXPECT_TRUE(s.empty());
  s.set(15);
  EXPECT_EQ(s, JointSet<16>({15}));
  EXPECT_EQ(JointSet<16>(JointSet<16>({9, 10, 11}).flags()), joint_set<16>({11, 10, 9}));
}

TEST(LockedJoints, ScenesLockingAsManyJointsAreDifferentAndEachIsRight) {
  const auto desc = human_description(default_parameters());
  check_locked_scene<LeftArmLocked>(desc, 41);
  check_locked_scene<RightArmLocked>(desc, 43);
  check_locked_scene<LeftArmTorques>(desc, 45);
}

TEST(LockedJoints, RuntimeLockingOfAnyModelMatchesTheStaticScene) {
  // lock_joints on a runtime-shaped model gives the same torques as the static scene
  using SceneT = MidChainLocks;
  const auto desc = human_description(default_parameters());
  const Eigen::VectorXd q_lock = random_lock_angles(31);
  const auto flags = SceneT::spec.locked.flags();
  const AnyModel<double> any(lock_joints(desc, std::vector<bool>(flags.begin(), flags.end()), q_lock));
  Data<AnyModel<double>> any_data(any);
  const auto model = SceneT::model<double>(desc, q_lock);
  Data<SceneT::model_type<double>> data(model);
  for (const Motion& m : random_motions(50, 32)) {
    const Eigen::VectorXd q = SceneT::reduce(m.q), qd = SceneT::reduce(m.qd), qdd = SceneT::reduce(m.qdd);
    const Eigen::VectorXd expected = rnea(any, any_data, q, qd, qdd);
    const Eigen::VectorXd got =
        scene_rnea<SceneT>(model, data, SceneT::reduce(m.q), SceneT::reduce(m.qd), SceneT::reduce(m.qdd));
    EXPECT_LE((got - expected).cwiseAbs().maxCoeff(), 1e-12);
  }
}

TEST(LockedJoints, MergeInertiasIsTheParallelAxisTheorem) {
  // two point masses 1 kg at +-x: I = diag(0, 2, 2) about their midpoint
  RigidBodyInertia<double> a, b;
  a.mass = b.mass = 1;
  a.com = Eigen::Vector3d(1, 0, 0);
  b.com = Eigen::Vector3d(-1, 0, 0);
  const auto m = merge_inertias({a, b});
  EXPECT_DOUBLE_EQ(m.mass, 2);
  EXPECT_LE(m.com.norm(), 1e-15);
  EXPECT_LE((m.inertia - Eigen::Vector3d(0, 2, 2).asDiagonal().toDenseMatrix()).norm(), 1e-15);
}

TEST(LockedJoints, ErrorsNameTheJoint) {
  const auto desc = human_description(default_parameters());
  Eigen::VectorXd q_lock = Eigen::VectorXd::Zero(16);
  q_lock[1] = std::nan("");
  try {
    (void)MidChainLocks::model<double>(desc, q_lock);
    FAIL() << "a NaN lock angle must be refused";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("r_knee_pitch"), std::string::npos) << e.what();
    EXPECT_EQ(e.where(), ModelError::Where::Joint);
    EXPECT_EQ(e.joint(), 1);
  }
  // a fault on a link the locks merge away is named as the whole body's validation names it (a negative
  // mass would otherwise only lighten the merged body)
  q_lock.setZero();
  ModelDescription<double> bad = desc;
  bad.joints[1].body.mass = -1;
  try {
    (void)MidChainLocks::model<double>(bad, q_lock);
    FAIL() << "a negative mass on a locked link must be refused";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("negative mass"), std::string::npos) << e.what();
    EXPECT_EQ(e.joint(), 1) << e.what();
  }
  std::vector<bool> knee(16, false);
  knee[1] = true;
  EXPECT_THROW(lock_joints(bad, knee, q_lock), ModelError);  // a runtime-shaped scene alike
  EXPECT_THROW(lock_joints(desc, std::vector<bool>(16, true), Eigen::VectorXd::Zero(16)), ModelError);
  EXPECT_THROW(lock_joints(desc, std::vector<bool>(3, true), Eigen::VectorXd::Zero(16)), ModelError);
}

// --- forward dynamics ------------------------------------------------------------------------------

// Scene forward dynamics against the full model: with the scene's accelerations (locked joints still),
// the full model's inverse dynamics needs exactly the scene's torques at the moving joints; the locked
// joints take whatever torque holds them. FullModel is the full shape's model type.
template <class SceneT, FdMethod method>
void check_scene_forward_dynamics(const ModelDescription<double>& desc, unsigned seed) {
  using FullModel = Model<double, typename SceneT::full_shape>;
  const Eigen::VectorXd q_lock = random_lock_angles(seed);
  const FullModel full(desc);
  Data<FullModel> full_data(full);
  const auto model = SceneT::template model<double>(desc, q_lock);
  Data<std::decay_t<decltype(model)>> data(model);
  double max_error = 0, max_qdd = 0;
  for (Motion m : random_motions(50, seed + 1)) {
    SceneT::constrain(q_lock, m.q, m.qd, m.qdd);
    const typename SceneT::template vector<double> q = SceneT::reduce(m.q), qd = SceneT::reduce(m.qd),
                                                   tau = SceneT::reduce(Vec16(2.5 * m.qdd));
    Eigen::internal::set_is_malloc_allowed(false);
    const typename SceneT::template vector<double> qdd =
        scene_forward_dynamics<SceneT, method>(model, data, q, qd, tau);
    Eigen::internal::set_is_malloc_allowed(true);
    Vec16 qdd_full = Vec16::Zero();
    for (int k = 0; k < SceneT::nj; ++k) qdd_full[SceneT::full_index[std::size_t(k)]] = qdd[k];
    const Vec16 tau_full = rnea<forward_terms<SceneT>>(full, full_data, m.q, m.qd, qdd_full);
    for (int k = 0; k < SceneT::nj; ++k)
      max_error = std::max(max_error, scaled_error(tau_full[SceneT::full_index[std::size_t(k)]], tau[k]));
    max_qdd = std::max(max_qdd, qdd.cwiseAbs().maxCoeff());
  }
  EXPECT_LE(max_error, 1e-9) << label<SceneT>();
  EXPECT_GT(max_qdd, 1.0) << label<SceneT>();
}

// With Table 1's massless pelvis (the paper model) the mass matrix is singular: joints 4, 5 and 13 turn
// about one line and the link between them carries nothing. Locking the legs removes that direction, so
// the upper-body and arms-only scenes have forward dynamics even there; and on the default body.
TEST(SceneForwardDynamics, LockedLegsMakeTheSeedBodysForwardDynamicsDefined) {
  for (const auto& desc : {human_description(paper_parameters()), human_description(default_parameters())}) {
    check_scene_forward_dynamics<scenes::UpperBody, FdMethod::Articulated>(desc, 61);
    check_scene_forward_dynamics<scenes::UpperBody, FdMethod::MassMatrix>(desc, 61);
    check_scene_forward_dynamics<scenes::ArmsOnly, FdMethod::Articulated>(desc, 63);
    check_scene_forward_dynamics<scenes::ArmsOnly, FdMethod::MassMatrix>(desc, 63);
  }
}

// Every named scene's spec, and the locked test scenes, on the default body (a regular mass matrix).
template <class SceneT>
using OnPelvisBody = BasicScene<SeedShape, SceneT::spec>;

TEST(SceneForwardDynamics, EveryScenesForwardDynamicsInvertsTheFullInverseDynamics) {
  const auto desc = human_description(default_parameters());
  for_each_named_scene([&](auto scene) {
    using SceneT = OnPelvisBody<decltype(scene)>;
    check_scene_forward_dynamics<SceneT, FdMethod::Articulated>(desc, 71);
    check_scene_forward_dynamics<SceneT, FdMethod::MassMatrix>(desc, 73);
  });
  check_scene_forward_dynamics<OnPelvisBody<MidChainLocks>, FdMethod::Articulated>(desc, 75);
  check_scene_forward_dynamics<OnPelvisBody<MidChainLocks>, FdMethod::MassMatrix>(desc, 75);
  check_scene_forward_dynamics<OnPelvisBody<AnkleLocked>, FdMethod::Articulated>(desc, 77);
}

// --- time stepping -------------------------------------------------------------------------------

// A semi-implicit Euler step in a locked scene is the full body's step under the torques that hold the
// locked joints still: the moving joints land at the same state, the locked ones stay put.
TEST(SceneTimeStepping, EulerStepOfALockedSceneIsTheFullBodysWithTheLocksHeld) {
  using SceneT = OnPelvisBody<scenes::UpperBody>;
  using FullModel = Model<double, SeedShape>;
  const auto desc = human_description(default_parameters());
  const Eigen::VectorXd q_lock = random_lock_angles(81);
  const FullModel full(desc);
  const auto model = SceneT::model<double>(desc, q_lock);
  StepWorkspace<FullModel> full_ws(full);
  StepWorkspace<SceneT::model_type<double>> ws(model);
  Data<FullModel> full_data(full);
  constexpr double h = 1e-3;
  double error = 0, moved = 0;
  for (Motion m : random_motions(20, 82)) {
    SceneT::constrain(q_lock, m.q, m.qd, m.qdd);
    State<SceneT::model_type<double>> x(model);
    x.q = SceneT::reduce(m.q);
    x.qd = SceneT::reduce(m.qd);
    const SceneT::vector<double> tau = SceneT::reduce(Vec16(2.0 * m.qdd));
    // the full body under the torques that realise the scene's accelerations, locked joints still
    const SceneT::vector<double> qdd =
        scene_forward_dynamics<SceneT, FdMethod::MassMatrix>(model, ws.data, x.q, x.qd, tau);
    Vec16 qdd_full = Vec16::Zero();
    for (int k = 0; k < SceneT::nj; ++k) qdd_full[SceneT::full_index[std::size_t(k)]] = qdd[k];
    const Vec16 tau_full = rnea(full, full_data, m.q, m.qd, qdd_full);
    State<FullModel> y(full);
    y.q = m.q;
    y.qd = m.qd;
    Eigen::internal::set_is_malloc_allowed(false);
    const StepStatus s1 = scene_step<SceneT, Integrator::SemiImplicitEuler>(model, ws, x, tau, h);
    const StepStatus s2 = step<Integrator::SemiImplicitEuler>(full, full_ws, y, tau_full, h);
    Eigen::internal::set_is_malloc_allowed(true);
    ASSERT_TRUE(s1.ok() && s2.ok());
    error = std::max(
        error, (SceneT::reduce(y.q) - x.q).cwiseAbs().maxCoeff() + (SceneT::reduce(y.qd) - x.qd).cwiseAbs().maxCoeff());
    for (int i = 0; i < 16; ++i)
      if (SceneT::spec.locked[std::size_t(i)])
        error = std::max(error, std::abs(y.q[i] - q_lock[i]) + std::abs(y.qd[i]));
    moved = std::max(moved, (x.q - SceneT::reduce(m.q)).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(error, 1e-11);
  EXPECT_GT(moved, 1e-4);
}

// --- float, gravity off, allocation -------------------------------------------------------------

TEST(SceneScalars, FloatAgreesWithDouble) {
  const auto desc = human_description(default_parameters());
  const Eigen::VectorXd q_lock = random_lock_angles(41);
  const auto md = RightArmOfUpperBody::model<double>(desc, q_lock);
  const auto mf = RightArmOfUpperBody::model<float>(desc, q_lock);
  Data<std::decay_t<decltype(md)>> dd(md);
  Data<std::decay_t<decltype(mf)>> df(mf);
  for (const Motion& m : random_motions(50, 42)) {
    using SceneT = RightArmOfUpperBody;
    const Eigen::VectorXd td =
        scene_rnea<SceneT>(md, dd, SceneT::reduce(m.q), SceneT::reduce(m.qd), SceneT::reduce(m.qdd));
    const Eigen::VectorXf tf =
        scene_rnea<SceneT>(mf, df, SceneT::reduce(m.q).cast<float>(), SceneT::reduce(m.qd).cast<float>(),
                           SceneT::reduce(m.qdd).cast<float>());
    for (int k = 0; k < SceneT::nj; ++k) EXPECT_NEAR(tf[k], td[k], 1e-4 * std::max(1.0, std::abs(td[k])));
  }
}

TEST(SceneScalars, GravityOffDropsTheWeight) {
  using Weightless = Scene<SceneSpec<16>{.gravity = false, .locked = scenes::seed_legs}>;
  const auto desc = human_description(default_parameters());
  const auto model = Weightless::model<double>(desc, Eigen::VectorXd::Zero(16));
  EXPECT_EQ(model.gravity().norm(), 0.0);
  Data<Weightless::model_type<double>> data(model);
  const Eigen::Matrix<double, 8, 1> zero = Eigen::Matrix<double, 8, 1>::Zero();
  EXPECT_EQ(scene_rnea<Weightless>(model, data, zero, zero, zero).norm(), 0.0);
}

TEST(SceneAllocation, ScenesNeverAllocate) {
  const auto desc = human_description(default_parameters());
  const Eigen::VectorXd q_lock = random_lock_angles(51);
  const Motion m = random_motions(1, 52)[0];
  for_each_named_scene([&](auto scene) {
    using SceneT = decltype(scene);
    const auto model = SceneT::template model<double>(desc, q_lock);
    Data<std::decay_t<decltype(model)>> data(model);
    const auto q = SceneT::reduce(m.q), qd = SceneT::reduce(m.qd), qdd = SceneT::reduce(m.qdd);
    Eigen::internal::set_is_malloc_allowed(false);
    scene_rnea<SceneT>(model, data, q, qd, qdd);
    const auto tau = SceneT::expand(data.tau);
    Eigen::internal::set_is_malloc_allowed(true);
    EXPECT_TRUE(tau.allFinite()) << SceneT::name;
  });
}

}  // namespace

}  // namespace test_scene
