// humandyn bench: the project's main job. Three measurements on one model:
//   1. the 1 kHz loop: K characters per 1 ms tick (inverse dynamics; a full simulation step; KDL's tree
//      solver for the same K), latency percentiles, deadline misses, share of the period used, the
//      largest K with 50 % headroom;
//   2. error against run time: every variant of the table in bench_variants(), timed and compared with
//      a long double reference of the full model, on random states and on realistic motions;
//   3. integration work-precision: each integrator over a sweep of steps on a tracked walk and a passive
//      swing, end-state error against a fine long double reference versus computing time;
//   4. crowds: characters per core (and on every core) at 1 kHz with half the period free, the scalar
//      loop against the SIMD lanes of each instruction set (bench/crowd.hpp), and the 1 kHz loop at that size;
// printed as tables, and on request written as JSON and CSV (tools/plot_bench.py draws the charts).
#include "bench/crowd.hpp"
#include "bench/realtime_loop.hpp"
#include "bench/scene_variants.hpp"
#include "bench/variants.hpp"
#include "bench/work_precision.hpp"
#include "cli/atomic_file.hpp"
#include "cli/commands.hpp"
#include "cli/model_source.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"
#include "humandyn/model.hpp"
#include "support/motions.hpp"
#include "text/shown.hpp"

#ifdef HUMANDYN_BENCH_WITH_KDL
#include "bench/kdl_variants.hpp"
#endif
#include "bench/simulation.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#ifndef HUMANDYN_CXX_FLAGS
#define HUMANDYN_CXX_FLAGS "unknown"
#endif

namespace humandyn::cli {

namespace {

using namespace humandyn::bench;

// How long each measurement runs.
struct Budget {
  double loop_seconds = 5;       // each real-time loop
  double variant_seconds = 0.3;  // timing of one variant on one workload
  int random_states = 1000;
  int motion_samples = 500;                   // per motion
  double reference_steps_per_second = 40000;  // the long double RK4 reference of the work-precision runs
  std::vector<double> steps_h{1e-4, 2e-4, 5e-4, 1e-3, 2e-3, 5e-3, 1e-2, 1.0 / 60, 1.0 / 30};
  double min_run_seconds = 0.02;  // each work-precision run is repeated until it has taken this long
  double crowd_seconds = 0.3;     // timing of one crowd row
};

// ---------------------------------------------------------------------------------------------------
// The table of variants: one line each.

bool is_seed_shape(const ModelDescription<double>& d);

std::vector<Variant> bench_variants(const ModelDescription<double>& d) {
  std::vector<Variant> v;
  // the model as a runtime shape (what an imported model runs)
  const auto dd = std::make_shared<const AnyModel<double>>(d);
  const auto df = std::make_shared<const AnyModel<float>>(d.cast<float>());
  if (is_seed_shape(d)) {
    // the seed shape, known at compile time
    const auto sd = std::make_shared<const HumanModel<double>>(d);
    const auto sf = std::make_shared<const HumanModel<float>>(d.cast<float>());
    v.push_back(rnea_variant<Terms::Full>("ID full double", "double", sd));
    v.push_back(rnea_variant<Terms::NoCoriolis>("ID no-Coriolis double", "double", sd));
    v.push_back(rnea_variant<Terms::GravityOnly>("ID gravity double", "double", sd));
    v.push_back(rnea_variant<Terms::Full>("ID full float", "float", sf));
    v.push_back(rnea_variant<Terms::NoCoriolis>("ID no-Coriolis float", "float", sf));
    v.push_back(rnea_variant<Terms::GravityOnly>("ID gravity float", "float", sf));
    // forward dynamics (a model with a regular mass matrix: the paper model's is singular)
    v.push_back(forward_dynamics_variant<FdMethod::MassMatrix, Terms::Full>("FD mass matrix double", "double", sd));
    v.push_back(forward_dynamics_variant<FdMethod::Articulated, Terms::Full>("FD articulated double", "double", sd));
    v.push_back(forward_dynamics_variant<FdMethod::MassMatrix, Terms::NoCoriolis>("FD mass matrix no-Coriolis double",
                                                                                  "double", sd));
    v.push_back(forward_dynamics_variant<FdMethod::MassMatrix, Terms::Full>("FD mass matrix float", "float", sf));
    v.push_back(forward_dynamics_variant<FdMethod::Articulated, Terms::Full>("FD articulated float", "float", sf));
    v.push_back(forward_dynamics_variant<FdMethod::MassMatrix, Terms::Full>("FD mass matrix double dynamic-shape",
                                                                            "double", dd));
  }
  v.push_back(rnea_variant<Terms::Full>("ID full double dynamic-shape", "double", dd));
  v.push_back(rnea_variant<Terms::Full>("ID full float dynamic-shape", "float", df));
#ifdef HUMANDYN_BENCH_WITH_KDL
  v.push_back(kdl_tree_id_variant(d));
#endif
  // the named scenes (scene.hpp): reduced models that drop joints or terms
  for (auto& s : scene_variants(d)) v.push_back(std::move(s));
  return v;
}

bool is_seed_shape(const ModelDescription<double>& d) {
  try {
    HumanModel<double> m(d);
    return true;
  } catch (const ModelError&) {
    return false;
  }
}

// ---------------------------------------------------------------------------------------------------
// 1. the 1 kHz loop

struct LoopReport {
  std::vector<LoopStats> runs;  // at K, then the headroom check at the largest K that fits
  struct Fit {
    std::string work;
    int k_fit = 0;  // largest K whose p99 compute fits half the period
  };
  std::vector<Fit> fits;
};

// The largest K whose tick, at the p99 cost per character measured in `s`, uses at most half the period.
int largest_k_with_headroom(const LoopStats& s) {
  const double per_character = s.compute_p99_us / std::max(1, s.characters);
  return per_character > 0 ? int(std::floor(0.5 * s.period_us / per_character)) : 0;
}

// The work of one tick for K characters, each at its own phase of the 1.1 s motion sampled at 1 kHz (the
// walk, or another model's swing: loop_motion).
using TickWork = std::function<void(long tick)>;
using WorkFactory = std::function<TickWork(int k)>;

std::vector<std::pair<std::string, WorkFactory>> loop_works(const ModelDescription<double>& d, const StateSet& walk) {
  std::vector<std::pair<std::string, WorkFactory>> works;
  const int n = walk.size();
  const auto phase = [n](long tick, int c) { return std::size_t(((tick + 37L * c) % n + n) % n); };

  if (is_seed_shape(d)) {
    const auto model = std::make_shared<const HumanModel<double>>(d);
    using V = HumanModel<double>::JointVector;
    const auto q = std::make_shared<std::vector<V>>(cast_all<V>(walk.q));
    const auto qd = std::make_shared<std::vector<V>>(cast_all<V>(walk.qd));
    const auto qdd = std::make_shared<std::vector<V>>(cast_all<V>(walk.qdd));
    works.emplace_back("humandyn ID (full, double)", [=](int k) -> TickWork {
      auto data =
          std::make_shared<std::vector<Data<HumanModel<double>>>>(std::size_t(k), Data<HumanModel<double>>(*model));
      return [=](long tick) {
        for (int c = 0; c < k; ++c) {
          const auto s = phase(tick, c);
          do_not_optimize(rnea<Terms::Full>(*model, (*data)[std::size_t(c)], (*q)[s], (*qd)[s], (*qdd)[s]));
        }
      };
    });
  }
  if (!is_seed_shape(d)) {
    // another model: its runtime shape (what an imported model runs)
    using M = AnyModel<double>;
    const auto model = std::make_shared<const M>(d);
    const auto motion = std::make_shared<const StateSet>(walk);
    works.emplace_back("humandyn ID (full, double, runtime shape)", [=](int k) -> TickWork {
      auto data = std::make_shared<std::vector<Data<M>>>(std::size_t(k), Data<M>(*model));
      return [=](long tick) {
        for (int c = 0; c < k; ++c) {
          const auto s = phase(tick, c);
          do_not_optimize(
              rnea<Terms::Full>(*model, (*data)[std::size_t(c)], motion->q[s], motion->qd[s], motion->qdd[s]));
        }
      };
    });
  }
  if (is_seed_shape(d)) {
    // a full simulation step per character: PD tracking of the walk with inverse-dynamics feed-forward,
    // forward dynamics (mass matrix), semi-implicit Euler, 1 ms
    using M = HumanModel<double>;
    const auto model = std::make_shared<const M>(d);
    using V = M::JointVector;
    const auto q = std::make_shared<std::vector<V>>(cast_all<V>(walk.q));
    const auto qd = std::make_shared<std::vector<V>>(cast_all<V>(walk.qd));
    const auto qdd = std::make_shared<std::vector<V>>(cast_all<V>(walk.qdd));
    works.emplace_back("humandyn sim step (double)", [=](int k) -> TickWork {
      struct Character {
        explicit Character(const M& m) : ws(m), x(m), servo(m), data(m) {}
        StepWorkspace<M> ws;
        State<M> x;
        PdServo<M> servo;
        Data<M> data;
      };
      auto chars = std::make_shared<std::vector<std::unique_ptr<Character>>>();
      for (int c = 0; c < k; ++c) {
        chars->push_back(std::make_unique<Character>(*model));
        auto& ch = *chars->back();
        set_servo_gains(*model, ch.servo, 4.0);
        ch.x.q = (*q)[phase(0, c)];
        ch.x.qd = (*qd)[phase(0, c)];
      }
      return [=](long tick) {
        for (int c = 0; c < k; ++c) {
          const auto s = phase(tick, c);
          auto& ch = *(*chars)[std::size_t(c)];
          ch.servo.q_ref = (*q)[s];
          ch.servo.qd_ref = (*qd)[s];
          const V& tau = rnea(*model, ch.data, (*q)[s], (*qd)[s], (*qdd)[s]);
          if (!step<Integrator::SemiImplicitEuler, FdMethod::MassMatrix>(*model, ch.ws, ch.x, tau, &ch.servo, 1e-3)) {
            ch.x.q = (*q)[s];  // a failed step leaves the state as it was; start again on the reference
            ch.x.qd = (*qd)[s];
          }
          do_not_optimize(ch.x.q);
        }
      };
    });
  }
#ifdef HUMANDYN_BENCH_WITH_KDL
  {
    auto q = std::make_shared<std::vector<KDL::JntArray>>(), qd = q, qdd = q;
    qd = std::make_shared<std::vector<KDL::JntArray>>();
    qdd = std::make_shared<std::vector<KDL::JntArray>>();
    for (int s = 0; s < n; ++s) {
      q->push_back(to_jnt_array(walk.q[std::size_t(s)]));
      qd->push_back(to_jnt_array(walk.qd[std::size_t(s)]));
      qdd->push_back(to_jnt_array(walk.qdd[std::size_t(s)]));
    }
    works.emplace_back("KDL TreeIdSolver_RNE", [=](int k) -> TickWork {
      auto solvers = std::make_shared<std::vector<std::unique_ptr<KdlTreeDynamics>>>();
      for (int c = 0; c < k; ++c) solvers->push_back(std::make_unique<KdlTreeDynamics>(d));
      return [=](long tick) {
        for (int c = 0; c < k; ++c) {
          const auto s = phase(tick, c);
          auto& kdl = *(*solvers)[std::size_t(c)];
          kdl.solve((*q)[s], (*qd)[s], (*qdd)[s], kdl.tau);
          do_not_optimize(kdl.tau);
        }
      };
    });
  }
#endif
  return works;
}

// The loop's motion, 1.1 s at 1 kHz: the seed body's walk; for another model, every joint swinging by 0.3 rad
// once in the 1.1 s, each at its own phase.
StateSet loop_motion(const ModelDescription<double>& d) {
  if (is_seed_shape(d)) return walking_cycle(1100);
  const int nj = int(d.joints.size());
  std::vector<Harmonic> terms;
  for (int j = 0; j < nj; ++j) terms.push_back({j, 0.0, 0.3, 1, 0.7 * j});
  return sample_harmonics("swing", nj, terms, 1.1, 1100);
}

LoopReport run_loops(const ModelDescription<double>& d, int characters, const Budget& budget) {
  LoopReport report;
  const StateSet walk = loop_motion(d);
  for (const auto& [name, factory] : loop_works(d, walk)) {
    const LoopStats at_k = run_fixed_period_loop(name, characters, factory(characters), budget.loop_seconds);
    report.runs.push_back(at_k);
    // check the estimate: the loop again at the largest K that keeps half the period free
    const int k_fit = std::max(1, std::min(largest_k_with_headroom(at_k), 20000));
    report.fits.push_back({name, k_fit});
    report.runs.push_back(run_fixed_period_loop(name, k_fit, factory(k_fit), budget.loop_seconds / 2));
  }
  return report;
}

// ---------------------------------------------------------------------------------------------------
// 2. error against run time

struct VariantResult {
  std::string name, problem, unit, scalar, engine, workload;
  double ns_per_call = 0;
  ErrorStats error;
};

std::vector<VariantResult> run_variants(const ModelDescription<double>& d, const Budget& budget) {
  std::vector<StateSet> sets{random_states(int(d.joints.size()), budget.random_states)};
  if (is_seed_shape(d)) sets.push_back(realistic_motions(budget.motion_samples));
  std::vector<Workload> workloads;
  for (const auto& s : sets) {
    workloads.push_back(inverse_dynamics_workload(d, s));
    if (is_seed_shape(d)) workloads.push_back(forward_dynamics_workload(d, s));
  }

  std::vector<VariantResult> results;
  for (const auto& v : bench_variants(d))
    for (const auto& w : workloads) {
      if (w.problem != v.problem) continue;
      VariantResult r{v.name, problem_name(v.problem), problem_unit(v.problem), v.scalar, v.engine, w.name, 0, {}};
      r.error = measure_error(v, w);
      r.ns_per_call = v.time(w, budget.variant_seconds);
      results.push_back(r);
    }
  return results;
}

// ---------------------------------------------------------------------------------------------------
// 3. integration work-precision

std::vector<WorkPrecisionPoint> run_work_precision(const ModelDescription<double>& d, const Budget& budget,
                                                   std::vector<std::pair<std::string, double>>& reference_uncertainty) {
  std::vector<WorkPrecisionPoint> points;
  if (!is_seed_shape(d)) return points;
  using HD = HumanModel<double>;
  using HL = Model<long double, SeedShape>;
  const HD model(d);
  const HL model_ld(d.cast<long double>());
  // the integrators compared: one line each
  using Runner = bool (*)(ScenarioRun<HD>&, int);
  const std::vector<std::pair<const char*, Runner>> integrators{
      {"semi-implicit Euler", [](ScenarioRun<HD>& r, int n) { return r.run<Integrator::SemiImplicitEuler>(n); }},
      {"RK4", [](ScenarioRun<HD>& r, int n) { return r.run<Integrator::RungeKutta4>(n); }},
      {"implicit PD", [](ScenarioRun<HD>& r, int n) { return r.run<Integrator::ImplicitPD>(n); }},
      {"backward Euler", [](ScenarioRun<HD>& r, int n) { return r.run<Integrator::BackwardEuler>(n); }},
  };
  for (const Scenario sc : {Scenario::TrackedWalk, Scenario::PassiveSwing}) {
    const double T = scenario_duration(sc);
    // the reference: RK4 in long double with a fine step; half as many steps says how converged it is
    const int n_ref = int(std::lround(budget.reference_steps_per_second * T));
    ScenarioRun<HL> ref(model_ld, sc), coarse(model_ld, sc);
    if (!ref.run<Integrator::RungeKutta4>(n_ref) || !coarse.run<Integrator::RungeKutta4>(n_ref / 2))
      throw std::runtime_error(std::string("the reference simulation of the ") + scenario_name(sc) + " failed");
    const Eigen::VectorXd q_ref = ref.state().q.cast<double>(), qd_ref = ref.state().qd.cast<double>();
    reference_uncertainty.emplace_back(scenario_name(sc),
                                       double((ref.state().q - coarse.state().q).cwiseAbs().maxCoeff()));
    for (const auto& [name, runner] : integrators)
      for (const double h : budget.steps_h) {
        WorkPrecisionPoint p;
        p.scenario = scenario_name(sc);
        p.integrator = name;
        p.steps = std::max(1, int(std::lround(T / h)));
        p.h = T / p.steps;
        ScenarioRun<HD> run(model, sc);
        // time whole runs, repeated up to min_run_seconds; the fastest counts
        double best = 1e300, spent = 0;
        for (int rep = 0; rep < 50 && (rep == 0 || spent < budget.min_run_seconds); ++rep) {
          const auto t0 = now_ns();
          p.ok = runner(run, p.steps);
          const double dt = double(now_ns() - t0) * 1e-9;
          best = std::min(best, dt);
          spent += dt;
          if (!p.ok) break;
        }
        p.ms_per_sim_second = 1e3 * best / T;
        p.q_error = p.ok ? (run.state().q - q_ref).cwiseAbs().maxCoeff() : INFINITY;
        p.qd_error = p.ok ? (run.state().qd - qd_ref).cwiseAbs().maxCoeff() : INFINITY;
        points.push_back(p);
      }
  }
  return points;
}

// ---------------------------------------------------------------------------------------------------
// output

std::string cpu_model() {
  std::ifstream f("/proc/cpuinfo");
  std::string line;
  while (std::getline(f, line))
    if (line.rfind("model name", 0) == 0) {
      const auto colon = line.find(':');
      if (colon != std::string::npos) return line.substr(colon + 2);
    }
  return "unknown";
}

const char* march_native() {
#ifdef HUMANDYN_MARCH_NATIVE
  return "on";
#else
  return "off";
#endif
}

void print_loops(const LoopReport& r) {
  fmt::print("\n== 1 kHz loop: per-tick latency from release to end of work (us), 1 ms period\n");
  fmt::print("{:<28} {:>6} {:>7} {:>8} {:>8} {:>8} {:>8} {:>8} {:>7} {:>7} {:>5} {:>7} {:>9}  {}\n", "work", "K",
             "ticks", "p50", "p99", "p99.9", "max", "compute", "share", "misses", "late", "overrun", "max wake",
             "scheduling");
  for (const auto& s : r.runs)
    fmt::print("{:<28} {:6} {:7} {:8.1f} {:8.1f} {:8.1f} {:8.1f} {:8.1f} {:6.1f}% {:7} {:5} {:7} {:9.1f}  {}\n", s.work,
               s.characters, s.ticks, s.p50_us, s.p99_us, s.p999_us, s.max_us, s.compute_mean_us, 100 * s.share,
               s.misses, s.misses_late, s.misses_overrun, s.max_wakeup_us, s.scheduling);
  fmt::print(
      "(misses: late = the work fitted in the period but started late, overrun = the work took longer; "
      "max wake = largest delay from a release to the start of its work, us)\n");
  for (const auto& f : r.fits)
    fmt::print("largest K with 50% headroom (p99 compute <= 0.5 ms), {}: {} characters\n", f.work, f.k_fit);
}

void print_variants(const std::vector<VariantResult>& results) {
  fmt::print("\n== error against run time (reference: full model in long double, same states)\n");
  fmt::print("{:<32} {:<9} {:>10} {:>12} {:>12} {:>12}  {}\n", "variant", "states", "ns/call", "max abs", "rms abs",
             "max rel", "unit");
  for (const auto& r : results)
    fmt::print("{:<32} {:<9} {:10.1f} {:12.3e} {:12.3e} {:12.3e}  {}\n", r.name, r.workload, r.ns_per_call,
               r.error.max_abs, r.error.rms_abs, r.error.max_rel, r.unit);
}

void print_work_precision(const std::vector<WorkPrecisionPoint>& points,
                          const std::vector<std::pair<std::string, double>>& reference_uncertainty) {
  if (points.empty()) return;
  fmt::print("\n== integration work-precision (end-state error vs a long double RK4 reference, fine step)\n");
  for (const auto& [scenario, u] : reference_uncertainty)
    fmt::print("reference {}: converged to {:.1e} rad (fine step against half as many steps)\n", scenario, u);
  fmt::print("{:<14} {:<20} {:>10} {:>7} {:>14} {:>12} {:>12}\n", "scenario", "integrator", "h (s)", "steps",
             "ms/sim-second", "q err (rad)", "qd err");
  for (const auto& p : points)
    if (p.ok)
      fmt::print("{:<14} {:<20} {:10.2e} {:7} {:14.3f} {:12.3e} {:12.3e}\n", p.scenario, p.integrator, p.h, p.steps,
                 p.ms_per_sim_second, p.q_error, p.qd_error);
    else
      fmt::print("{:<14} {:<20} {:10.2e} {:7} {:14.3f} {:>12} {:>12}\n", p.scenario, p.integrator, p.h, p.steps,
                 p.ms_per_sim_second, "diverged", "diverged");
}

// Headline ratios: the time of a reference over ours, from results on random states.
std::vector<std::pair<std::string, double>> headline_ratios(const std::vector<VariantResult>& results) {
  const auto ns = [&](const std::string& name) -> std::optional<double> {
    for (const auto& r : results)
      if (r.name == name && r.workload == "random") return r.ns_per_call;
    return std::nullopt;
  };
  std::vector<std::pair<std::string, double>> out;
  const auto add = [&](const std::string& label, const std::string& slow, const std::string& fast) {
    const auto a = ns(slow), b = ns(fast);
    if (a && b && *b > 0) out.emplace_back(label, *a / *b);
  };
  add("KDL TreeIdSolver_RNE / ID full double", "ID full double KDL tree", "ID full double");
  add("ID full / ID no-Coriolis (double)", "ID full double", "ID no-Coriolis double");
  add("ID full / ID gravity (double)", "ID full double", "ID gravity double");
  add("ID dynamic shape / static shape (double)", "ID full double dynamic-shape", "ID full double");
  add("FD articulated / FD mass matrix (double)", "FD articulated double", "FD mass matrix double");
  add("FD mass matrix / ID full (double)", "FD mass matrix double", "ID full double");
  return out;
}

// The JSON document (nlohmann::ordered_json: keys in the order written; a non-finite number, e.g. the error
// of a diverged run, is written as null).
nlohmann::ordered_json loop_json(const LoopStats& s) {
  return {{"work", s.work},
          {"characters", s.characters},
          {"seconds", s.seconds},
          {"period_us", s.period_us},
          {"ticks", s.ticks},
          {"misses", s.misses},
          {"misses_late", s.misses_late},
          {"misses_overrun", s.misses_overrun},
          {"max_wakeup_us", s.max_wakeup_us},
          {"skipped", s.skipped},
          {"p50_us", s.p50_us},
          {"p99_us", s.p99_us},
          {"p999_us", s.p999_us},
          {"max_us", s.max_us},
          {"compute_mean_us", s.compute_mean_us},
          {"compute_p99_us", s.compute_p99_us},
          {"share", s.share},
          {"scheduling", s.scheduling}};
}

void print_crowd(const std::optional<CrowdReport>& crowd) {
  if (!crowd) {
    fmt::print("\n== crowds: not run (the crowd's kernels are compiled for the seed body's shape)\n");
    return;
  }
  const CrowdReport& r = *crowd;
  fmt::print("\n== crowds: characters served at 1 kHz with half the period free ({} core{})\n", r.cores,
             r.cores == 1 ? "" : "s");
  fmt::print("{:<14} {:<7} {:<12} {:>7} {:>6} {:>10} {:>11} {:>8} {:>10} {:>8}\n", "work", "scalar", "lanes", "threads",
             "crowd", "ns/char", "characters", "speedup", "per-core", "refused");
  for (const auto& x : r.rows)
    fmt::print("{:<14} {:<7} {:<12} {:>7} {:>6} {:>10.1f} {:>11} {:>7.2f}x {:>10.2f} {:>8}\n", x.work, x.scalar,
               x.lanes, x.threads, x.crowd, x.ns_per_character, x.characters, x.speedup, x.per_core_share, x.refused);
  const LoopStats& s = r.loop;
  fmt::print(
      "1 kHz loop, {} x {}: p50 {:.0f} us, p99 {:.0f} us, max {:.0f} us, compute mean {:.0f} us ({:.1f} % of the "
      "period), misses {} ({} late / {} overrun) of {} ticks; {}\n",
      s.work, s.characters, s.p50_us, s.p99_us, s.max_us, s.compute_mean_us, 100 * s.share, s.misses, s.misses_late,
      s.misses_overrun, s.ticks, s.scheduling);
}

// The bench's output files, written into as they are made and committed together at the end.
using Outputs = std::vector<std::unique_ptr<AtomicFile>>;

void add_output(Outputs& outputs, const std::string& path, std::string_view text) {
  outputs.push_back(std::make_unique<AtomicFile>(path));
  outputs.back()->write(text);
}

void write_json(Outputs& outputs, const std::string& path, const ModelDescription<double>& d, const LoopReport& loops,
                const std::vector<VariantResult>& variants, const std::vector<WorkPrecisionPoint>& wp,
                const std::optional<CrowdReport>& crowd, const Budget& budget) {
  using Json = nlohmann::ordered_json;
  Json crowd_rows = Json::array();
  for (const auto& x : crowd ? crowd->rows : std::vector<CrowdRow>{})
    crowd_rows.push_back({{"work", x.work},
                          {"scalar", x.scalar},
                          {"lanes", x.lanes},
                          {"threads", x.threads},
                          {"crowd", x.crowd},
                          {"ns_per_character", x.ns_per_character},
                          {"characters", x.characters},
                          {"speedup", x.speedup},
                          {"per_core_share", x.per_core_share},
                          {"refused", x.refused}});
  Json runs = Json::array(), fits = Json::array(), vs = Json::array(), ratios = Json::array(), wps = Json::array();
  for (const auto& p : wp)
    wps.push_back({{"scenario", p.scenario},
                   {"integrator", p.integrator},
                   {"h", p.h},
                   {"steps", p.steps},
                   {"ms_per_sim_second", p.ms_per_sim_second},
                   {"q_error", p.q_error},
                   {"qd_error", p.qd_error},
                   {"ok", p.ok}});
  for (const auto& s : loops.runs) runs.push_back(loop_json(s));
  for (const auto& f : loops.fits) fits.push_back({{"work", f.work}, {"characters", f.k_fit}});
  for (const auto& r : variants)
    vs.push_back({{"name", r.name},
                  {"problem", r.problem},
                  {"unit", r.unit},
                  {"scalar", r.scalar},
                  {"engine", r.engine},
                  {"states", r.workload},
                  {"state_count", r.error.states},
                  {"ns_per_call", r.ns_per_call},
                  {"max_abs_error", r.error.max_abs},
                  {"rms_abs_error", r.error.rms_abs},
                  {"max_rel_error", r.error.max_rel}});
  for (const auto& [label, ratio] : headline_ratios(variants)) ratios.push_back({{"ratio", label}, {"value", ratio}});
  const Json doc{
      {"machine",
       {{"cpu", cpu_model()},
        {"compiler", __VERSION__},
        {"flags", HUMANDYN_CXX_FLAGS},
        {"march_native", march_native()}}},
      {"model", d.name},
      {"joints", d.joints.size()},
      {"loop", {{"runs", runs}, {"largest_k_with_half_period_free", fits}}},
      {"variants", vs},
      {"ratios", ratios},
      {"work_precision", wps},
      {"crowd", crowd ? Json{{"cores", crowd->cores}, {"rows", crowd_rows}, {"loop", loop_json(crowd->loop)}} : Json()},
      {"variant_seconds", budget.variant_seconds}};
  add_output(outputs, path, doc.dump(2) + '\n');
}

// A CSV cell: quoted when it holds a comma or a quote.
std::string csv_cell(const std::string& s) {
  if (s.find_first_of(",\"\n") == std::string::npos) return s;
  std::string out = "\"";
  for (char c : s) out += (c == '"') ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// A number cell; a non-finite one (the error of a diverged run) is empty, as it is null in the JSON.
std::string csv_number(double v) { return std::isfinite(v) ? fmt::format("{:.9g}", v) : std::string(); }

// One CSV file of the bench: a header line and a line per row (cells already written).
void write_bench_csv(Outputs& outputs, const std::string& path, const std::string& header,
                     const std::vector<std::string>& lines) {
  std::string text = header + '\n';
  for (const auto& line : lines) text += line + '\n';
  add_output(outputs, path, text);
}

// The files of --csv DIR.
constexpr const char* loop_csv = "bench_loop.csv";
constexpr const char* variants_csv = "bench_variants.csv";
constexpr const char* work_precision_csv = "bench_work_precision.csv";

void write_csv(Outputs& outputs, const std::string& dir, const LoopReport& loops,
               const std::vector<VariantResult>& variants, const std::vector<WorkPrecisionPoint>& wp) {
  // (the header alone for a model of another shape, which has no points: no earlier run's file left beside
  // this run's)
  std::vector<std::string> lines;
  for (const auto& p : wp)
    lines.push_back(fmt::format("{},{},{},{},{},{},{},{}", csv_cell(p.scenario), csv_cell(p.integrator),
                                csv_number(p.h), p.steps, csv_number(p.ms_per_sim_second), csv_number(p.q_error),
                                csv_number(p.qd_error), p.ok ? 1 : 0));
  write_bench_csv(outputs, dir + "/" + work_precision_csv,
                  "scenario,integrator,h,steps,ms_per_sim_second,q_error,qd_error,ok", lines);
  lines.clear();
  for (const auto& s : loops.runs)
    lines.push_back(fmt::format("{},{},{},{},{},{},{},{},{},{},{},{},{},{},{}", csv_cell(s.work), s.characters, s.ticks,
                                s.misses, s.misses_late, s.misses_overrun, csv_number(s.max_wakeup_us),
                                csv_number(s.p50_us), csv_number(s.p99_us), csv_number(s.p999_us), csv_number(s.max_us),
                                csv_number(s.compute_mean_us), csv_number(s.compute_p99_us), csv_number(s.share),
                                s.scheduling));
  write_bench_csv(outputs, dir + "/" + loop_csv,
                  "work,characters,ticks,misses,misses_late,misses_overrun,max_wakeup_us,p50_us,p99_us,p999_us,max_us,"
                  "compute_mean_us,compute_p99_us,share,scheduling",
                  lines);
  lines.clear();
  for (const auto& r : variants)
    lines.push_back(fmt::format("{},{},{},{},{},{},{},{},{},{}", csv_cell(r.name), csv_cell(r.problem),
                                csv_cell(r.unit), r.scalar, r.engine, r.workload, csv_number(r.ns_per_call),
                                csv_number(r.error.max_abs), csv_number(r.error.rms_abs), csv_number(r.error.max_rel)));
  write_bench_csv(outputs, dir + "/" + variants_csv,
                  "variant,problem,unit,scalar,engine,states,ns_per_call,max_abs_error,rms_abs_error,max_rel_error",
                  lines);
}

struct BenchOptions {
  ModelOptions model;
  std::optional<double> seconds;  // default: the budget's
  long characters = 100;
  bool quick = false;
  std::string json, csv;  // "" for none
};

int run_bench(const BenchOptions& o) {
  const ModelDescription<double> d = load_model(o.model);
  Budget budget;
  const bool quick = o.quick;
  if (quick) {
    budget.loop_seconds = 0.2;
    budget.variant_seconds = 0.005;
    budget.random_states = 200;
    budget.motion_samples = 100;
    budget.reference_steps_per_second = 2000;
    budget.steps_h = {1e-3, 1e-2, 1.0 / 30};
    budget.min_run_seconds = 0;
    budget.crowd_seconds = 0.005;
  }
  budget.loop_seconds = o.seconds.value_or(budget.loop_seconds);
  const long characters = o.characters;
  if (budget.loop_seconds <= 0 || budget.loop_seconds > 3600) throw UsageError("--seconds must be in (0, 3600]");
  if (characters < 1 || characters > 100000) throw UsageError("--characters must be in [1, 100000]");
  // forward dynamics of a singular mass matrix is NaN: say which joint before any table
  check_mass_matrix_at_home(AnyModel<double>(d));
  // the outputs' places, before the run: a file for --json, a folder for --csv (made here)
  namespace fs = std::filesystem;
  if (!o.json.empty() && names_standard_output(o.json))  // (the tables go there)
    throw UsageError("--json " + text::shown(o.json) + ": standard output holds the tables; give the JSON a file");
  const fs::path json_name = fs::path(o.json).filename();  // (d/, d/. and d/.. name folders, made or not)
  if (std::error_code ec;
      !o.json.empty() && (fs::is_directory(o.json, ec) || json_name.empty() || json_name == "." || json_name == ".."))
    throw UsageError("--json " + text::shown(o.json) + " is a folder: the results go to a file");
  if (o.csv == "-") throw UsageError("--csv -: the CSV files go to a folder, not to standard output");
  // (the folder is made after the run, with the files: a run that fails or is stopped leaves none)
  if (const std::string fault = o.csv.empty() ? "" : output_folder_fault(o.csv); !fault.empty())
    throw UsageError("--csv " + text::shown(o.csv) + " is not a folder that can be made: " + fault);
  // the JSON's folder exists, or is --csv's or one of its parents, made with it
  const auto made_with_csv = [&](const fs::path& folder) {
    // (d/sub/.. is no folder while d/sub is not one, whatever d is made)
    if (std::find(folder.begin(), folder.end(), fs::path("..")) != folder.end()) return false;
    bool failed = false;
    const auto normal = [&](const fs::path& p) {  // (d/. and d/ as d)
      std::error_code absolute_ec, canonical_ec;
      const fs::path a = fs::absolute(p, absolute_ec);
      const fs::path n = fs::weakly_canonical(a, canonical_ec).lexically_normal();
      failed = failed || absolute_ec || canonical_ec;
      return n.has_filename() ? n : n.parent_path();
    };
    const fs::path f = normal(folder), csv = normal(o.csv);
    return !o.csv.empty() && !failed && std::mismatch(f.begin(), f.end(), csv.begin(), csv.end()).first == f.end();
  };
  if (std::error_code ec; !o.json.empty()) {
    const fs::path folder = fs::path(o.json).parent_path();
    if (!folder.empty() && !fs::is_directory(folder, ec) && !made_with_csv(folder))
      throw UsageError("--json " + text::shown(o.json) + ": no folder " + text::shown(folder.string()));
  }
  if (!o.csv.empty()) {
    std::vector<std::string> outputs;
    for (const char* name : {loop_csv, variants_csv, work_precision_csv})
      outputs.push_back((fs::path(o.csv) / name).string());
    if (!o.json.empty()) outputs.push_back(o.json);
    refuse_outputs(outputs);
  }

  fmt::print("humandyn bench: model '{}', {} joints\n", text::shown(d.name), d.joints.size());
  fmt::print("cpu: {}; compiler: {}; flags: {}; -march=native: {}\n", cpu_model(), __VERSION__, HUMANDYN_CXX_FLAGS,
             march_native());
  if (quick) fmt::print("--quick: a smoke run, the timings below mean nothing\n");

  const LoopReport loops = run_loops(d, int(characters), budget);
  print_loops(loops);
  const std::vector<VariantResult> variants = run_variants(d, budget);
  print_variants(variants);
  std::vector<std::pair<std::string, double>> reference_uncertainty;
  const std::vector<WorkPrecisionPoint> wp = run_work_precision(d, budget, reference_uncertainty);
  print_work_precision(wp, reference_uncertainty);
  // (none for a model of another shape, whose peers are not built)
  if (const auto headline = headline_ratios(variants); !headline.empty()) {
    fmt::print("\n== headline ratios (random states, same binary, same flags)\n");
    for (const auto& [label, ratio] : headline) fmt::print("{:<44} {:6.2f} x\n", label, ratio);
  }
  std::optional<CrowdReport> crowd;  // (the seed's shape only)
  if (is_seed_shape(d)) crowd = run_crowd(d, budget.crowd_seconds, budget.loop_seconds / 2);
  print_crowd(crowd);

  // every output or none, in the --csv folder made now (the JSON's too, when it is inside), and the
  // folders made removed again if a write fails or a stop (Ctrl-C, a kill) comes before the commit
  const HeldStops stops;
  MadeFolders made;
  if (const std::string fault = o.csv.empty() ? "" : made.make(o.csv); !fault.empty())
    throw InputError(text::shown(o.csv) + ": cannot create the folder: " + fault);
  Outputs outputs;
  if (!o.json.empty()) write_json(outputs, o.json, d, loops, variants, wp, crowd, budget);
  if (!o.csv.empty()) write_csv(outputs, o.csv, loops, variants, wp);
  std::vector<AtomicFile*> files;
  for (const auto& f : outputs) files.push_back(f.get());
  if (!commit_together(files, &stops)) return 1;  // stopped: the outputs and folders go, then the stop ends the process
  made.keep();
  return 0;
}

}  // namespace

Command add_bench(CLI::App& humandyn) {
  const auto o = std::make_shared<BenchOptions>();
  CLI::App* c = humandyn.add_subcommand(
      "bench",
      "the main job: 1 kHz loop, error against run time, charts\n\n"
      "The 1 kHz loop (K characters per 1 ms tick, N seconds each run; default K = 100, N = 5), the\n"
      "error-against-run-time table of every variant and the integrators' work-precision, on stdout;\n"
      "--json and --csv also write them as JSON and as CSV files (bench_*.csv: the loop, the variants\n"
      "and the work-precision; the crowd and the ratios are in the JSON alone), each all or nothing\n"
      "(non-finite numbers, e.g. the error of a diverged run, are null in the JSON, empty cells in the\n"
      "CSV). The charts are drawn from the JSON by tools/plot_bench.py. A model whose mass matrix is singular at the "
      "home\n"
      "pose (the built-in paper model's is) is refused before any run, naming the joint, as fd does. A\n"
      "model of another shape than the seed body's (a URDF) runs the loop on every joint swinging, in the\n"
      "runtime shape beside KDL, and the variants of the runtime shape; the seed's compiled shape, its\n"
      "scenes, the work-precision runs and the crowds are left out (the crowd is null in the JSON).");
  add_model_options(*c, o->model);
  CLI::Option* seconds =
      add_number(*c, "--seconds", o->seconds, "each real-time loop's duration (s, default 5)")->option_text("N");
  add_whole_number(*c, "--characters", o->characters, "characters per 1 ms tick (default 100)");
  c->add_flag("--quick", o->quick, "a few seconds in all (a smoke run; its timings mean nothing)")->excludes(seconds);
  c->add_option("--json", o->json, "the results as JSON")->option_text("FILE");
  c->add_option("--csv", o->csv, "the results as CSV files")->option_text("DIR");
  return {c, [o] { return run_bench(*o); }};
}

}  // namespace humandyn::cli
