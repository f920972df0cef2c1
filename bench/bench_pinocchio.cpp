// Pinocchio's rnea, computeGeneralizedGravity, aba, crba, computeRNEADerivatives and computeABADerivatives on the same human, the same states and with
// the same flags. The model is built through Pinocchio's C++ API from the same description: each joint a
// revolute about z (JointModelRZ) placed at its parent link frame * mount * Rz(theta), each link's body
// appended at Tz(d) Tx(a) Rx(alpha) from its joint frame. Before the benchmarks are registered, Pinocchio's
// torques are checked against humandyn's on the pool: a model that disagrees is never timed.
#include "bench_common.hpp"

#include "humandyn/algorithm/rnea.hpp"

#include <pinocchio/algorithm/aba-derivatives.hpp>
#include <pinocchio/algorithm/aba.hpp>
#include <pinocchio/algorithm/crba.hpp>
#include <pinocchio/algorithm/rnea-derivatives.hpp>
#include <pinocchio/algorithm/rnea.hpp>
#include <pinocchio/multibody.hpp>

#include <benchmark/benchmark.h>

#include <cmath>
#include <cstdio>
#include <stdexcept>

namespace humandyn::bench {

namespace {

pinocchio::SE3 se3(const Pose<double>& X) { return pinocchio::SE3(X.R, X.p); }

// Rz(theta)
pinocchio::SE3 rot_z(double theta) {
  return pinocchio::SE3(Eigen::AngleAxisd(theta, Eigen::Vector3d::UnitZ()).toRotationMatrix(), Eigen::Vector3d::Zero());
}

// The DH link after the joint's rotation: Tz(d) Tx(a) Rx(alpha).
pinocchio::SE3 dh_link(const DHParameters<double>& dh) {
  return pinocchio::SE3(Eigen::AngleAxisd(dh.alpha, Eigen::Vector3d::UnitX()).toRotationMatrix(),
                        Eigen::Vector3d(dh.a, 0, dh.d));
}

pinocchio::Model pinocchio_model(const ModelDescription<double>& d) {
  pinocchio::Model m;
  std::vector<pinocchio::SE3> link_in_joint;  // link frame i seen from Pinocchio's joint frame i
  for (std::size_t i = 0; i < d.joints.size(); ++i) {
    const auto& j = d.joints[i];
    // the joint frame: the parent's link frame, the mount, the DH offset theta
    pinocchio::SE3 placement = j.parent < 0 ? pinocchio::SE3::Identity() : link_in_joint[std::size_t(j.parent)];
    if (j.mounted) placement = placement * se3(j.mount);
    placement = placement * rot_z(j.dh.theta);
    const auto parent = pinocchio::JointIndex(j.parent + 1);  // 0 is the universe (our base)
    const auto id = m.addJoint(parent, pinocchio::JointModelRZ(), placement, j.name);
    link_in_joint.push_back(dh_link(j.dh));
    m.appendBodyToJoint(id, pinocchio::Inertia(j.body.mass, j.body.com, j.body.inertia), link_in_joint.back());
  }
  m.gravity.linear(d.base_pose.R.transpose() * d.gravity);  // Pinocchio's universe is our base frame
  return m;
}

const pinocchio::Model& pin_model() {
  static const pinocchio::Model m = pinocchio_model(bench_description());
  return m;
}

// Pinocchio against humandyn on the whole pool: the largest torque difference (N m).
double largest_difference() {
  const auto& model = bench_model<HumanModel<double>>();
  Data<HumanModel<double>> data(model);
  pinocchio::Data pd(pin_model());
  const auto& s = random_pool();
  double worst = 0;
  for (int i = 0; i < s.size(); ++i) {
    const auto k = std::size_t(i);
    const Eigen::VectorXd ours = rnea(model, data, s.q[k], s.qd[k], s.qdd[k]);
    const Eigen::VectorXd theirs = pinocchio::rnea(pin_model(), pd, s.q[k], s.qd[k], s.qdd[k]);
    worst = std::max(worst, (ours - theirs).cwiseAbs().maxCoeff());
  }
  return worst;
}

void pin_rnea(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  std::size_t i = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(pinocchio::rnea(pin_model(), data, pool.q[i], pool.qd[i], pool.qdd[i]));
    i = next_state(i);
  }
}

void pin_gravity(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  std::size_t i = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(pinocchio::computeGeneralizedGravity(pin_model(), data, pool.q[i]));
    i = next_state(i);
  }
}

void pin_aba(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  // the torques of the pool's accelerations
  std::vector<Eigen::VectorXd> tau;
  for (std::size_t k = 0; k < pool.q.size(); ++k) tau.push_back(pinocchio::rnea(pin_model(), data, pool.q[k], pool.qd[k], pool.qdd[k]));
  std::size_t i = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(pinocchio::aba(pin_model(), data, pool.q[i], pool.qd[i], tau[i]));
    i = next_state(i);
  }
}

void pin_rnea_derivatives(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  std::size_t i = 0;
  for (auto _ : st) {
    pinocchio::computeRNEADerivatives(pin_model(), data, pool.q[i], pool.qd[i], pool.qdd[i]);
    benchmark::DoNotOptimize(data.dtau_dq.data());
    i = next_state(i);
  }
}

void pin_aba_derivatives(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  std::vector<Eigen::VectorXd> tau;
  for (std::size_t k = 0; k < pool.q.size(); ++k) tau.push_back(pinocchio::rnea(pin_model(), data, pool.q[k], pool.qd[k], pool.qdd[k]));
  std::size_t i = 0;
  for (auto _ : st) {
    pinocchio::computeABADerivatives(pin_model(), data, pool.q[i], pool.qd[i], tau[i]);
    benchmark::DoNotOptimize(data.ddq_dq.data());
    i = next_state(i);
  }
}

void pin_crba(benchmark::State& st) {
  pinocchio::Data data(pin_model());
  const auto& pool = random_pool();
  std::size_t i = 0;
  for (auto _ : st) {
    benchmark::DoNotOptimize(pinocchio::crba(pin_model(), data, pool.q[i]));
    i = next_state(i);
  }
}

}  // namespace

void register_pinocchio_benchmarks() {
  const double diff = largest_difference();
  if (!(diff <= 1e-9)) {
    std::fprintf(stderr, "Pinocchio's model disagrees with humandyn by %.3g N m: its benchmarks are skipped\n", diff);
    return;
  }
  char text[32];
  std::snprintf(text, sizeof text, "%.1e", diff);
  benchmark::AddCustomContext("pinocchio_vs_humandyn_max_torque_difference_Nm", text);
  benchmark::RegisterBenchmark("pinocchio/rnea", pin_rnea);
  benchmark::RegisterBenchmark("pinocchio/computeGeneralizedGravity", pin_gravity);
  benchmark::RegisterBenchmark("pinocchio/aba", pin_aba);
  benchmark::RegisterBenchmark("pinocchio/crba", pin_crba);
  benchmark::RegisterBenchmark("pinocchio/computeRNEADerivatives", pin_rnea_derivatives);
  benchmark::RegisterBenchmark("pinocchio/computeABADerivatives", pin_aba_derivatives);
}

}  // namespace humandyn::bench
