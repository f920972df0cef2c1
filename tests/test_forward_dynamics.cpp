// Forward dynamics, both methods (mass matrix + LTDL, articulated body), proven by the round trip with
// inverse dynamics, against each other, and against KDL's ChainFdSolver_RNE; on light and heavy bodies
// and fast motion; without allocation.
//
// Table 1's body (the paper model) has a singular mass matrix (see support/fd_models.hpp and test_crba):
// its forward dynamics is undefined along e4 - e5 - e13. The suites run the default body (de Leva's lower
// trunk on the pelvis link).
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/builders.hpp"
#include "support/fd_models.hpp"
#include "support/kdl_tree.hpp"
#include "support/long_runs.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/jntarray.hpp>

#include <Eigen/Dense>

#include <cstdio>
#include <string>

namespace test_forward_dynamics {

using namespace humandyn;
using namespace humandyn::testing;

namespace {

constexpr double pi = 3.14159265358979323846;

using StaticModel = Model<double, SeedShape>;

// Forward dynamics needs the inertial terms: each aba overload takes Full and NoCoriolis, and refuses
// GravityOnly where it is called, by its requires-clause.
template <Terms terms>
constexpr bool aba_takes = requires(const StaticModel& m, Data<StaticModel>& d, const StaticModel::JointVector& x) {
  aba<terms>(m, d, x, x, x);
};
template <Terms terms>
constexpr bool aba_takes_wrenches = requires(const StaticModel& m, Data<StaticModel>& d,
                                             const StaticModel::JointVector& x, const LinkWrenches<StaticModel>& f) {
  aba<terms>(m, d, x, x, x, f);
};
template <Terms terms>
constexpr bool aba_takes_a_floating_base = requires(const StaticModel& m, Data<StaticModel>& d,
                                                    const StaticModel::JointVector& x, ArticulatedBase<double>& b) {
  aba<terms>(m, d, b, x, x, x);
};
static_assert(aba_takes<Terms::Full> && aba_takes<Terms::NoCoriolis> && !aba_takes<Terms::GravityOnly>);
static_assert(aba_takes_wrenches<Terms::Full> && aba_takes_wrenches<Terms::NoCoriolis> &&
              !aba_takes_wrenches<Terms::GravityOnly>);
static_assert(aba_takes_a_floating_base<Terms::Full> && aba_takes_a_floating_base<Terms::NoCoriolis> &&
              !aba_takes_a_floating_base<Terms::GravityOnly>);

// The largest error of qdd_fd against qdd, relative to the largest |qdd| of the state.
double relative_error(const Eigen::VectorXd& got, const Eigen::VectorXd& want) {
  return (got - want).cwiseAbs().maxCoeff() / want.cwiseAbs().maxCoeff();
}

// Round trip on `states`: tau = rnea(q, qd, qdd), then forward dynamics of tau; the worst relative error.
template <FdMethod method, Terms terms = Terms::Full, class M>
double round_trip(const M& model, const std::vector<JointState>& states) {
  using S = typename M::scalar_type;
  using V = Eigen::Matrix<S, Eigen::Dynamic, 1>;
  Data<M> data(model);
  double worst = 0;
  for (const auto& s : states) {
    const V q = s.q.cast<S>(), qd = s.qd.cast<S>(), qdd = s.qdd.cast<S>();
    const V tau = rnea<terms>(model, data, q, qd, qdd);
    const V back = forward_dynamics<method, terms>(model, data, q, qd, tau);
    worst = std::max(worst, relative_error(back.template cast<double>(), qdd.template cast<double>()));
  }
  return worst;
}

// A link made `mass` kg, its inertia scaled with it.
void set_mass(RigidBodyInertia<double>& b, double mass) {
  b.inertia *= mass / b.mass;
  b.mass = mass;
}

}  // namespace

// tau = ID(q, qd, qdd) -> FD(q, qd, tau) = qdd on 1000 random states, both methods, static and dynamic
// shapes, and a body with mounted joints and general twists.
TEST(ForwardDynamics, RoundTrip) {
  const auto ms = default_model<double>();
  const AnyModel<double> md(human_description(default_parameters()));
  const AnyModel<double> mounted(mounted_general_description());
  const auto states = random_states(16, long_run(1000, 100), 21, pi, 10, 50);
  const double e[6] = {
      round_trip<FdMethod::Articulated>(ms, states),      round_trip<FdMethod::MassMatrix>(ms, states),
      round_trip<FdMethod::Articulated>(md, states),      round_trip<FdMethod::MassMatrix>(md, states),
      round_trip<FdMethod::Articulated>(mounted, states), round_trip<FdMethod::MassMatrix>(mounted, states)};
  std::printf(
      "round trip, worst relative error: static shape aba %.2g ltdl %.2g, dynamic shape aba %.2g ltdl %.2g, "
      "mounted and general twists aba %.2g ltdl %.2g\n",
      e[0], e[1], e[2], e[3], e[4], e[5]);
  for (double x : e) EXPECT_LE(x, 1e-9);
}

// External wrenches and dropped velocity products on the mounted body: the mass-matrix method's own
// bias pass crosses mounts and general twists as rnea does.
TEST(ForwardDynamics, RoundTripMountedWithWrenches) {
  const AnyModel<double> model(mounted_general_description());
  Data<AnyModel<double>> data(model);
  LinkWrenches<AnyModel<double>> fext(16);
  fext[11].force = Eigen::Vector3d(3, -20, 5);
  fext[11].moment = Eigen::Vector3d(0.5, 0.1, -1);
  fext[15].force = Eigen::Vector3d(0, 300, 0);
  fext[5].moment = Eigen::Vector3d(-4, 2, 7);
  double worst = 0;
  for (const auto& s : random_states(16, long_run(300, 30), 23, pi, 10, 50)) {
    const Eigen::VectorXd tau = rnea(model, data, s.q, s.qd, s.qdd, fext);
    worst = std::max(worst, relative_error(forward_dynamics(model, data, s.q, s.qd, tau, fext), s.qdd));
    const Eigen::VectorXd tau_nc = rnea<Terms::NoCoriolis>(model, data, s.q, s.qd, s.qdd);
    worst = std::max(
        worst, relative_error(forward_dynamics<FdMethod::MassMatrix, Terms::NoCoriolis>(model, data, s.q, s.qd, tau_nc),
                              s.qdd));
    const Eigen::VectorXd h = rnea(model, data, s.q, s.qd, Eigen::VectorXd::Zero(16));
    forward_dynamics(model, data, s.q, s.qd, tau);
    worst = std::max(worst, relative_error(data.nle, h));
  }
  EXPECT_LE(worst, 1e-9);
}

// Without velocity products: FD<NoCoriolis> inverts rnea<NoCoriolis>, and ignores qd.
TEST(ForwardDynamics, RoundTripNoCoriolis) {
  const StaticModel ms(human_description(default_parameters()));
  const auto states = random_states(16, long_run(300, 30), 22, pi, 10, 50);
  EXPECT_LE((round_trip<FdMethod::Articulated, Terms::NoCoriolis>(ms, states)), 1e-9);
  EXPECT_LE((round_trip<FdMethod::MassMatrix, Terms::NoCoriolis>(ms, states)), 1e-9);
  Data<StaticModel> data(ms);
  const auto& s = states[0];
  const Eigen::VectorXd tau = rnea(ms, data, s.q, s.qd, s.qdd);
  const Eigen::VectorXd a = forward_dynamics<FdMethod::Articulated, Terms::NoCoriolis>(ms, data, s.q, s.qd, tau);
  const Eigen::VectorXd b = forward_dynamics<FdMethod::Articulated, Terms::NoCoriolis>(ms, data, s.q, 0 * s.qd, tau);
  EXPECT_EQ(a, b);
  const Eigen::VectorXd full = forward_dynamics<FdMethod::Articulated>(ms, data, s.q, s.qd, tau);
  EXPECT_GT((full - a).cwiseAbs().maxCoeff(), 1.0) << "the velocity products matter in this state";
}

// External wrenches: FD(q, qd, ID(q, qd, qdd, fext), fext) = qdd.
TEST(ForwardDynamics, RoundTripExternalWrenches) {
  const StaticModel model(human_description(default_parameters()));
  Data<StaticModel> data(model);
  LinkWrenches<StaticModel> fext{};
  fext[11].force = Eigen::Vector3d(3, -200, 5);  // a load pulling on the right hand
  fext[11].moment = Eigen::Vector3d(0.5, 0.1, -1);
  fext[15].force = Eigen::Vector3d(100, 300, -20);  // a push on the free foot
  double worst_a = 0, worst_m = 0;
  for (const auto& s : random_states(16, long_run(300, 30), 23, pi, 10, 50)) {
    const Eigen::VectorXd tau = rnea(model, data, s.q, s.qd, s.qdd, fext);
    worst_a = std::max(
        worst_a, relative_error(forward_dynamics<FdMethod::Articulated>(model, data, s.q, s.qd, tau, fext), s.qdd));
    worst_m = std::max(
        worst_m, relative_error(forward_dynamics<FdMethod::MassMatrix>(model, data, s.q, s.qd, tau, fext), s.qdd));
    // the wrench changes the answer
    EXPECT_GT(relative_error(forward_dynamics(model, data, s.q, s.qd, tau), s.qdd), 1e-3);
  }
  EXPECT_LE(worst_a, 1e-9);
  EXPECT_LE(worst_m, 1e-9);
}

// Both methods side by side on arbitrary torques (not from inverse dynamics).
TEST(ForwardDynamics, MethodsAgree) {
  const StaticModel model(human_description(default_parameters()));
  Data<StaticModel> data(model);
  double worst = 0;
  for (const auto& s : random_states(16, long_run(500, 50), 24, pi, 10, 200)) {
    const Eigen::VectorXd& tau = s.qdd;  // torques up to 200 N m
    const Eigen::VectorXd a = forward_dynamics<FdMethod::Articulated>(model, data, s.q, s.qd, tau);
    const Eigen::VectorXd m = forward_dynamics<FdMethod::MassMatrix>(model, data, s.q, s.qd, tau);
    worst = std::max(worst, relative_error(a, m));
  }
  EXPECT_LE(worst, 1e-9);
}

// KDL's ChainFdSolver_RNE on single chains: the right leg with the pelvis, and the chain from the
// stance foot to the left hand.
TEST(ForwardDynamics, MatchesKdlChainFdSolver) {
  const auto full = human_description(default_parameters());
  for (const auto& joints : {std::vector<int>{0, 1, 2, 3}, std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8}}) {
    const auto desc = sub_chain(full, joints);
    const AnyModel<double> model(desc);
    Data<AnyModel<double>> data(model);
    const KDL::Chain chain = kdl_chain(desc);
    KDL::ChainFdSolver_RNE solver(chain, kdl_gravity(desc));
    const unsigned n = chain.getNrOfJoints();
    KDL::JntArray q(n), qd(n), tau(n), qdd(n);
    KDL::Wrenches no_wrenches(chain.getNrOfSegments(), KDL::Wrench::Zero());
    double worst_a = 0, worst_m = 0;
    for (const auto& s : random_states(int(n), long_run(300, 30), 25, pi, 10, 100)) {
      q.data = s.q;
      qd.data = s.qd;
      tau.data = s.qdd;  // torques up to 100 N m
      ASSERT_GE(solver.CartToJnt(q, qd, tau, no_wrenches, qdd), 0);
      worst_a = std::max(
          worst_a, relative_error(forward_dynamics<FdMethod::Articulated>(model, data, s.q, s.qd, s.qdd), qdd.data));
      worst_m = std::max(
          worst_m, relative_error(forward_dynamics<FdMethod::MassMatrix>(model, data, s.q, s.qd, s.qdd), qdd.data));
    }
    std::printf("%zu-joint chain against KDL ChainFdSolver_RNE: aba %.2g ltdl %.2g\n", joints.size(), worst_a, worst_m);
    EXPECT_LE(worst_a, 1e-9);
    EXPECT_LE(worst_m, 1e-9);
  }
}

// Light and heavy bodies: forearms with hands and the free foot at 1e-4 kg; a 50 kg load at the right
// wrist; both at once. The condition number of M grows by orders of magnitude; the round trip must
// stay within 1e-8 for both methods.
TEST(ForwardDynamics, LightAndHeavyBodies) {
  struct Case {
    std::string name;
    ModelDescription<double> desc;
  };
  auto light = human_description(default_parameters());
  for (int k : {8, 11, 15}) set_mass(light.joints[std::size_t(k)].body, 1e-4);
  auto heavy = human_description(default_parameters());
  heavy.joints[11].body +=
      RigidBodyInertia<double>::point_mass(50.0, Eigen::Vector3d::Zero());  // link 12's frame sits at the wrist
  auto both = light;
  both.joints[11].body += RigidBodyInertia<double>::point_mass(50.0, Eigen::Vector3d::Zero());
  const auto states = random_states(16, long_run(1000, 100), 26, pi, 10, 50);
  for (const auto& c : {Case{"nominal", human_description(default_parameters())}, Case{"light hands and foot", light},
                        Case{"50 kg in the right hand", heavy}, Case{"light, 50 kg in the right hand", both}}) {
    const StaticModel model(c.desc);
    Data<StaticModel> data(model);
    double cond = 0;
    for (int k = 0; k < long_run(100, 20); ++k) {
      const Eigen::VectorXd ev =
          Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Eigen::MatrixXd(crba(model, data, states[std::size_t(k)].q)))
              .eigenvalues();
      cond = std::max(cond, ev[15] / ev[0]);
    }
    const double ea = round_trip<FdMethod::Articulated>(model, states);
    const double em = round_trip<FdMethod::MassMatrix>(model, states);
    double between = 0;
    for (const auto& s : states) {
      const Eigen::VectorXd tau = s.qdd * 4.0;  // arbitrary torques up to 200 N m
      const Eigen::VectorXd a = forward_dynamics<FdMethod::Articulated>(model, data, s.q, s.qd, tau);
      const Eigen::VectorXd m = forward_dynamics<FdMethod::MassMatrix>(model, data, s.q, s.qd, tau);
      between = std::max(between, relative_error(m, a));
    }
    std::printf("%-32s cond(M) up to %.2e  round trip: aba %.2g ltdl %.2g  aba vs ltdl %.2g\n", c.name.c_str(), cond,
                ea, em, between);
    EXPECT_LE(ea, 1e-8) << c.name;
    EXPECT_LE(em, 1e-8) << c.name;
    EXPECT_LE(between, 1e-8) << c.name;
  }
}

// Fast motion: |qd| up to 100 rad/s, |qdd| up to 1e4 rad/s^2, angles up to 1e3 rad. The torques are
// then dominated by velocity products of order M |qd|^2 ~ 1e4 |M|, the same order as M qdd, so the
// error relative to |qdd| stays at the size of the slow states': 1e-9 in double. In float, the solve
// loses up to about cond(M) * eps = 2.5e4 * 6e-8 = 1.5e-3 relative (eps = 2^-24); 3e-3 allows twice that.
TEST(ForwardDynamics, FastMotion) {
  const StaticModel md(human_description(default_parameters()));
  const auto mf = md.cast<float>();
  const AnyModel<double> dd(human_description(default_parameters()));
  const auto states = random_states(16, long_run(1000, 100), 27, 1e3, 100, 1e4);
  const double e[6] = {round_trip<FdMethod::Articulated>(md, states), round_trip<FdMethod::MassMatrix>(md, states),
                       round_trip<FdMethod::Articulated>(dd, states), round_trip<FdMethod::MassMatrix>(dd, states),
                       round_trip<FdMethod::Articulated>(mf, states), round_trip<FdMethod::MassMatrix>(mf, states)};
  std::printf("fast motion round trip: double aba %.2g ltdl %.2g (dynamic %.2g %.2g), float aba %.2g ltdl %.2g\n", e[0],
              e[1], e[2], e[3], e[4], e[5]);
  for (int k = 0; k < 4; ++k) EXPECT_LE(e[k], 1e-9);
  EXPECT_LE(e[4], 3e-3);
  EXPECT_LE(e[5], 3e-3);
}

// Float on ordinary states: the round trip to float's precision (cond(M) * eps, as above).
TEST(ForwardDynamics, Float) {
  const auto mf = StaticModel(human_description(default_parameters())).cast<float>();
  const auto af = AnyModel<double>(human_description(default_parameters())).cast<float>();
  const auto states = random_states(16, long_run(1000, 100), 28, pi, 10, 50);
  const double e[4] = {round_trip<FdMethod::Articulated>(mf, states), round_trip<FdMethod::MassMatrix>(mf, states),
                       round_trip<FdMethod::Articulated>(af, states), round_trip<FdMethod::MassMatrix>(af, states)};
  std::printf("float round trip: static aba %.2g ltdl %.2g, dynamic aba %.2g ltdl %.2g\n", e[0], e[1], e[2], e[3]);
  for (double x : e) EXPECT_LE(x, 3e-3);
}

// No allocation in either method, for static and dynamic shapes, in double and float.
template <class M>
void expect_no_allocation(const M& model) {
  using S = typename M::scalar_type;
  using V = typename M::JointVector;
  Data<M> data(model);
  const V q = V::Constant(model.size(), S(0.3)), qd = V::Constant(model.size(), S(-0.7)),
          tau = V::Constant(model.size(), S(2));
  LinkWrenches<M> fext{};
  if constexpr (M::nj == Eigen::Dynamic) fext.resize(std::size_t(model.size()));
  Eigen::internal::set_is_malloc_allowed(false);
  forward_dynamics<FdMethod::Articulated>(model, data, q, qd, tau);
  forward_dynamics<FdMethod::MassMatrix>(model, data, q, qd, tau);
  forward_dynamics<FdMethod::Articulated, Terms::NoCoriolis>(model, data, q, qd, tau);
  forward_dynamics<FdMethod::MassMatrix, Terms::NoCoriolis>(model, data, q, qd, tau);
  forward_dynamics<FdMethod::Articulated>(model, data, q, qd, tau, fext);
  forward_dynamics<FdMethod::MassMatrix>(model, data, q, qd, tau, fext);
  aba(model, data, q, qd, tau);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(data.qdd.allFinite());
}

TEST(ForwardDynamics, NoAllocation) {
  expect_no_allocation(StaticModel(human_description(default_parameters())));
  expect_no_allocation(StaticModel(human_description(default_parameters())).cast<float>());
  expect_no_allocation(AnyModel<double>(human_description(default_parameters())));
  expect_no_allocation(AnyModel<double>(human_description(default_parameters())).cast<float>());
  expect_no_allocation(default_model<double>());
  expect_no_allocation(default_model<float>());
}

}  // namespace test_forward_dynamics
