// Kinetic and potential energy, proven against the mass matrix (1/2 qd^T M qd), against the gravity
// torques (the gradient of the potential), and by the power balance dE/dt = qd . tau along motions
// from inverse dynamics and from forward dynamics.
#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/energy.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/builders.hpp"
#include "support/fd_models.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace test_energy {

using namespace humandyn;
using namespace humandyn::testing;

namespace {

constexpr double pi = 3.14159265358979323846;

template <class M>
void expect_kinetic_energy_is_quadratic_form(const M& model, unsigned seed) {
  Data<M> data(model);
  double worst = 0;
  for (const auto& s : random_states(model.size(), 1000, seed, pi, 10, 0)) {
    const double T = kinetic_energy(model, data, s.q, s.qd);
    const Eigen::MatrixXd Mq = crba(model, data, s.q);
    const double quadratic = 0.5 * s.qd.dot(Mq * s.qd);
    worst = std::max(worst, std::abs(T - quadratic) / quadratic);
  }
  EXPECT_LE(worst, 1e-13);
}

// A smooth motion: q(t) = q0 + v t + a t^2 / 2 + j t^3 / 6.
struct Motion {
  Eigen::VectorXd q0, v, a, j;
  Eigen::VectorXd q(double t) const { return q0 + v * t + a * (t * t / 2) + j * (t * t * t / 6); }
  Eigen::VectorXd qd(double t) const { return v + a * t + j * (t * t / 2); }
  Eigen::VectorXd qdd(double t) const { return a + j * t; }
};

}  // namespace

// 1/2 qd^T M qd, with M from composite rigid bodies, equals the sum over links from link velocities.
TEST(Energy, KineticIsHalfQdMQd) {
  expect_kinetic_energy_is_quadratic_form(default_model<double>(), 31);
  expect_kinetic_energy_is_quadratic_form(AnyModel<double>(human_description(female_parameters())), 32);
  expect_kinetic_energy_is_quadratic_form(Model<double, SeedShape>(human_description(default_parameters())), 33);
}

// mechanical_energy's potential energy (gravity carried into link frames) equals potential_energy's from
// forward kinematics, on bodies with mounts, general twists and a base pose turned and lifted in the
// world (so that g . o_i is not the origin's height in the base frame); its kinetic energy is
// kinetic_energy's, and their sum total_energy's.
template <class M>
void expect_one_pass_potential_is_forward_kinematics(const M& model, unsigned seed) {
  Data<M> data(model);
  double worst = 0;
  for (const auto& s : random_states(model.size(), 500, seed, pi, 10, 0)) {
    double T, V;
    mechanical_energy(model, data, s.q, s.qd, T, V);
    EXPECT_EQ(kinetic_energy(model, data, s.q, s.qd), T);
    EXPECT_EQ(total_energy(model, data, s.q, s.qd), T + V);
    // the potential's terms are the links' weights at their heights: rounding against their sum of sizes
    const double V_ref = potential_energy(model, data, s.q);
    double scale = 0;
    for (int i = 0; i < model.size(); ++i)
      scale += model.joint(i).mass * model.gravity().norm() * data.com_world[std::size_t(i)].norm();
    worst = std::max(worst, std::abs(V - V_ref) / scale);
  }
  EXPECT_LE(worst, 1e-14);
  std::printf("one pass's potential against forward kinematics: %.1e of its terms' sizes\n", worst);
}

TEST(Energy, OnePassPotentialIsForwardKinematics) {
  expect_one_pass_potential_is_forward_kinematics(default_model<double>(), 41);
  auto d = mounted_general_description();
  d.base_pose.R = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, -2, 0.5).normalized()).toRotationMatrix();
  d.base_pose.p = Eigen::Vector3d(3.0, -1.5, 2.0);
  expect_one_pass_potential_is_forward_kinematics(AnyModel<double>(d), 42);
}

// The gradient of the potential energy is the gravity torque vector: dV/dq_i = g_i(q), by central
// differences of fourth order (step 1e-3: truncation about 1e-12, rounding about 1e-13 of V's size).
TEST(Energy, PotentialGradientIsGravityTorque) {
  const auto model = default_model<double>();
  Data<HumanModel<double>> data(model);
  const double h = 1e-3;
  double worst = 0;
  for (const auto& s : random_states(16, 50, 34, pi, 0, 0)) {
    const Eigen::VectorXd g = gravity_torques(model, data, s.q);
    for (int i = 0; i < 16; ++i) {
      const auto V = [&](double dx) {
        Eigen::VectorXd q = s.q;
        q[i] += dx;
        return potential_energy(model, data, q);
      };
      const double grad = (8 * (V(h) - V(-h)) - (V(2 * h) - V(-2 * h))) / (12 * h);
      worst = std::max(worst, std::abs(grad - g[i]) / g.cwiseAbs().maxCoeff());
    }
  }
  EXPECT_LE(worst, 1e-9);
}

// Power balance along a motion driven by inverse-dynamics torques: d(T + V)/dt = qd . tau at every
// instant (fourth-order central difference of the energy, step 1e-3 s).
TEST(Energy, PowerBalanceAlongInverseDynamicsMotion) {
  const auto model = default_model<double>();
  Data<HumanModel<double>> data(model);
  const auto draws = random_states(16, 40, 35, 1.0, 3.0, 10.0);
  const double h = 1e-3;
  double worst = 0;
  for (std::size_t k = 0; k + 1 < draws.size(); k += 2) {
    const Motion m{draws[k].q, draws[k].qd, draws[k].qdd, draws[k + 1].qdd};
    const auto E = [&](double t) { return total_energy(model, data, m.q(t), m.qd(t)); };
    for (double t : {0.0, 0.1, 0.3}) {
      const double dE = (8 * (E(t + h) - E(t - h)) - (E(t + 2 * h) - E(t - 2 * h))) / (12 * h);
      const Eigen::VectorXd tau = rnea(model, data, m.q(t), m.qd(t), m.qdd(t));
      const double power = m.qd(t).dot(tau);
      const double scale = m.qd(t).cwiseAbs().dot(tau.cwiseAbs());
      worst = std::max(worst, std::abs(dE - power) / scale);
    }
  }
  std::printf("power balance, worst |dE/dt - qd.tau| / sum |qd_i tau_i|: %.2g\n", worst);
  EXPECT_LE(worst, 1e-8);
}

// A passive motion from forward dynamics (no torque, no damping) keeps its energy: RK4 with a small
// step, 0.5 s, both methods. RK4's error falls as h^4, so halving the step cuts the drift about 16x.
TEST(Energy, PassiveForwardDynamicsConservesEnergy) {
  using M = Model<double, SeedShape>;
  const M model(human_description(default_parameters()));
  Data<M> data(model);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(16);
  const auto run = [&](auto method_tag, double h) {
    constexpr FdMethod method = decltype(method_tag)::value;
    Eigen::VectorXd q = Eigen::VectorXd::Constant(16, 0.3), qd = Eigen::VectorXd::Zero(16);
    const double E0 = total_energy(model, data, q, qd);
    double swing = 0;
    const auto f = [&](const Eigen::VectorXd& x, const Eigen::VectorXd& v) {
      return Eigen::VectorXd(forward_dynamics<method>(model, data, x, v, zero));
    };
    for (int n = 0; n < int(0.5 / h + 0.5); ++n) {
      const Eigen::VectorXd a1 = f(q, qd);
      const Eigen::VectorXd v2 = qd + 0.5 * h * a1, a2 = f(q + 0.5 * h * qd, v2);
      const Eigen::VectorXd v3 = qd + 0.5 * h * a2, a3 = f(q + 0.5 * h * v2, v3);
      const Eigen::VectorXd v4 = qd + h * a3, a4 = f(q + h * v3, v4);
      q += h / 6 * (qd + 2 * v2 + 2 * v3 + v4);
      qd += h / 6 * (a1 + 2 * a2 + 2 * a3 + a4);
      swing = std::max(swing, kinetic_energy(model, data, q, qd));
    }
    return std::abs(total_energy(model, data, q, qd) - E0) / swing;
  };
  using Aba = std::integral_constant<FdMethod, FdMethod::Articulated>;
  using Ltdl = std::integral_constant<FdMethod, FdMethod::MassMatrix>;
  const double a1 = run(Aba{}, 2e-3), a2 = run(Aba{}, 1e-3), m2 = run(Ltdl{}, 1e-3);
  std::printf("passive 0.5 s, energy drift / peak kinetic energy: aba h=2ms %.2g, h=1ms %.2g; ltdl h=1ms %.2g\n", a1,
              a2, m2);
  EXPECT_LE(a2, 1e-6);
  EXPECT_LE(m2, 1e-6);
  EXPECT_GT(a1 / a2, 8.0) << "fourth order: halving h cuts the drift about 16x";
  EXPECT_LE(std::abs(a2 - m2), 1e-3 * a2 + 1e-12) << "the two methods give the same motion";
}

// Float: the quadratic form to float's precision (a few hundred roundings of 6e-8).
TEST(Energy, Float) {
  const auto md = default_model<double>();
  const auto mf = default_model<float>();
  Data<HumanModel<double>> dd(md);
  Data<HumanModel<float>> df(mf);
  double worst = 0;
  for (const auto& s : random_states(16, 200, 36, pi, 10, 0)) {
    const Eigen::VectorXf q = s.q.cast<float>(), qd = s.qd.cast<float>();
    const double T = kinetic_energy(md, dd, q.cast<double>(), qd.cast<double>());
    worst = std::max(worst, std::abs(double(kinetic_energy(mf, df, q, qd)) - T) / T);
  }
  EXPECT_LE(worst, 1e-5);
}

template <class M>
void expect_no_allocation(const M& model) {
  using S = typename M::scalar_type;
  using V = typename M::JointVector;
  Data<M> data(model);
  const V q = V::Constant(model.size(), S(0.3)), qd = V::Constant(model.size(), S(-0.7));
  Eigen::internal::set_is_malloc_allowed(false);
  const S e = kinetic_energy(model, data, q, qd) + potential_energy(model, data, q) + total_energy(model, data, q, qd);
  Eigen::internal::set_is_malloc_allowed(true);
  EXPECT_TRUE(std::isfinite(double(e)));
}

TEST(Energy, NoAllocation) {
  expect_no_allocation(default_model<double>());
  expect_no_allocation(default_model<float>());
  expect_no_allocation(AnyModel<double>(human_description(default_parameters())));
  expect_no_allocation(AnyModel<double>(human_description(default_parameters())).cast<float>());
}

}  // namespace test_energy
