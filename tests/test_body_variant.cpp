// A variant body made by editing the seed's table (body.hpp): each arm gets a wrist joint and a hand,
// 18 joints. Everything else follows from the table: the static shape the algorithms unroll over, the
// DH rows and segments of a person, the groups of the scenes and the mirror of stance switching. Its
// inverse dynamics must match KDL's as the seed body's do (test_rnea.cpp).
#include "humandyn/crowd.hpp"
#include "humandyn/humandyn.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <limits>
#include <string>

namespace test_body_variant {

namespace {

using namespace humandyn;
using humandyn::testing::JointState;
using humandyn::testing::KdlTreeDynamics;
using humandyn::testing::random_states;

constexpr int kStates = 1000;
constexpr double kKdlTolerance = 1e-9;  // N m, largest |tau - tau_KDL| allowed in double

// The seed body with a wrist on each arm: the hand turns about the forearm's distal axis (parallel to
// the elbow's) and lies on along the forearm's line.
constexpr BodyJoint wrist(const char* name, const char* hand, const char* elbow, const char* mirror, unsigned arm) {
  return {name,   hand, elbow,      {Dim::None, Twist::MinusHalfPi, Dim::None, Twist::Zero},
          mirror, arm,  Part::Hand, Span::ParentOnward};
}
constexpr BodyTable<18> wrist_body = with_joint(
    with_joint(seed_body, wrist("l_wrist_pitch", "l_hand", "l_elbow_pitch", "r_wrist_pitch", group::left_arm)),
    wrist("r_wrist_pitch", "r_hand", "r_elbow_pitch", "l_wrist_pitch", group::right_arm));
using WristShape = BodyShape<wrist_body>;
using WristModel = Model<double, WristShape>;

// The shape follows the table: two more joints, the same five chains, each wrist continuing its arm.
static_assert(WristShape::nj == 18 && WristShape::num_chains == 5);
static_assert(wrist_body.parent(wrist_body.index("l_wrist_pitch")) == wrist_body.index("l_elbow_pitch"));
static_assert(WristShape::spec.twist[std::size_t(wrist_body.index("r_wrist_pitch"))] == Twist::MinusHalfPi);
static_assert(!WristShape::spec.massless[std::size_t(wrist_body.index("r_wrist_pitch"))]);
static_assert(wrist_body.mirror_link(wrist_body.index("l_elbow_pitch")) == wrist_body.index("r_elbow_pitch"));

// de Leva's reference male with forearm and hand apart (the seed carries both on the forearm).
SeedParameters wrist_parameters() {
  using namespace anthropometry;
  SeedParameters p = default_parameters();
  p.name = "default with wrists";
  const double basis = reference_male.mass / whole_body_mass_fraction(Sex::Male);
  const SegmentRow& forearm = row("forearm", "EJC-WJC", Sex::Male);
  const SegmentRow& hand = row("hand", "WJC-MET3", Sex::Male);
  p.forearm = detail::de_leva_segment(forearm, forearm.length, basis);
  p.hand = detail::de_leva_segment(hand, hand.length, basis);
  return p;
}

template <class M>
double max_kdl_error(const M& model, KdlTreeDynamics& kdl, const std::vector<JointState>& states, double& max_torque) {
  Data<M> data(model);
  double worst = 0;
  for (const auto& s : states) {
    const Eigen::VectorXd expected = kdl.torques(s);
    worst = std::max(worst, (Eigen::VectorXd(rnea(model, data, s.q, s.qd, s.qdd)) - expected).cwiseAbs().maxCoeff());
    max_torque = std::max(max_torque, expected.cwiseAbs().maxCoeff());
  }
  return worst;
}

TEST(BodyVariant, WristsMatchKdlOnStaticAndRuntimeShapes) {
  const SeedParameters p = wrist_parameters();
  const ModelDescription<double> desc = human_description<wrist_body>(p);
  ASSERT_EQ(desc.joints.size(), 18u);
  const int hand = wrist_body.index("r_wrist_pitch");
  EXPECT_EQ(desc.joints[std::size_t(hand)].link_name, "r_hand");
  EXPECT_EQ(desc.joints[std::size_t(hand)].body.mass, p.hand.mass);
  EXPECT_GT(p.hand.mass, 0.3);

  const WristModel fixed(desc);
  const AnyModel<double> any(desc);
  KdlTreeDynamics kdl(desc);
  const auto states = random_states(18, kStates, 1);
  double max_torque = 0;
  const double s = max_kdl_error(fixed, kdl, states, max_torque);
  const double d = max_kdl_error(any, kdl, states, max_torque);
  EXPECT_LE(s, kKdlTolerance) << "static shape";
  EXPECT_LE(d, kKdlTolerance) << "runtime shape";
  EXPECT_GT(max_torque, 100.0);
  std::printf("  wrists: max |tau - KDL| (N m), static / runtime shape %.3g / %.3g, max |tau_KDL| %.3g\n", s, d,
              max_torque);
}

// The mirror map and the groups come from the table too: the variant stands on its left foot (the
// switch checks that both models describe one body), and its upper-body scene locks its legs.
TEST(BodyVariant, StanceSwitchAndScenesFollowTheTable) {
  const SeedParameters p = wrist_parameters();
  EXPECT_EQ(mirror_name<wrist_body>("l_hand"), "r_hand");
  EXPECT_EQ(mirror_name<wrist_body>("r_foot"), "l_foot");
  const WristModel right(human_description<wrist_body>(p)), left(left_stance_description<wrist_body>(p));
  EXPECT_EQ(left.description().base_link_name, "l_foot");
  const StanceSwitch<WristModel, WristModel> to_left(right, left), to_right(left, right);
  StanceState<WristModel> l, r;
  for (const auto& s : random_states<WristModel::JointVector>(18, 50, 5, 1.5)) {
    to_left(right, left, s.q, s.qd, l);
    to_right(rebase(left, l.base_pose), right, l.q, l.qd, r);
    EXPECT_LE((r.q - s.q).cwiseAbs().maxCoeff(), 1e-10);
    EXPECT_LE((r.qd - s.qd).cwiseAbs().maxCoeff(), 1e-10);
  }

  using Upper = BasicScene<WristShape, SceneSpec<18>{.locked = wrist_body.joint_set(group::legs)}>;
  static_assert(Upper::nj == 10);
  const auto q_lock = random_states(18, 1, 3)[0].q;
  const auto scene = Upper::model<double>(right.description(), q_lock);
  Data<Upper::model_type<double>> ds(scene);
  Data<WristModel> df(right);
  double error = 0, max_torque = 0;
  for (auto s : random_states<WristModel::JointVector>(18, 200, 9)) {
    Upper::constrain(q_lock, s.q, s.qd, s.qdd);
    const WristModel::JointVector full = rnea(right, df, s.q, s.qd, s.qdd);
    const WristModel::JointVector part =
        Upper::expand(scene_rnea<Upper>(scene, ds, Upper::reduce(s.q), Upper::reduce(s.qd), Upper::reduce(s.qdd)));
    for (int i = 0; i < 18; ++i) {
      if (!Upper::outputs(i)) continue;
      error = std::max(error, std::abs(part[i] - full[i]) / std::max(1.0, std::abs(full[i])));
      max_torque = std::max(max_torque, std::abs(full[i]));
    }
  }
  EXPECT_LE(error, 1e-10);
  EXPECT_GT(max_torque, 10.0);
}

// Crowds of the variant in SIMD lanes (crowd.hpp): its 18 joints leave two over the lanes' blocks of 4
// floats, which are moved between the layouts joint by joint; 37 characters leave a partial batch.
// Every character's torques and step equal the scalar code's, and a poisoned one is refused alone.
template <class B>
void expect_crowd_equals_scalar() {
  using T = typename detail::lanes<B>::value_type;
  using M = Model<T, WristShape>;
  constexpr int nj = M::nj;
  constexpr double tol = std::is_same_v<T, double> ? 1e-12 : 1e-5;
  const M model(human_description<wrist_body>(wrist_parameters()).template cast<T>());
  const BatchModel<B, WristShape> batch(model);
  CrowdWorkspace<B, WristShape> ws(batch);
  constexpr std::size_t n = 37;
  std::vector<T> q, qd, qdd, tau(n * nj);
  for (const auto& s : random_states(nj, int(n), 11))
    for (int i = 0; i < nj; ++i) {
      q.push_back(T(s.q[i]));
      qd.push_back(T(s.qd[i]));
      qdd.push_back(T(s.qdd[i]));
    }
  qd[5 * nj + 17] = std::numeric_limits<T>::quiet_NaN();  // the last joint, one past the lanes' blocks
  using V = Eigen::Map<const typename M::JointVector>;
  Data<M> data(model);
  const auto relative = [](const auto& a, const auto& b) {
    return double((a - b).cwiseAbs().maxCoeff()) / std::max(1.0, double(b.cwiseAbs().maxCoeff()));
  };

  inverse_dynamics_crowd(batch, ws, q.data(), qd.data(), qdd.data(), tau.data(), 0, n);
  double worst = 0;
  for (std::size_t c = 0; c < n; ++c) {
    const typename M::JointVector expected = rnea(model, data, V(&q[c * nj]), V(&qd[c * nj]), V(&qdd[c * nj]));
    if (c == 5) {
      EXPECT_FALSE(V(&tau[c * nj]).allFinite());
      continue;
    }
    worst = std::max(worst, relative(V(&tau[c * nj]), expected));
  }
  EXPECT_LE(worst, tol) << "inverse dynamics";

  // the checked step, the accelerations as torques
  std::vector<T> q1 = q, qd1 = qd;
  std::vector<StepStatus> status(n);
  const CrowdView<T> view{n, q1.data(), qd1.data(), qdd.data(), nullptr, status.data()};
  step_crowd<Integrator::SemiImplicitEuler>(batch, ws, view, 0, n, T(1e-3));
  StepWorkspace<M> sws(model);
  for (std::size_t c = 0; c < n; ++c) {
    State<M> x(model);
    x.q = V(&q[c * nj]);
    x.qd = V(&qd[c * nj]);
    const StepStatus expected = step<Integrator::SemiImplicitEuler>(model, sws, x, V(&qdd[c * nj]), T(1e-3));
    EXPECT_EQ(int(status[c].error), int(expected.error)) << "character " << c;
    EXPECT_EQ(status[c].joint, expected.joint) << "character " << c;
    if (!expected.ok()) continue;
    worst = std::max({worst, relative(V(&q1[c * nj]), x.q), relative(V(&qd1[c * nj]), x.qd)});
  }
  EXPECT_EQ(status[5].error, StepError::BadInput);
  EXPECT_EQ(status[5].joint, 17);
  EXPECT_LE(worst, tol) << "step";
  std::printf("  wrists in lanes of %d: largest relative difference %.3g\n", int(detail::lanes<B>::width), worst);
}

TEST(BodyVariant, CrowdLanesEqualTheScalarCode) {
  expect_crowd_equals_scalar<NativeBatch<double>>();
  expect_crowd_equals_scalar<NativeBatch<float>>();
}

}  // namespace

}  // namespace test_body_variant
