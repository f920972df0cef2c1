// Crowd throughput (crowd.hpp's declarations): the same crowd, the same states, the scalar loop and the
// per-instruction-set kernels in one run.
#include "bench/crowd.hpp"

#include "bench/timing.hpp"
#include "cli/cores.hpp"
#include "humandyn/crowd_kernels.hpp"
#include "humandyn/integrators.hpp"
#include "support/crowd_states.hpp"

#include <algorithm>
#include <cstring>
#include <random>

namespace humandyn::bench {

namespace {

constexpr int nj = SeedShape::nj;
constexpr std::size_t crowd_size = 1024;  // per thread
constexpr double half_period_ns = 0.5e6;

template <class T>
using Crowd = CrowdStates<T, nj>;

// Best time (ns) of pass() over repetitions lasting `seconds` in all, the state restored before each.
template <class T, class Pass>
double best_pass_ns(Crowd<T>& crowd, double seconds, Pass&& pass) {
  crowd.restore();
  pass();  // warm-up
  double best = 1e300, spent = 0;
  for (int r = 0; r < 3 || spent < seconds * 1e9; ++r) {
    crowd.restore();
    const auto t0 = now_ns();
    pass();
    const double t = double(now_ns() - t0);
    best = std::min(best, t);
    spent += t;
  }
  return best;
}

const char* work_name(int w) { return w == 0 ? "ID" : w == 1 ? "step euler" : "step implicit"; }
Integrator integrator_of(int w) { return w == 1 ? Integrator::SemiImplicitEuler : Integrator::ImplicitPD; }

template <class T>
void rows_for(const HumanModel<T>& model, double seconds, int cores, CrowdReport& report) {
  const char* type = std::is_same_v<T, double> ? "double" : "float";
  const T h = T(1e-3);
  for (int w = 0; w < 3; ++w) {
    // the scalar loop, one character after another on its own State, tau and servo
    Crowd<T> crowd(crowd_size);
    double scalar_ns = 0;
    {
      Data<HumanModel<T>> data(model);
      StepWorkspace<HumanModel<T>> ws(model);
      std::vector<State<HumanModel<T>>> states(crowd.n, State<HumanModel<T>>(model));
      std::vector<PdServo<HumanModel<T>>> servos(crowd.n, PdServo<HumanModel<T>>(model));
      std::vector<typename HumanModel<T>::JointVector> tau(crowd.n);
      using V = Eigen::Map<const typename HumanModel<T>::JointVector>;
      for (std::size_t c = 0; c < crowd.n; ++c) {
        const std::size_t k = c * nj;
        tau[c] = V(crowd.tau.data() + k);
        character_servo(crowd.servo, c, servos[c]);
      }
      long refused = 0;
      const auto pass = [&] {
        for (std::size_t c = 0; c < crowd.n; ++c) {
          const std::size_t k = c * nj;
          if (w == 0) {
            do_not_optimize(rnea(model, data, V(crowd.q.data() + k), V(crowd.qd.data() + k), V(crowd.qdd.data() + k)));
            continue;
          }
          states[c].q = V(crowd.q.data() + k);  // (the restored start state)
          states[c].qd = V(crowd.qd.data() + k);
          const StepStatus st = w == 1
                                    ? step<Integrator::SemiImplicitEuler>(model, ws, states[c], tau[c], &servos[c], h)
                                    : step<Integrator::ImplicitPD>(model, ws, states[c], tau[c], &servos[c], h);
          refused += !st.ok();
        }
      };
      scalar_ns = best_pass_ns(crowd, seconds, pass) / double(crowd.n);
      report.rows.push_back({work_name(w), type, "scalar loop", 1, crowd.n, scalar_ns, int(half_period_ns / scalar_ns),
                             1.0, 1.0, refused});
    }
    // every instruction set's lanes, one thread
    for (Isa isa : available_isas()) {
      const CrowdKernel<T> kernel(model, isa);
      auto ws = kernel.workspace();
      const auto pass = [&] {
        if (w == 0)
          kernel.inverse_dynamics(ws, crowd.q.data(), crowd.qd.data(), crowd.qdd.data(), crowd.out.data(), 0, crowd.n);
        else
          kernel.step(integrator_of(w), ws, crowd.view(), 0, crowd.n, h);
      };
      const double ns = best_pass_ns(crowd, seconds, pass) / double(crowd.n);
      report.rows.push_back({work_name(w), type, std::string(isa_name(isa)) + " x" + std::to_string(kernel.width()), 1,
                             crowd.n, ns, int(half_period_ns / ns), scalar_ns / ns, 1.0, w == 0 ? 0 : crowd.refused()});
    }
    // the widest lanes on every core, on threads kept between passes (CrowdThreads): a crowd of crowd_size
    // per core, and one eight times larger
    if (cores > 1) {
      CrowdThreads team(cores);
      const CrowdKernel<T> kernel(model, widest_isa());
      std::vector<typename CrowdKernel<T>::Workspace> ws;
      for (int t = 0; t < cores; ++t) ws.push_back(kernel.workspace());
      const CrowdRow one = report.rows.back();
      for (std::size_t per_core : {crowd_size, 8 * crowd_size}) {
        Crowd<T> all(per_core * std::size_t(cores));
        const auto pass = [&] {
          team.run(all.n, kernel.width(), [&](int t, std::size_t b, std::size_t e) {
            if (w == 0)
              kernel.inverse_dynamics(ws[std::size_t(t)], all.q.data(), all.qd.data(), all.qdd.data(), all.out.data(),
                                      b, e);
            else
              kernel.step(integrator_of(w), ws[std::size_t(t)], all.view(), b, e, h);
          });
        };
        const double ns = best_pass_ns(all, seconds, pass) / double(all.n);
        report.rows.push_back(
            {work_name(w), type, one.lanes, cores, all.n, ns, int(half_period_ns / ns), scalar_ns / ns,
             (half_period_ns / ns) / (cores * (half_period_ns / one.ns_per_character)), w == 0 ? 0 : all.refused()});
      }
    }
  }
}

}  // namespace

CrowdReport run_crowd(const ModelDescription<double>& d, double seconds, double loop_seconds) {
  CrowdReport report;
  report.cores = cli::usable_cores();  // (the affinity mask: taskset -c 0 is one core)
  const HumanModel<double> model(d);
  rows_for(model, seconds, report.cores, report);
  rows_for(HumanModel<float>(d.cast<float>()), seconds, report.cores, report);

  // the 1 kHz loop at the size fitted for one core: widest lanes, double, implicit step
  int fitted = 1;
  for (const auto& r : report.rows)
    if (r.work == std::string("step implicit") && r.scalar == "double" && r.threads == 1 && r.lanes != "scalar loop")
      fitted = std::max(1, r.characters);  // (the rows run narrowest to widest: the widest's stays)
  const CrowdKernel<double> kernel(model, widest_isa());
  auto ws = kernel.workspace();
  Crowd<double> crowd{std::size_t(fitted)};
  report.loop = run_fixed_period_loop(
      std::string("crowd step implicit (double, ") + isa_name(widest_isa()) + ")", fitted,
      [&](long) { kernel.step(Integrator::ImplicitPD, ws, crowd.view(), 0, crowd.n, 1e-3); }, loop_seconds);
  return report;
}

}  // namespace humandyn::bench
