// Micro-benchmarks of every per-call function of humandyn, with KDL's solvers on the same model and the
// same states in the same binary (and Pinocchio's, when it was found: bench_pinocchio.cpp). Each
// benchmark is one line of the table in register_benchmarks().
#include "bench_common.hpp"
#include "support/kdl_tree.hpp"

#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"

#include "humandyn/algorithm/crba.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/rnea_derivatives.hpp"
#include "humandyn/floating.hpp"
#include "humandyn/integrators.hpp"
#include "humandyn/servo.hpp"

#include <benchmark/benchmark.h>
#include <kdl/chaindynparam.hpp>
#include <kdl/chainfdsolver_recursive_newton_euler.hpp>
#include <kdl/chainidsolver_recursive_newton_euler.hpp>
#include <kdl/treeidsolver_recursive_newton_euler.hpp>

#include <cstdio>
#include <cstring>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace humandyn::bench {

namespace {

using HD = HumanModel<double>;
using HF = HumanModel<float>;
using AD = AnyModel<double>;
using AF = AnyModel<float>;

// ---- humandyn ---------------------------------------------------------------------------------------

template <class Model>
void forward_kinematics_bench(benchmark::State& st) {
  const auto& model = bench_model<Model>();
  Data<Model> data(model);
  const auto& pool = typed_pool<typename Model::JointVector>();
  over_pool(st, [&](std::size_t i) {
    forward_kinematics(model, data, pool.q[i]);
    benchmark::DoNotOptimize(data.com);
  });
}

template <class Model, Terms terms>
void rnea_bench(benchmark::State& st) {
  const auto& model = bench_model<Model>();
  Data<Model> data(model);
  const auto& pool = typed_pool<typename Model::JointVector>();
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(rnea<terms>(model, data, pool.q[i], pool.qd[i], pool.qdd[i]));
  });
}

// Torques that realise the pool's accelerations: forward dynamics then runs on realistic inputs.
template <class Model>
const std::vector<typename Model::JointVector>& tau_pool() {
  static const auto taus = [] {
    const auto& model = bench_model<Model>();
    Data<Model> data(model);
    const auto& pool = typed_pool<typename Model::JointVector>();
    std::vector<typename Model::JointVector> out;
    for (std::size_t i = 0; i < pool.q.size(); ++i)
      out.push_back(rnea(model, data, pool.q[i], pool.qd[i], pool.qdd[i]));
    return out;
  }();
  return taus;
}

template <class Model>
void crba_bench(benchmark::State& st) {
  const auto& model = bench_model<Model>();
  Data<Model> data(model);
  const auto& pool = typed_pool<typename Model::JointVector>();
  over_pool(st, [&](std::size_t i) { benchmark::DoNotOptimize(crba(model, data, pool.q[i])); });
}

template <class Model, FdMethod method, Terms terms>
void forward_dynamics_bench(benchmark::State& st) {
  const auto& model = bench_model<Model>();
  Data<Model> data(model);
  const auto& pool = typed_pool<typename Model::JointVector>();
  const auto& tau = tau_pool<Model>();
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(forward_dynamics<method, terms>(model, data, pool.q[i], pool.qd[i], tau[i]));
  });
}

// ---- the floating form: the same body with a free base at the pelvis -------------------------------------

// What the floating form's benchmarks run on: the model, a workspace, the pool and a base state per pool state.
struct FloatingBench {
  const FD& model = floating_bench_model();
  FloatingData<FD> fd{model};
  const TypedPool<FD::JointVector>& pool = typed_pool<FD::JointVector>();
  const std::vector<BaseSample>& base = base_pool();
};

void floating_rnea_bench(benchmark::State& st) {
  FloatingBench f;
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(
        floating_rnea(f.model, f.fd, f.base[i].X, f.base[i].v, f.base[i].a, f.pool.q[i], f.pool.qd[i], f.pool.qdd[i]));
    benchmark::DoNotOptimize(f.fd.base_wrench);
  });
}

// dtau/dq and dtau/dqd at the pool's states (rnea_derivatives.hpp)
template <class Model>
void rnea_derivatives_bench(benchmark::State& st) {
  const auto& model = bench_model<Model>();
  DerivativeData<Model> dd(model);
  const auto& pool = typed_pool<typename Model::JointVector>();
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(rnea_derivatives(model, dd, pool.q[i], pool.qd[i], pool.qdd[i]));
  });
}

template <FdMethod method>
void floating_fd_bench(benchmark::State& st) {
  FloatingBench f;
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(floating_forward_dynamics<method>(f.model, f.fd, f.base[i].X, f.base[i].v, f.pool.q[i],
                                                               f.pool.qd[i], f.pool.qdd[i]));
    benchmark::DoNotOptimize(f.fd.a_b);
  });
}

// dqdd/dq, dqdd/dqd and dqdd/dtau at the pool's states and the torques of their accelerations
template <class Model>
void forward_dynamics_derivatives_bench(benchmark::State& st) {
  const auto& model = bench_model<Model>();
  Data<Model> data(model);
  DerivativeData<Model> dd(model);
  const auto& pool = typed_pool<typename Model::JointVector>();
  const auto& tau = tau_pool<Model>();
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(forward_dynamics_derivatives(model, data, dd, pool.q[i], pool.qd[i], tau[i]));
  });
}

// What both step benchmarks need: a workspace, a state, the HD servo (kp 200, kd 20), and Newton's work
// per backward-Euler step (inverse-dynamics residuals, Jacobians: derivatives and an LU) as counters.
template <class Model>
struct ServoSteps {
  using S = typename Model::scalar_type;
  const Model& model = bench_model<Model>();
  StepWorkspace<Model> ws{model};
  State<Model> x{model};
  PdServo<Model> servo{model};
  double residuals = 0, jacobians = 0;
  ServoSteps() {
    servo.kp.setConstant(S(200));
    servo.kd.setConstant(S(20));
  }
  void count() noexcept {
    residuals += ws.report.residuals;
    jacobians += ws.report.jacobians;
  }
  void report(benchmark::State& st, Integrator integrator) const {
    if (integrator != Integrator::BackwardEuler) return;
    st.counters["residuals"] = benchmark::Counter(residuals, benchmark::Counter::kAvgIterations);
    st.counters["jacobians"] = benchmark::Counter(jacobians, benchmark::Counter::kAvgIterations);
  }
};

// One step of 1 ms from a pool state, the HD servo tracking the pool's next state (a full simulation
// step: forward dynamics, integration, HD tracking; backward Euler: its Newton iterations and energy check).
template <class Model, Integrator integrator, FdMethod method>
void step_bench(benchmark::State& st) {
  using S = typename Model::scalar_type;
  ServoSteps<Model> b;
  const auto& pool = typed_pool<typename Model::JointVector>();
  const auto& tau = tau_pool<Model>();
  std::size_t i = 0;
  for ([[maybe_unused]] auto _ : st) {
    b.x.q = pool.q[i];
    b.x.qd = pool.qd[i];
    const std::size_t j = next_state(i);
    b.servo.q_ref = pool.q[j];
    b.servo.qd_ref = pool.qd[j];
    benchmark::DoNotOptimize(step<integrator, method>(b.model, b.ws, b.x, tau[i], &b.servo, S(1e-3)));
    benchmark::DoNotOptimize(b.x.q);
    b.count();
    i = j;
  }
  b.report(st, integrator);
}

// Steps of 1 ms continuing one simulation, as a character is stepped frame after frame: the HD servo
// tracks a reference that swings every joint by 0.3 rad at 1 Hz about a pool pose; a step that fails
// (none does) starts over from that pose at rest.
template <class Model, Integrator integrator>
void simulation_step_bench(benchmark::State& st) {
  using S = typename Model::scalar_type;
  using JointVector = typename Model::JointVector;
  ServoSteps<Model> b;
  const JointVector home = typed_pool<JointVector>().q[0];
  const JointVector tau = JointVector::Zero(b.model.size());
  b.x.q = home;
  b.x.qd.setZero();
  const S h = S(1e-3), omega = S(2 * M_PI);
  long steps = 0, failures = 0;
  for ([[maybe_unused]] auto _ : st) {
    const S t = S(steps++) * h;
    b.servo.q_ref = home.array() + S(0.3) * std::sin(omega * t);
    b.servo.qd_ref.setConstant(S(0.3) * omega * std::cos(omega * t));
    if (!step<integrator>(b.model, b.ws, b.x, tau, &b.servo, h)) {
      ++failures;
      b.x.q = home;
      b.x.qd.setZero();
    }
    benchmark::DoNotOptimize(b.x.q);
    b.count();
  }
  st.counters["failures"] = double(failures);
  b.report(st, integrator);
}

// ---- KDL --------------------------------------------------------------------------------------------

KDL::JntArray jnt(const Eigen::VectorXd& v, int n) {
  KDL::JntArray a(static_cast<unsigned>(n));
  a.data = v.head(n);
  return a;
}

struct KdlPool {
  std::vector<KDL::JntArray> q, qd, qdd, tau;
};

// The pool as KDL arrays over the first n joints (the whole tree, or the chain foot -> left hand, whose
// joints are the model's joints 1-9 in order).
const KdlPool& kdl_pool(int n) {
  static std::vector<std::unique_ptr<KdlPool>> pools(64);
  auto& p = pools[std::size_t(n)];
  if (!p) {
    p = std::make_unique<KdlPool>();
    const auto& s = random_pool();
    for (int i = 0; i < s.size(); ++i) {
      p->q.push_back(jnt(s.q[std::size_t(i)], n));
      p->qd.push_back(jnt(s.qd[std::size_t(i)], n));
      p->qdd.push_back(jnt(s.qdd[std::size_t(i)], n));
    }
  }
  return *p;
}

const KDL::Tree& kdl_tree() {
  static const KDL::Tree tree = testing::kdl_tree(bench_description());
  return tree;
}

// The longest serial chain of the seed body: right foot to left hand, 9 joints (the model's 1-9), cut out
// of the tree of `d`.
KDL::Chain foot_to_hand(const ModelDescription<double>& d) {
  KDL::Chain c;
  if (!testing::kdl_tree(d).getChain("root", testing::kdl_segment_name(d, 8), c))
    throw std::runtime_error("no KDL chain from the foot to the left hand");
  return c;
}

const KDL::Chain& kdl_chain_foot_to_hand() {
  static const KDL::Chain chain = foot_to_hand(bench_description());
  return chain;
}

// KDL's inverse dynamics by `solver` (tree or chain) over the pool's first n joints, no external wrench.
template <class Solver, class Wrenches>
void kdl_rnea(benchmark::State& st, Solver& solver, int n, const Wrenches& no_wrenches) {
  const auto& pool = kdl_pool(n);
  KDL::JntArray tau(static_cast<unsigned>(n));
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(solver.CartToJnt(pool.q[i], pool.qd[i], pool.qdd[i], no_wrenches, tau));
    benchmark::DoNotOptimize(tau.data);
  });
}

void kdl_tree_rnea(benchmark::State& st) {
  KDL::TreeIdSolver_RNE solver(kdl_tree(), testing::kdl_gravity(bench_description()));
  kdl_rnea(st, solver, int(kdl_tree().getNrOfJoints()), KDL::WrenchMap());
}

void kdl_chain_rnea(benchmark::State& st) {
  const auto& chain = kdl_chain_foot_to_hand();
  KDL::ChainIdSolver_RNE solver(chain, testing::kdl_gravity(bench_description()));
  kdl_rnea(st, solver, int(chain.getNrOfJoints()), KDL::Wrenches(chain.getNrOfSegments(), KDL::Wrench::Zero()));
}

void kdl_chain_fd(benchmark::State& st) {
  const auto& chain = kdl_chain_foot_to_hand();
  KDL::ChainFdSolver_RNE solver(chain, testing::kdl_gravity(bench_description()));
  KDL::ChainIdSolver_RNE id(chain, testing::kdl_gravity(bench_description()));
  const int n = int(chain.getNrOfJoints());
  const auto& pool = kdl_pool(n);
  const KDL::Wrenches no_wrenches(chain.getNrOfSegments(), KDL::Wrench::Zero());
  // the chain's own torques for the pool's accelerations
  std::vector<KDL::JntArray> tau(pool.q.size(), KDL::JntArray(unsigned(n)));
  for (std::size_t k = 0; k < pool.q.size(); ++k) id.CartToJnt(pool.q[k], pool.qd[k], pool.qdd[k], no_wrenches, tau[k]);
  KDL::JntArray qdd(static_cast<unsigned>(n));
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(solver.CartToJnt(pool.q[i], pool.qd[i], tau[i], no_wrenches, qdd));
    benchmark::DoNotOptimize(qdd.data);
  });
}

void kdl_chain_mass_matrix(benchmark::State& st) {
  const auto& chain = kdl_chain_foot_to_hand();
  KDL::ChainDynParam dyn(chain, testing::kdl_gravity(bench_description()));
  const int n = int(chain.getNrOfJoints());
  const auto& pool = kdl_pool(n);
  KDL::JntSpaceInertiaMatrix M(static_cast<unsigned>(n));
  over_pool(st, [&](std::size_t i) {
    benchmark::DoNotOptimize(dyn.JntToMass(pool.q[i], M));
    benchmark::DoNotOptimize(M.data);
  });
}

}  // namespace

// Pinocchio's benchmarks (bench_pinocchio.cpp), when it was found.
#ifdef HUMANDYN_WITH_PINOCCHIO
void register_pinocchio_benchmarks();
#endif

namespace {

void register_benchmarks() {
  using Fn = void (*)(benchmark::State&);
  const std::vector<std::pair<const char*, Fn>> table{
      {"fk/double/static", forward_kinematics_bench<HD>},
      {"fk/float/static", forward_kinematics_bench<HF>},
      {"fk/double/dynamic", forward_kinematics_bench<AD>},
      {"rnea/full/double/static", rnea_bench<HD, Terms::Full>},
      {"rnea/no_coriolis/double/static", rnea_bench<HD, Terms::NoCoriolis>},
      {"rnea/gravity/double/static", rnea_bench<HD, Terms::GravityOnly>},
      {"rnea/full/float/static", rnea_bench<HF, Terms::Full>},
      {"rnea/no_coriolis/float/static", rnea_bench<HF, Terms::NoCoriolis>},
      {"rnea/gravity/float/static", rnea_bench<HF, Terms::GravityOnly>},
      {"rnea/full/double/dynamic", rnea_bench<AD, Terms::Full>},
      {"rnea/no_coriolis/double/dynamic", rnea_bench<AD, Terms::NoCoriolis>},
      {"rnea/gravity/double/dynamic", rnea_bench<AD, Terms::GravityOnly>},
      {"rnea/full/float/dynamic", rnea_bench<AF, Terms::Full>},
      {"rnea/no_coriolis/float/dynamic", rnea_bench<AF, Terms::NoCoriolis>},
      {"rnea/gravity/float/dynamic", rnea_bench<AF, Terms::GravityOnly>},
      {"derivatives/rnea/double/static", rnea_derivatives_bench<HD>},
      {"derivatives/rnea/float/static", rnea_derivatives_bench<HF>},
      {"derivatives/rnea/double/dynamic", rnea_derivatives_bench<AD>},
      {"derivatives/fd/double/static", forward_dynamics_derivatives_bench<HD>},
      {"crba/double/static", crba_bench<HD>},
      {"crba/float/static", crba_bench<HF>},
      {"crba/double/dynamic", crba_bench<AD>},
      {"fd/mass_matrix/full/double/static", forward_dynamics_bench<HD, FdMethod::MassMatrix, Terms::Full>},
      {"fd/articulated/full/double/static", forward_dynamics_bench<HD, FdMethod::Articulated, Terms::Full>},
      {"fd/mass_matrix/no_coriolis/double/static", forward_dynamics_bench<HD, FdMethod::MassMatrix, Terms::NoCoriolis>},
      {"fd/articulated/no_coriolis/double/static",
       forward_dynamics_bench<HD, FdMethod::Articulated, Terms::NoCoriolis>},
      {"fd/mass_matrix/full/float/static", forward_dynamics_bench<HF, FdMethod::MassMatrix, Terms::Full>},
      {"fd/articulated/full/float/static", forward_dynamics_bench<HF, FdMethod::Articulated, Terms::Full>},
      {"fd/mass_matrix/full/double/dynamic", forward_dynamics_bench<AD, FdMethod::MassMatrix, Terms::Full>},
      {"fd/articulated/full/double/dynamic", forward_dynamics_bench<AD, FdMethod::Articulated, Terms::Full>},
      {"floating/rnea/full/double", floating_rnea_bench},
      {"floating/fd/mass_matrix/full/double", floating_fd_bench<FdMethod::MassMatrix>},
      {"floating/fd/articulated/full/double", floating_fd_bench<FdMethod::Articulated>},
      {"step/euler/mass_matrix/double", step_bench<HD, Integrator::SemiImplicitEuler, FdMethod::MassMatrix>},
      {"step/euler/articulated/double", step_bench<HD, Integrator::SemiImplicitEuler, FdMethod::Articulated>},
      {"step/rk4/mass_matrix/double", step_bench<HD, Integrator::RungeKutta4, FdMethod::MassMatrix>},
      {"step/rk4/articulated/double", step_bench<HD, Integrator::RungeKutta4, FdMethod::Articulated>},
      {"step/implicit/mass_matrix/double", step_bench<HD, Integrator::ImplicitPD, FdMethod::MassMatrix>},
      {"step/backward_euler/double", step_bench<HD, Integrator::BackwardEuler, FdMethod::MassMatrix>},
      {"step/backward_euler/float", step_bench<HF, Integrator::BackwardEuler, FdMethod::MassMatrix>},
      {"step/simulation/implicit/double", simulation_step_bench<HD, Integrator::ImplicitPD>},
      {"step/simulation/backward_euler/double", simulation_step_bench<HD, Integrator::BackwardEuler>},
      {"step/euler/mass_matrix/float", step_bench<HF, Integrator::SemiImplicitEuler, FdMethod::MassMatrix>},
      {"kdl/TreeIdSolver_RNE/tree16", kdl_tree_rnea},
      {"kdl/ChainIdSolver_RNE/chain9_foot_to_hand", kdl_chain_rnea},
      {"kdl/ChainFdSolver_RNE/chain9_foot_to_hand", kdl_chain_fd},
      {"kdl/ChainDynParam_JntToMass/chain9_foot_to_hand", kdl_chain_mass_matrix},
  };
  for (const auto& [name, fn] : table) benchmark::RegisterBenchmark(name, fn);
#ifdef HUMANDYN_WITH_PINOCCHIO
  register_pinocchio_benchmarks();
#endif
}

}  // namespace

}  // namespace humandyn::bench

int main(int argc, char** argv) {
  // --model NAME (or --model=NAME) is ours; everything else goes to Google Benchmark
  std::vector<char*> rest{argv[0]};
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    std::string name;
    if (a.rfind("--model=", 0) == 0)
      name = a.substr(8);
    else if (a == "--model" && i + 1 < argc)
      name = argv[++i];
    else {
      rest.push_back(argv[i]);
      continue;
    }
    if (!humandyn::bench::select_model(name)) {
      std::fprintf(stderr, "humandyn_bench: unknown model '%s' (default|female|paper)\n", name.c_str());
      return 2;
    }
  }
  int rest_argc = int(rest.size());
  benchmark::Initialize(&rest_argc, rest.data());
  if (benchmark::ReportUnrecognizedArguments(rest_argc, rest.data())) return 2;
  benchmark::AddCustomContext("model", humandyn::bench::bench_description().name);
#ifdef __OPTIMIZE__
  benchmark::AddCustomContext("optimised", "yes");
#endif
  benchmark::AddCustomContext("march_native",
#ifdef HUMANDYN_MARCH_NATIVE
                              "on"
#else
                              "off"
#endif
  );
  humandyn::bench::register_benchmarks();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

// The model, chosen before any benchmark runs.
namespace humandyn::bench {
namespace {
ModelDescription<double>& selected() {
  static ModelDescription<double> d = human_description(default_parameters());
  return d;
}
}  // namespace
const ModelDescription<double>& bench_description() { return selected(); }
bool select_model(const std::string& name) {
  if (name == "default")
    selected() = human_description(default_parameters());
  else if (name == "female")
    selected() = human_description(female_parameters());
  else if (name == "paper")
    selected() = human_description(paper_parameters());
  else
    return false;
  return true;
}
}  // namespace humandyn::bench
