// Inverse dynamics (algorithm/rnea.hpp) against KDL's recursive Newton-Euler solvers, and the
// identities that any correct inverse dynamics obeys.
//
// KDL's convention for external wrenches (TreeIdSolver_RNE and ChainIdSolver_RNE): f_ext[segment]
// is the wrench the environment applies TO the segment, expressed in the segment's tip frame (the
// link frame here) with its moment taken about the tip frame's origin; KDL subtracts it from the
// wrench the segment's own motion needs (f = I a + v x* I v - f_ext). humandyn's Wrench has the same
// meaning (data.hpp), so both take the same numbers.
#include "humandyn/humandyn.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <kdl/treefksolverpos_recursive.hpp>

#include <Eigen/Geometry>

#include <cmath>
#include <cstdio>
#include <set>
#include <string>

namespace test_rnea {

namespace {

using namespace humandyn;
using humandyn::testing::JointState;
using humandyn::testing::KdlChainDynamics;
using humandyn::testing::KdlTreeDynamics;
using humandyn::testing::random_states;

constexpr double kPi = 3.14159265358979323846;
constexpr int kStates = 1000;
constexpr double kKdlTolerance = 1e-9;  // N m, largest |tau - tau_KDL| allowed in double

// Prints a measured figure (and records it in the test's XML output).
void report(const std::string& what, double value) {
  std::printf("  %-58s %.3g\n", what.c_str(), value);
  ::testing::Test::RecordProperty(what, std::to_string(value));
}

// Torques of a humandyn model for one state, as a dynamic vector.
template <Terms terms = Terms::Full, class M>
Eigen::VectorXd torques(const M& model, Data<M>& data, const JointState& s) {
  return rnea<terms>(model, data, s.q, s.qd, s.qdd);
}

template <Terms terms = Terms::Full, class M>
Eigen::VectorXd torques(const M& model, Data<M>& data, const JointState& s, const LinkWrenches<M>& fext) {
  return rnea<terms>(model, data, s.q, s.qd, s.qdd, fext);
}

// Largest |tau - tau_KDL| over random states, and the largest |tau_KDL| (to show the check is not vacuous).
struct Comparison {
  double max_error = 0, max_torque = 0;
};

template <class M, class Reference>
Comparison compare(const M& model, Reference& reference, const std::vector<JointState>& states) {
  Data<M> data(model);
  Comparison c;
  for (const auto& s : states) {
    const Eigen::VectorXd expected = reference.torques(s);
    c.max_error = std::max(c.max_error, (torques(model, data, s) - expected).cwiseAbs().maxCoeff());
    c.max_torque = std::max(c.max_torque, expected.cwiseAbs().maxCoeff());
  }
  return c;
}

struct NamedParameters {
  const char* name;
  SeedParameters (*make)();
};
const NamedParameters kBuiltIn[] = {
    {"default", default_parameters}, {"female", female_parameters}, {"paper", paper_parameters}};

// The seed's scenarios: standing upright, and the left arm raised forward by 90 degrees.
std::vector<JointState> scenarios() {
  JointState standing{Eigen::VectorXd::Zero(16), Eigen::VectorXd::Zero(16), Eigen::VectorXd::Zero(16)};
  std::vector<JointState> out{standing};
  for (double sign : {-1.0, 1.0}) {
    JointState arm = standing;
    arm.q[6] = sign * kPi / 2;  // joint 7, left shoulder pitch
    out.push_back(arm);
  }
  return out;
}

TEST(RneaVsKdlTree, BuiltInModelsStaticAndRuntimeShapes) {
  for (const auto& [name, make] : kBuiltIn) {
    SCOPED_TRACE(name);
    const ModelDescription<double> desc = human_description(make());
    const HumanModel<double> fixed(desc);
    const AnyModel<double> any(desc);
    KdlTreeDynamics kdl(desc);
    const auto states = random_states(16, kStates, 1);

    const Comparison s = compare(fixed, kdl, states);
    EXPECT_LE(s.max_error, kKdlTolerance) << "HumanModel";
    EXPECT_GT(s.max_torque, 100.0);
    const Comparison d = compare(any, kdl, states);
    EXPECT_LE(d.max_error, kKdlTolerance) << "AnyModel";
    report(std::string(name) + ": max |tau - KDL| (N m), static / runtime shape", std::max(s.max_error, d.max_error));
    report(std::string(name) + ": max |tau_KDL| (N m)", s.max_torque);

    const auto scene = scenarios();
    EXPECT_LE(compare(fixed, kdl, scene).max_error, kKdlTolerance) << "scenarios, HumanModel";
    EXPECT_LE(compare(any, kdl, scene).max_error, kKdlTolerance) << "scenarios, AnyModel";
  }
}

// The default description with fixed mount transforms before some joints: a different valid tree.
ModelDescription<double> mounted_description() {
  ModelDescription<double> desc = human_description(default_parameters());
  desc.name = "default with mounts";
  int k = 0;
  for (int i : {0, 4, 6, 12, 15}) {  // right ankle (on the base), waist pitch, left shoulder, left hip, left ankle
    auto& j = desc.joints[std::size_t(i)];
    j.mounted = true;
    j.mount.R = Eigen::AngleAxisd(0.3 + 0.2 * k, Eigen::Vector3d(1, 2 - k, 3).normalized()).toRotationMatrix();
    j.mount.p = Eigen::Vector3d(0.02 * (k + 1), -0.03, 0.05 - 0.01 * k);
    ++k;
  }
  return desc;
}

TEST(RneaVsKdlTree, MountedJointsThroughRuntimeShape) {
  const ModelDescription<double> desc = mounted_description();
  const AnyModel<double> model(desc);
  KdlTreeDynamics kdl(desc);
  const auto states = random_states(16, kStates, 2);
  const Comparison c = compare(model, kdl, states);
  EXPECT_LE(c.max_error, kKdlTolerance);
  report("mounted tree: max |tau - KDL| (N m)", c.max_error);

  // the mounts matter: the unmounted model gives other torques
  const AnyModel<double> plain(human_description(default_parameters()));
  Data<AnyModel<double>> a(model), b(plain);
  EXPECT_GT((torques(model, a, states[0]) - torques(plain, b, states[0])).cwiseAbs().maxCoeff(), 1.0);
}

// A model made of the joints `first .. first + n - 1` of the default description, which must form a
// serial chain from the base.
ModelDescription<double> sub_chain(int n) {
  ModelDescription<double> full = human_description(default_parameters());
  ModelDescription<double> d = full;
  d.joints.assign(full.joints.begin(), full.joints.begin() + n);
  for (int i = 0; i < n; ++i) EXPECT_EQ(d.joints[std::size_t(i)].parent, i - 1);
  d.name = "chain of " + std::to_string(n);
  return d;
}

TEST(RneaVsKdlChain, RightLegAlone) {
  const ModelDescription<double> desc = sub_chain(4);
  const AnyModel<double> model(desc);
  KdlChainDynamics kdl(desc);
  const Comparison c = compare(model, kdl, random_states(4, kStates, 3));
  EXPECT_LE(c.max_error, kKdlTolerance);
  EXPECT_GT(c.max_torque, 10.0);
}

TEST(RneaVsKdlChain, FootToHandNineJoints) {
  // joints 1-9: right leg, waist, left arm, without the right arm and the left leg
  const ModelDescription<double> desc = sub_chain(9);
  const AnyModel<double> model(desc);
  KdlChainDynamics kdl(desc);
  const Comparison c = compare(model, kdl, random_states(9, kStates, 4));
  EXPECT_LE(c.max_error, kKdlTolerance);
  report("9-joint chain: max |tau - ChainIdSolver_RNE| (N m)", c.max_error);
  EXPECT_GT(c.max_torque, 10.0);
}

TEST(RneaVsKdlChain, FootToHandWithMounts) {
  ModelDescription<double> desc = sub_chain(9);
  for (int i : {0, 4, 7}) {
    auto& j = desc.joints[std::size_t(i)];
    j.mounted = true;
    j.mount.R = Eigen::AngleAxisd(-0.4 + 0.3 * i, Eigen::Vector3d(3, -1, 2).normalized()).toRotationMatrix();
    j.mount.p = Eigen::Vector3d(0.01 * i, 0.04, -0.02);
  }
  const AnyModel<double> model(desc);
  KdlChainDynamics kdl(desc);
  EXPECT_LE(compare(model, kdl, random_states(9, kStates, 5)).max_error, kKdlTolerance);
}

// Random wrenches on every link, in the link frame.
template <class M>
LinkWrenches<M> random_wrenches(const M& model, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  LinkWrenches<M> w{};
  if constexpr (M::nj == Eigen::Dynamic) w.resize(std::size_t(model.size()));
  for (auto& x : w) {
    x.force = 50.0 * Eigen::Vector3d(u(rng), u(rng), u(rng));
    x.moment = 10.0 * Eigen::Vector3d(u(rng), u(rng), u(rng));
  }
  return w;
}

KDL::WrenchMap kdl_wrenches(const ModelDescription<double>& desc, const std::vector<Wrench<double>>& w) {
  KDL::WrenchMap map;
  for (int i = 0; i < int(w.size()); ++i)
    map[humandyn::testing::kdl_segment_name(desc, i)] = KDL::Wrench(
        humandyn::testing::to_kdl(w[std::size_t(i)].force), humandyn::testing::to_kdl(w[std::size_t(i)].moment));
  return map;
}

TEST(RneaExternalWrench, RandomWrenchesOnEveryLinkVsKdlTree) {
  for (const auto& desc : {human_description(default_parameters()), mounted_description()}) {
    SCOPED_TRACE(desc.name);
    const AnyModel<double> any(desc);
    Data<AnyModel<double>> data(any);
    KdlTreeDynamics kdl(desc);
    double max_error = 0, max_effect = 0;
    int k = 0;
    for (const auto& s : random_states(16, 200, 6)) {
      const auto fext = random_wrenches(any, unsigned(100 + k++));
      const Eigen::VectorXd expected = kdl.torques(s, kdl_wrenches(desc, fext));
      max_error = std::max(max_error, (torques(any, data, s, fext) - expected).cwiseAbs().maxCoeff());
      max_effect = std::max(max_effect, (expected - kdl.torques(s)).cwiseAbs().maxCoeff());
    }
    EXPECT_LE(max_error, kKdlTolerance);
    EXPECT_GT(max_effect, 10.0);  // the wrenches change the torques
  }

  // the static shape takes the same wrenches
  const ModelDescription<double> desc = human_description(default_parameters());
  const HumanModel<double> fixed(desc);
  Data<HumanModel<double>> data(fixed);
  KdlTreeDynamics kdl(desc);
  double max_error = 0;
  int k = 0;
  for (const auto& s : random_states(16, 200, 7)) {
    const auto fext = random_wrenches(fixed, unsigned(300 + k++));
    const std::vector<Wrench<double>> as_vector(fext.begin(), fext.end());
    max_error =
        std::max(max_error,
                 (torques(fixed, data, s, fext) - kdl.torques(s, kdl_wrenches(desc, as_vector))).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(max_error, kKdlTolerance);
}

TEST(RneaExternalWrench, RandomWrenchesOnAChainVsKdlChain) {
  ModelDescription<double> desc = sub_chain(9);
  desc.joints[4].mounted = true;  // a fixed segment in the KDL chain: it takes no wrench
  desc.joints[4].mount.R = Eigen::AngleAxisd(0.5, Eigen::Vector3d(0, 1, 1).normalized()).toRotationMatrix();
  desc.joints[4].mount.p = Eigen::Vector3d(0.03, 0, 0.01);
  const AnyModel<double> model(desc);
  Data<AnyModel<double>> data(model);
  KdlChainDynamics kdl(desc);
  double max_error = 0;
  int k = 0;
  for (const auto& s : random_states(9, 200, 8)) {
    const auto fext = random_wrenches(model, unsigned(500 + k++));
    KDL::Wrenches w;  // one per KDL segment, in chain order
    for (int i = 0; i < 9; ++i) {
      if (desc.joints[std::size_t(i)].mounted) w.push_back(KDL::Wrench::Zero());
      w.push_back(KDL::Wrench(humandyn::testing::to_kdl(fext[std::size_t(i)].force),
                              humandyn::testing::to_kdl(fext[std::size_t(i)].moment)));
    }
    ASSERT_EQ(w.size(), kdl.chain().getNrOfSegments());
    max_error = std::max(max_error, (torques(model, data, s, fext) - kdl.torques(s, w)).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(max_error, kKdlTolerance);
}

// A 5 kg load held in the left hand (link 9), given in the world: wrench_from_world against KDL fed
// the same load through its own forward kinematics, and against the Jacobian-transpose law
// tau(load) - tau(no load) = -J(p)^T F, J's column k = z_k x (p - o_k) for the joints between the
// base and the hand, zero elsewhere.
TEST(RneaExternalWrench, LoadInTheHandFromTheWorld) {
  const ModelDescription<double> desc = human_description(default_parameters());
  const HumanModel<double> model(desc);
  Data<HumanModel<double>> data(model);
  KdlTreeDynamics kdl(desc);
  KDL::TreeFkSolverPos_recursive fk(kdl.tree());
  const Eigen::Vector3d load(0, 0, -5.0 * 9.81);
  const int hand = 8;  // joint 9, left elbow; its link is the forearm and hand
  const std::set<int> path{0, 1, 2, 3, 4, 5, 6, 7, 8};
  const Pose<double>& base = desc.base_pose;

  double max_vs_kdl = 0, max_vs_jacobian = 0;
  for (const auto& s : random_states(16, 200, 9)) {
    forward_kinematics(model, data, s.q);
    const Eigen::Vector3d grip = data.oMi[hand] * Eigen::Vector3d(0.05, 0.01, 0.0);  // a point beyond the wrist
    LinkWrenches<HumanModel<double>> fext{};
    fext[hand] = wrench_from_world(data, hand, load, grip);
    const Eigen::VectorXd loaded = torques(model, data, s, fext);
    const Eigen::VectorXd free = torques(model, data, s);

    // KDL: the load in the base frame, moved into the hand's tip frame by KDL's own kinematics
    KDL::Frame tip;
    ASSERT_GE(fk.JntToCart(humandyn::testing::to_jnt(s.q), tip, humandyn::testing::kdl_segment_name(desc, hand)), 0);
    const Eigen::Vector3d f_base = base.R.transpose() * load;
    const Eigen::Vector3d p_base = base.inverse() * grip;
    const KDL::Wrench about_base_origin(humandyn::testing::to_kdl(f_base),
                                        humandyn::testing::to_kdl(Eigen::Vector3d(p_base.cross(f_base))));
    KDL::WrenchMap map{{humandyn::testing::kdl_segment_name(desc, hand), tip.Inverse(about_base_origin)}};
    max_vs_kdl = std::max(max_vs_kdl, (loaded - kdl.torques(s, map)).cwiseAbs().maxCoeff());

    // Jacobian transpose: joint k turns about the z axis of its parent's frame
    for (int k = 0; k < 16; ++k) {
      const int parent = desc.joints[std::size_t(k)].parent;
      const Pose<double>& P = parent < 0 ? base : data.oMi[std::size_t(parent)];
      const double expected = path.count(k) ? -P.R.col(2).cross(grip - P.p).dot(load) : 0.0;
      max_vs_jacobian = std::max(max_vs_jacobian, std::abs((loaded[k] - free[k]) - expected));
    }
  }
  EXPECT_LE(max_vs_kdl, kKdlTolerance);
  EXPECT_LE(max_vs_jacobian, kKdlTolerance);
  report("hand load: max |tau - KDL| (N m)", max_vs_kdl);
  report("hand load: max |delta tau + J^T F| (N m)", max_vs_jacobian);
}

// General twists (alpha not a multiple of 90 degrees) and twists of 180 degrees, so that every
// branch of the twist specialisation runs through the runtime shape.
TEST(RneaVsKdlTree, EveryTwistClass) {
  ModelDescription<double> desc = human_description(default_parameters());
  desc.name = "every twist";
  desc.joints[8].dh.alpha = kPi;    // left elbow: Pi
  desc.joints[15].dh.alpha = -kPi;  // left ankle: Pi (the other side)
  desc.joints[7].dh.alpha = 0.7;    // left shoulder roll: general
  desc.joints[13].dh.alpha = -2.1;  // left hip roll: general
  desc.joints[3].dh.alpha = 0.4;    // right hip pitch: general
  const AnyModel<double> model(desc);
  std::set<Twist> classes;
  for (int i = 0; i < model.size(); ++i) classes.insert(model.joint(i).twist);
  EXPECT_EQ(classes.size(), 5u) << "every twist class present";

  KdlTreeDynamics kdl(desc);
  EXPECT_LE(compare(model, kdl, random_states(16, kStates, 10)).max_error, kKdlTolerance);

  Data<AnyModel<double>> data(model);
  double max_error = 0;
  int k = 0;
  for (const auto& s : random_states(16, 100, 11)) {
    const auto fext = random_wrenches(model, unsigned(700 + k++));
    max_error = std::max(
        max_error, (torques(model, data, s, fext) - kdl.torques(s, kdl_wrenches(desc, fext))).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(max_error, kKdlTolerance);
}

// ---- identities ----

class RneaIdentities : public ::testing::Test {
 protected:
  HumanModel<double> model{default_model<double>()};
  Data<HumanModel<double>> data{model};
  std::vector<JointState> states{random_states(16, 200, 12)};
  // a torque scale for relative tolerances: the largest torque of these states
  double scale() {
    double m = 0;
    for (const auto& s : states) m = std::max(m, torques(model, data, s).cwiseAbs().maxCoeff());
    return m;
  }
};

TEST_F(RneaIdentities, GravityOnlyIsFullAtRest) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(16);
  double max_error = 0, max_tau = 0;
  for (const auto& s : states) {
    const Eigen::VectorXd g = torques<Terms::GravityOnly>(model, data, s);
    const Eigen::VectorXd full = torques(model, data, {s.q, zero, zero});
    max_error = std::max(max_error, (g - full).cwiseAbs().maxCoeff());
    max_tau = std::max(max_tau, g.cwiseAbs().maxCoeff());
    // gravity_torques is the same computation
    const Eigen::VectorXd gt = gravity_torques(model, data, s.q);
    EXPECT_EQ(gt, g);
  }
  EXPECT_GT(max_tau, 50.0);
  EXPECT_LE(max_error, 1e-12 * max_tau);
}

TEST_F(RneaIdentities, NoCoriolisIsFullWithoutVelocity) {
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(16);
  double max_error = 0, max_coriolis = 0;
  for (const auto& s : states) {
    const Eigen::VectorXd nc = torques<Terms::NoCoriolis>(model, data, s);
    max_error = std::max(max_error, (nc - torques(model, data, {s.q, zero, s.qdd})).cwiseAbs().maxCoeff());
    max_coriolis = std::max(max_coriolis, (torques(model, data, s) - nc).cwiseAbs().maxCoeff());
    // the velocities are ignored altogether
    EXPECT_EQ(nc, torques<Terms::NoCoriolis>(model, data, {s.q, 2.0 * s.qd + Eigen::VectorXd::Ones(16), s.qdd}));
  }
  EXPECT_GT(max_coriolis, 1.0) << "the velocity-product terms are not negligible in these states";
  EXPECT_LE(max_error, 1e-12 * scale());
}

// tau(q, qd, a + b) - tau(q, qd, b) = M(q) a: linear in a, whatever b and qd are.
TEST_F(RneaIdentities, AffineInAcceleration) {
  const double tol = 1e-12 * scale();
  double max_error = 0;
  const auto extra = random_states(16, int(states.size()), 13);
  for (std::size_t k = 0; k < states.size(); ++k) {
    const auto& s = states[k];
    const Eigen::VectorXd a1 = extra[k].qdd, a2 = extra[k].qd * 3.0;
    const auto M_times = [&](const Eigen::VectorXd& a) {
      return Eigen::VectorXd(torques(model, data, {s.q, s.qd, s.qdd + a}) - torques(model, data, s));
    };
    max_error = std::max(max_error, (M_times(a1 + a2) - M_times(a1) - M_times(a2)).cwiseAbs().maxCoeff());
    max_error = std::max(max_error, (M_times(-2.5 * a1) + 2.5 * M_times(a1)).cwiseAbs().maxCoeff());
  }
  EXPECT_LE(max_error, 1e2 * tol);
}

// The columns of M(q) from unit accelerations form a symmetric positive semidefinite matrix with
// exactly one null direction, at every q: the right hip pitch (joint 4) turns about the same line as
// the waist pitch and the left hip pitch (joints 5 and 13, both about z of frame 4, which joint 4's
// axis passes through), and the pelvis link between them carries no mass. Turning joint 4 is then
// the same motion as turning joints 5 and 13 together: M (e4 - e5 - e13) = 0. Every other direction
// carries inertia.
TEST_F(RneaIdentities, MassMatrixFromUnitAccelerations) {
  // Table 1's massless pelvis sits between three coaxial joints (4, 5, 13): turning it one way and both
  // its children back moves no mass. The default model's pelvis carries the lower trunk.
  const HumanModel<double> paper = human_model<double>(paper_parameters());
  Data<HumanModel<double>> paper_data(paper);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(16);
  Eigen::VectorXd null = Eigen::VectorXd::Zero(16);
  null[3] = 1;    // joint 4
  null[4] = -1;   // joint 5
  null[12] = -1;  // joint 13
  const auto mass_matrix = [&](const HumanModel<double>& m, Data<HumanModel<double>>& d, const Eigen::VectorXd& q) {
    Eigen::MatrixXd M(16, 16);
    const Eigen::VectorXd bias = torques(m, d, {q, zero, zero});
    for (int c = 0; c < 16; ++c) M.col(c) = torques(m, d, {q, zero, Eigen::VectorXd::Unit(16, c)}) - bias;
    return M;
  };
  for (int k = 0; k < 20; ++k) {
    const auto& s = states[std::size_t(k)];
    for (const bool table1 : {true, false}) {
      const Eigen::MatrixXd M = table1 ? mass_matrix(paper, paper_data, s.q) : mass_matrix(model, data, s.q);
      const double size = M.cwiseAbs().maxCoeff();
      EXPECT_LE((M - M.transpose()).cwiseAbs().maxCoeff(), 1e-12 * size);
      const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(M).eigenvalues();
      if (table1) {
        EXPECT_LE((M * null).cwiseAbs().maxCoeff(), 1e-12 * size);
        EXPECT_GE(ev[0], -1e-12 * size);
        // the next smallest is a real inertia, of the order of the free foot's about its ankle (a few
        // 1e-3 kg m^2), nine orders of magnitude above the round-off of the null direction
        EXPECT_GT(ev[1], 1e-3) << "only one direction without inertia";
      } else {
        EXPECT_GT(ev[0], 1e-3) << "the default model's mass matrix is positive definite";
      }
    }
  }
}

// tau is affine in gravity: with tau_0 the torques without gravity, tau(g1 + g2) - tau_0 =
// (tau(g1) - tau_0) + (tau(g2) - tau_0), and tau(s g) - tau_0 = s (tau(g) - tau_0).
TEST_F(RneaIdentities, AffineInGravity) {
  const auto with_gravity = [&](const Eigen::Vector3d& g) {
    ModelDescription<double> d = model.description();
    d.gravity = g;
    return HumanModel<double>(d);
  };
  const Eigen::Vector3d g1(0, 0, -9.81), g2(1.5, -2.0, 0.7);
  const auto m0 = with_gravity(Eigen::Vector3d::Zero()), m1 = with_gravity(g1), m2 = with_gravity(g2),
             m12 = with_gravity(g1 + g2), m3 = with_gravity(-3.7 * g1);
  Data<HumanModel<double>> d0(m0), d1(m1), d2(m2), d12(m12), d3(m3);
  const double tol = 1e-12 * scale();
  double max_error = 0, max_gravity = 0;
  for (const auto& s : states) {
    const Eigen::VectorXd t0 = torques(m0, d0, s), t1 = torques(m1, d1, s) - t0, t2 = torques(m2, d2, s) - t0;
    max_error = std::max(max_error, (torques(m12, d12, s) - t0 - t1 - t2).cwiseAbs().maxCoeff());
    max_error = std::max(max_error, (torques(m3, d3, s) - t0 + 3.7 * t1).cwiseAbs().maxCoeff());
    max_gravity = std::max(max_gravity, t1.cwiseAbs().maxCoeff());
  }
  EXPECT_GT(max_gravity, 50.0);
  EXPECT_LE(max_error, 1e2 * tol);
}

// ---- float ----

// Float torques agree with double ones to what single precision allows: the relative round-off of
// a few hundred operations in float, 1e-5 of the largest torque of the state.
template <class FloatModel, class DoubleModel>
double float_vs_double(const FloatModel& mf, const DoubleModel& md, const std::vector<JointState>& states) {
  Data<FloatModel> df(mf);
  Data<DoubleModel> dd(md);
  double worst = 0;
  for (const auto& s : states) {
    const Eigen::VectorXf q = s.q.cast<float>(), qd = s.qd.cast<float>(), qdd = s.qdd.cast<float>();
    const Eigen::VectorXd tf = Eigen::VectorXf(rnea(mf, df, q, qd, qdd)).cast<double>();
    const Eigen::VectorXd td = rnea(md, dd, s.q, s.qd, s.qdd);
    // compare at the float-rounded inputs, so only the arithmetic differs
    const Eigen::VectorXd tdr = rnea(md, dd, q.cast<double>(), qd.cast<double>(), qdd.cast<double>());
    (void)td;
    worst = std::max(worst, (tf - tdr).cwiseAbs().maxCoeff() / tdr.cwiseAbs().maxCoeff());

    const Eigen::VectorXd gf = Eigen::VectorXf(gravity_torques(mf, df, q)).cast<double>();
    const Eigen::VectorXd gd = gravity_torques(md, dd, q.cast<double>());
    worst = std::max(worst, (gf - gd).cwiseAbs().maxCoeff() / gd.cwiseAbs().maxCoeff());
  }
  return worst;
}

TEST(RneaFloat, AgreesWithDouble) {
  const auto states = random_states(16, 500, 14);
  for (const auto& [name, make] : kBuiltIn) {
    SCOPED_TRACE(name);
    const ModelDescription<double> desc = human_description(make());
    const HumanModel<double> hd(desc);
    const HumanModel<float> hf(desc.cast<float>());
    const AnyModel<double> ad(desc);
    const AnyModel<float> af(desc.cast<float>());
    const double hs = float_vs_double(hf, hd, states), as = float_vs_double(af, ad, states);
    EXPECT_LE(hs, 1e-5) << "HumanModel<float>";
    EXPECT_LE(as, 1e-5) << "AnyModel<float>";
    report(std::string(name) + ": float vs double, max |dtau| / max |tau|", std::max(hs, as));
  }
  // the float builder gives the same model
  const HumanModel<float> built = default_model<float>();
  EXPECT_LE(float_vs_double(built, default_model<double>(), states), 1e-5);
}

}  // namespace

}  // namespace test_rnea
