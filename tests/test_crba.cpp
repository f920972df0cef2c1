// The mass matrix (crba), the bias vector (nonlinear_effects) and the tree-sparse L^T D L factorisation,
// proven against Newton-Euler, against KDL (ChainDynParam on single chains, TreeIdSolver_RNE on the tree)
// and against Eigen's dense LDLT.
#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/ldlt.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/builders.hpp"
#include "support/fd_models.hpp"
#include "support/kdl_tree.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <kdl/chaindynparam.hpp>
#include <kdl/jntarray.hpp>
#include <kdl/jntspaceinertiamatrix.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <Eigen/Dense>

#include <cstdio>

namespace test_crba {

using namespace humandyn;
using namespace humandyn::testing;

namespace {

constexpr double pi = 3.14159265358979323846;

// Whether joint a is joint b or one of its ancestors.
bool ancestor_or_self(const ModelDescription<double>& d, int a, int b) {
  for (int k = b; k >= 0; k = d.joints[std::size_t(k)].parent)
    if (k == a) return true;
  return false;
}

// M's columns by Newton-Euler: rnea(q, 0, e_i) - rnea(q, 0, 0).
template <class M>
Eigen::MatrixXd mass_matrix_by_rnea(const M& model, const Eigen::VectorXd& q) {
  Data<M> data(model);
  const int n = model.size();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd g = rnea(model, data, q, zero, zero);
  Eigen::MatrixXd out(n, n);
  for (int i = 0; i < n; ++i) out.col(i) = rnea(model, data, q, zero, Eigen::VectorXd::Unit(n, i)) - g;
  return out;
}

template <class M>
void expect_crba_matches_rnea(const M& model, int states, unsigned seed) {
  Data<M> data(model);
  const auto& desc = model.description();
  double worst = 0;
  for (const auto& s : random_states(model.size(), states, seed, pi, 0, 0)) {
    const Eigen::MatrixXd Mc = mass_matrix_by_rnea(model, s.q);
    const Eigen::MatrixXd Mx = crba(model, data, s.q);
    worst = std::max(worst, (Mx - Mc).cwiseAbs().maxCoeff() / Mc.cwiseAbs().maxCoeff());
    // symmetric by construction, and exactly zero between joints on different branches
    EXPECT_EQ(Mx, Mx.transpose());
    for (int i = 0; i < model.size(); ++i)
      for (int j = 0; j < model.size(); ++j)
        if (!ancestor_or_self(desc, i, j) && !ancestor_or_self(desc, j, i)) {
          EXPECT_EQ(Mx(i, j), 0.0) << i << "," << j;
        }
  }
  EXPECT_LE(worst, 1e-13);
}

}  // namespace

TEST(Crba, ColumnsEqualNewtonEulerDefaultModel) {
  expect_crba_matches_rnea(default_model<double>(), 200, 1);
  expect_crba_matches_rnea(AnyModel<double>(human_description(female_parameters())), 200, 2);
  expect_crba_matches_rnea(Model<double, SeedShape>(human_description(default_parameters())), 200, 3);
}

// Mounted joints and general twists (a URDF import's): the link-frame composite inertias cross each
// mount and each Rx(alpha) the general way; M still equals Newton-Euler's columns, with exact zeros.
TEST(Crba, MountedJointsAndGeneralTwists) {
  expect_crba_matches_rnea(AnyModel<double>(mounted_general_description()), 200, 12);
}

// The seed body as built: M is positive semidefinite with one null direction, e4 - e5 - e13 (three
// coaxial joints around a massless pelvis). With a pelvis on link 4 it is positive definite.
TEST(Crba, DefiniteWithPelvisSingularWithout) {
  const auto seed = human_model<double>(paper_parameters());  // Table 1: a massless pelvis
  const Model<double, SeedShape> pelvis(human_description(default_parameters()));
  Data<HumanModel<double>> ds(seed);
  Data<Model<double, SeedShape>> dp(pelvis);
  Eigen::VectorXd null = Eigen::VectorXd::Zero(16);
  null[3] = 1;
  null[4] = -1;
  null[12] = -1;
  double worst_cond = 0;
  for (const auto& s : random_states(16, 100, 4, pi, 0, 0)) {
    const Eigen::MatrixXd Ms = crba(seed, ds, s.q);
    EXPECT_LE((Ms * null).cwiseAbs().maxCoeff(), 1e-14 * Ms.cwiseAbs().maxCoeff());
    const Eigen::VectorXd ev_s = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Ms).eigenvalues();
    EXPECT_GT(ev_s[1], 1e-6) << "only one null direction";

    const Eigen::MatrixXd Mp = crba(pelvis, dp, s.q);
    const Eigen::VectorXd ev = Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd>(Mp).eigenvalues();
    EXPECT_GT(ev[0], 1e-4) << "positive definite with a pelvis";
    worst_cond = std::max(worst_cond, ev[15] / ev[0]);
  }
  std::printf("condition number of M with a pelvis, worst of 100 states: %.3g\n", worst_cond);
}

// KDL's ChainDynParam (mass matrix, Coriolis, gravity) on single chains cut from the body: the right
// leg alone and the chain from the stance foot to the left hand.
TEST(Crba, MatchesKdlChainDynParam) {
  const auto full = human_description(default_parameters());
  for (const auto& joints :
       {std::vector<int>{0, 1, 2, 3}, std::vector<int>{0, 1, 2, 3, 4, 5, 6, 7, 8}, std::vector<int>{12, 13, 14, 15}}) {
    const auto desc = sub_chain(full, joints);
    const AnyModel<double> model(desc);
    Data<AnyModel<double>> data(model);
    const KDL::Chain chain = kdl_chain(desc);
    KDL::ChainDynParam dyn(chain, kdl_gravity(desc));
    const unsigned n = chain.getNrOfJoints();
    ASSERT_EQ(int(n), model.size());
    KDL::JntArray q(n), qd(n), cor(n), grav(n);
    KDL::JntSpaceInertiaMatrix H(n);
    double worst_m = 0, worst_c = 0, worst_g = 0;
    for (const auto& s : random_states(int(n), 300, 5, pi, 5, 0)) {
      q.data = s.q;
      qd.data = s.qd;
      ASSERT_EQ(dyn.JntToMass(q, H), 0);
      ASSERT_EQ(dyn.JntToCoriolis(q, qd, cor), 0);
      ASSERT_EQ(dyn.JntToGravity(q, grav), 0);
      const Eigen::MatrixXd M = crba(model, data, s.q);
      const Eigen::VectorXd g = nonlinear_effects<Terms::NoCoriolis>(model, data, s.q, s.qd);
      const Eigen::VectorXd h = nonlinear_effects(model, data, s.q, s.qd);
      worst_m = std::max(worst_m, (M - H.data).cwiseAbs().maxCoeff() / H.data.cwiseAbs().maxCoeff());
      worst_g = std::max(worst_g, (g - grav.data).cwiseAbs().maxCoeff() / grav.data.cwiseAbs().maxCoeff());
      worst_c = std::max(worst_c, (h - g - cor.data).cwiseAbs().maxCoeff() / cor.data.cwiseAbs().maxCoeff());
    }
    EXPECT_LE(worst_m, 1e-12) << joints.size() << "-joint chain";
    EXPECT_LE(worst_g, 1e-12) << joints.size() << "-joint chain";
    EXPECT_LE(worst_c, 1e-11) << joints.size() << "-joint chain";
  }
}

// The whole tree's mass matrix against columns of KDL's tree inverse dynamics, without gravity.
TEST(Crba, MatchesKdlTreeColumns) {
  for (const auto& desc : {human_description(default_parameters()), human_description(default_parameters())}) {
    const AnyModel<double> model(desc);
    Data<AnyModel<double>> data(model);
    const KDL::Tree tree = kdl_tree(desc);
    KDL::TreeIdSolver_RNE solver(tree, KDL::Vector::Zero());
    const unsigned n = tree.getNrOfJoints();
    KDL::JntArray q(n), zero(n), e(n), tau(n);
    KDL::WrenchMap no_wrenches;
    double worst = 0;
    for (const auto& s : random_states(16, 100, 6, pi, 0, 0)) {
      q.data = s.q;
      Eigen::MatrixXd Mk(16, 16);
      for (int i = 0; i < 16; ++i) {
        e.data = Eigen::VectorXd::Unit(16, i);
        ASSERT_GE(solver.CartToJnt(q, zero, e, no_wrenches, tau), 0);
        Mk.col(i) = tau.data;
      }
      const Eigen::MatrixXd M = crba(model, data, s.q);
      worst = std::max(worst, (M - Mk).cwiseAbs().maxCoeff() / Mk.cwiseAbs().maxCoeff());
    }
    EXPECT_LE(worst, 1e-13);
  }
}

// The bias vector is rnea(q, qd, 0); without velocity products it is the gravity torques; external
// wrenches enter as in rnea.
TEST(NonlinearEffects, EqualsNewtonEulerAtZeroAcceleration) {
  const auto model = default_model<double>();
  Data<HumanModel<double>> data(model);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(16);
  LinkWrenches<HumanModel<double>> fext{};
  fext[11].force = Eigen::Vector3d(3, -20, 5);
  fext[11].moment = Eigen::Vector3d(0.5, 0.1, -1);
  fext[15].force = Eigen::Vector3d(0, 300, 0);
  for (const auto& s : random_states(16, 200, 7, pi, 10, 0)) {
    const Eigen::VectorXd h = nonlinear_effects(model, data, s.q, s.qd);
    EXPECT_EQ(h, Eigen::VectorXd(rnea(model, data, s.q, s.qd, zero)));
    const Eigen::VectorXd g = nonlinear_effects<Terms::NoCoriolis>(model, data, s.q, s.qd);
    EXPECT_EQ(g, Eigen::VectorXd(gravity_torques(model, data, s.q)));
    const Eigen::VectorXd hf = nonlinear_effects(model, data, s.q, s.qd, fext);
    EXPECT_EQ(hf, Eigen::VectorXd(rnea(model, data, s.q, s.qd, zero, fext)));
    const Eigen::VectorXd gf = nonlinear_effects<Terms::NoCoriolis>(model, data, s.q, s.qd, fext);
    const Eigen::VectorXd gf_ref = rnea<Terms::GravityOnly>(model, data, s.q, zero, zero, fext);
    EXPECT_LE((gf - gf_ref).cwiseAbs().maxCoeff(), 1e-12 * gf_ref.cwiseAbs().maxCoeff());
  }
}

// L^T D L reproduces M, L keeps the tree's sparsity (no fill-in), and the solve agrees with Eigen's
// dense LDLT, for M and for M + diag(extra); with several right-hand sides at once.
template <class M>
void expect_ltdl(const M& model, unsigned seed) {
  Data<M> data(model);
  const auto& desc = model.description();
  const int n = model.size();
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double worst_rec = 0, worst_solve = 0, worst_extra = 0;
  for (const auto& s : random_states(n, 200, seed, pi, 0, 0)) {
    const Eigen::MatrixXd Mx = crba(model, data, s.q);
    factorize_mass_matrix(model, data);
    const Eigen::MatrixXd L = data.L;
    const Eigen::VectorXd D = data.D;
    worst_rec =
        std::max(worst_rec, (L.transpose() * D.asDiagonal() * L - Mx).cwiseAbs().maxCoeff() / Mx.cwiseAbs().maxCoeff());
    for (int i = 0; i < n; ++i) {
      EXPECT_EQ(L(i, i), 1.0);
      for (int j = 0; j < n; ++j)
        if (j != i && !ancestor_or_self(desc, j, i)) {
          EXPECT_EQ(L(i, j), 0.0) << "fill-in at " << i << "," << j;
        }
    }
    Eigen::MatrixXd B = Eigen::MatrixXd::Random(n, 3);
    const Eigen::MatrixXd X_ref = Mx.ldlt().solve(B);
    Eigen::MatrixXd X = B;
    solve_mass_matrix(model, data, X);
    worst_solve = std::max(worst_solve, (X - X_ref).cwiseAbs().maxCoeff() / X_ref.cwiseAbs().maxCoeff());
    // M + diag(extra), as an implicit step needs; data.M stays untouched
    Eigen::VectorXd extra(n);
    for (int i = 0; i < n; ++i) extra[i] = 10.0 * u(rng);
    factorize_mass_matrix(model, data, extra);
    EXPECT_EQ(Eigen::MatrixXd(data.M), Mx);
    const Eigen::MatrixXd Me = Mx + Eigen::MatrixXd(extra.asDiagonal());
    Eigen::VectorXd x = B.col(0);
    solve_mass_matrix(model, data, x);
    const Eigen::VectorXd x_ref = Me.ldlt().solve(Eigen::VectorXd(B.col(0)));
    worst_extra = std::max(worst_extra, (x - x_ref).cwiseAbs().maxCoeff() / x_ref.cwiseAbs().maxCoeff());
  }
  EXPECT_LE(worst_rec, 1e-14);
  EXPECT_LE(worst_solve, 1e-11);  // M's condition number is up to about 3e4 here
  EXPECT_LE(worst_extra, 1e-12);
}

TEST(Ltdl, AgreesWithDenseLdlt) {
  expect_ltdl(Model<double, SeedShape>(human_description(default_parameters())), 8);
  expect_ltdl(AnyModel<double>(human_description(default_parameters())), 9);
}

// The singular seed body is still factorised and solved where the matrix is regular: with a diagonal
// added (an implicit servo's h Kd + h^2 Kp), M + diag is positive definite.
TEST(Ltdl, SeedBodyWithServoDiagonal) {
  const auto model = default_model<double>();
  Data<HumanModel<double>> data(model);
  for (const auto& s : random_states(16, 50, 10, pi, 0, 0)) {
    const Eigen::MatrixXd Mx = crba(model, data, s.q);
    const Eigen::VectorXd extra = Eigen::VectorXd::Constant(16, 1e-2);
    factorize_mass_matrix(model, data, extra);
    EXPECT_GT(data.D.minCoeff(), 0.0);
    Eigen::VectorXd x = Eigen::VectorXd::Ones(16);
    solve_mass_matrix(model, data, x);
    const Eigen::MatrixXd Me = Mx + Eigen::MatrixXd(extra.asDiagonal());
    EXPECT_LE((Me * x - Eigen::VectorXd::Ones(16)).cwiseAbs().maxCoeff(), 1e-11);
  }
}

// Float: the same matrix to float's precision.
TEST(Crba, Float) {
  const auto md = Model<double, SeedShape>(human_description(default_parameters()));
  const auto mf = md.cast<float>();
  Data<Model<double, SeedShape>> dd(md);
  Data<Model<float, SeedShape>> df(mf);
  double worst = 0, worst_solve = 0;
  for (const auto& s : random_states(16, 200, 11, pi, 0, 0)) {
    const Eigen::VectorXf qf = s.q.cast<float>();
    const Eigen::MatrixXd Md = crba(md, dd, qf.cast<double>());
    const Eigen::MatrixXd Mf = crba(mf, df, qf).cast<double>();
    worst = std::max(worst, (Mf - Md).cwiseAbs().maxCoeff() / Md.cwiseAbs().maxCoeff());
    factorize_mass_matrix(mf, df);
    Eigen::VectorXf x = Eigen::VectorXf::Ones(16);
    solve_mass_matrix(mf, df, x);
    const Eigen::VectorXd x_ref = Md.ldlt().solve(Eigen::VectorXd::Ones(16));
    worst_solve = std::max(worst_solve, (x.cast<double>() - x_ref).cwiseAbs().maxCoeff() / x_ref.cwiseAbs().maxCoeff());
  }
  // a few hundred roundings of about 6e-8 each
  EXPECT_LE(worst, 2e-5);
  // amplified by the condition number (up to about 3e4)
  EXPECT_LE(worst_solve, 1e-3);
}

// No per-call function allocates, for static and dynamic shapes, in double and float.
template <class M>
void expect_no_allocation(const M& model) {
  using S = typename M::scalar_type;
  using V = typename M::JointVector;
  Data<M> data(model);
  const V q = V::Constant(model.size(), S(0.3)), qd = V::Constant(model.size(), S(-0.7));
  V x = V::Ones(model.size());
  const V extra = V::Constant(model.size(), S(0.1));
  LinkWrenches<M> fext{};
  if constexpr (M::nj == Eigen::Dynamic) fext.resize(std::size_t(model.size()));
  Eigen::internal::set_is_malloc_allowed(false);
  crba(model, data, q);
  nonlinear_effects(model, data, q, qd);
  nonlinear_effects<Terms::NoCoriolis>(model, data, q, qd);
  nonlinear_effects(model, data, q, qd, fext);
  factorize_mass_matrix(model, data);
  solve_mass_matrix(model, data, x);
  factorize_mass_matrix(model, data, extra);
  solve_mass_matrix(model, data, x);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(x.allFinite());
}

TEST(Crba, NoAllocation) {
  expect_no_allocation(Model<double, SeedShape>(human_description(default_parameters())));
  expect_no_allocation(Model<double, SeedShape>(human_description(default_parameters())).cast<float>());
  expect_no_allocation(AnyModel<double>(human_description(default_parameters())));
  expect_no_allocation(AnyModel<double>(human_description(default_parameters())).cast<float>());
}

}  // namespace test_crba
