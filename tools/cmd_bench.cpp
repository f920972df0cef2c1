// humandyn bench: the project's main job. Three measurements on one model:
//   1. the 1 kHz loop: K characters per 1 ms tick (inverse dynamics; KDL's tree solver for the same K),
//      latency percentiles, deadline misses, share of the period used, the largest K with 50 % headroom;
//   2. error against run time: every variant of the table in bench_variants(), timed and compared with
//      a long double reference of the full model, on random states and on realistic motions;
//   3. the tables on stdout, and on request JSON, CSV and SVG charts.
#include "bench/motions.hpp"
#include "bench/realtime_loop.hpp"
#include "bench/report.hpp"
#include "bench/svg_chart.hpp"
#include "bench/variants.hpp"
#include "cli/commands.hpp"
#include "cli/model_source.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"
#include "humandyn/model.hpp"

#ifdef HUMANDYN_BENCH_WITH_KDL
#include "bench/kdl_variants.hpp"
#endif

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#ifndef HUMANDYN_CXX_FLAGS
#define HUMANDYN_CXX_FLAGS "unknown"
#endif

namespace humandyn::cli {

namespace {

using namespace humandyn::bench;

// How long each measurement runs.
struct Budget {
  double loop_seconds = 5;      // each real-time loop
  double variant_seconds = 0.3; // timing of one variant on one workload
  int random_states = 1000;
  int motion_samples = 500;     // per motion
};

// ---------------------------------------------------------------------------------------------------
// The table of variants: one line each.

std::vector<Variant> bench_variants(const ModelDescription<double>& d) {
  std::vector<Variant> v;
  // the seed shape, known at compile time
  const auto sd = std::make_shared<const HumanModel<double>>(d);
  const auto sf = std::make_shared<const HumanModel<float>>(d.cast<float>());
  // the same model as a runtime shape (what an imported model runs)
  const auto dd = std::make_shared<const AnyModel<double>>(d);
  const auto df = std::make_shared<const AnyModel<float>>(d.cast<float>());

  v.push_back(rnea_variant<Terms::Full>("ID full double", "double", sd));
  v.push_back(rnea_variant<Terms::NoCoriolis>("ID no-Coriolis double", "double", sd));
  v.push_back(rnea_variant<Terms::GravityOnly>("ID gravity double", "double", sd));
  v.push_back(rnea_variant<Terms::Full>("ID full float", "float", sf));
  v.push_back(rnea_variant<Terms::NoCoriolis>("ID no-Coriolis float", "float", sf));
  v.push_back(rnea_variant<Terms::GravityOnly>("ID gravity float", "float", sf));
  v.push_back(rnea_variant<Terms::Full>("ID full double dynamic-shape", "double", dd));
  v.push_back(rnea_variant<Terms::Full>("ID full float dynamic-shape", "float", df));
#ifdef HUMANDYN_BENCH_WITH_KDL
  v.push_back(kdl_tree_id_variant(d));
#endif
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

// The work of one tick for K characters, each walking at its own phase of the 1.1 s cycle sampled at 1 kHz.
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
      auto data = std::make_shared<std::vector<Data<HumanModel<double>>>>(std::size_t(k), Data<HumanModel<double>>(*model));
      return [=](long tick) {
        for (int c = 0; c < k; ++c) {
          const auto s = phase(tick, c);
          do_not_optimize(rnea<Terms::Full>(*model, (*data)[std::size_t(c)], (*q)[s], (*qd)[s], (*qdd)[s]));
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

LoopReport run_loops(const ModelDescription<double>& d, int characters, const Budget& budget) {
  LoopReport report;
  const StateSet walk = walking_cycle(1100);  // 1.1 s at 1 kHz
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
  std::vector<Workload> workloads;
  workloads.push_back(inverse_dynamics_workload(d, random_states(int(d.joints.size()), budget.random_states)));
  if (is_seed_shape(d)) workloads.push_back(inverse_dynamics_workload(d, realistic_motions(budget.motion_samples)));

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
  std::printf("\n== 1 kHz loop: per-tick latency from release to end of work (us), 1 ms period\n");
  std::printf("%-28s %6s %7s %8s %8s %8s %8s %8s %7s %7s  %s\n", "work", "K", "ticks", "p50", "p99", "p99.9", "max",
              "compute", "share", "misses", "scheduling");
  for (const auto& s : r.runs)
    std::printf("%-28s %6d %7ld %8.1f %8.1f %8.1f %8.1f %8.1f %6.1f%% %7ld  %s\n", s.work.c_str(), s.characters, s.ticks,
                s.p50_us, s.p99_us, s.p999_us, s.max_us, s.compute_mean_us, 100 * s.share, s.misses,
                s.scheduling.c_str());
  for (const auto& f : r.fits)
    std::printf("largest K with 50%% headroom (p99 compute <= 0.5 ms), %s: %d characters\n", f.work.c_str(), f.k_fit);
}

void print_variants(const std::vector<VariantResult>& results) {
  std::printf("\n== error against run time (reference: full model in long double, same states)\n");
  std::printf("%-32s %-9s %10s %12s %12s %12s  %s\n", "variant", "states", "ns/call", "max abs", "rms abs", "max rel",
              "unit");
  for (const auto& r : results)
    std::printf("%-32s %-9s %10.1f %12.3e %12.3e %12.3e  %s\n", r.name.c_str(), r.workload.c_str(), r.ns_per_call,
                r.error.max_abs, r.error.rms_abs, r.error.max_rel, r.unit.c_str());
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
  return out;
}

std::string loop_json(const LoopStats& s) {
  return JsonObject()
      .str("work", s.work)
      .num("characters", s.characters)
      .num("seconds", s.seconds)
      .num("period_us", s.period_us)
      .num("ticks", double(s.ticks))
      .num("misses", double(s.misses))
      .num("skipped", double(s.skipped))
      .num("p50_us", s.p50_us)
      .num("p99_us", s.p99_us)
      .num("p999_us", s.p999_us)
      .num("max_us", s.max_us)
      .num("compute_mean_us", s.compute_mean_us)
      .num("compute_p99_us", s.compute_p99_us)
      .num("share", s.share)
      .str("scheduling", s.scheduling)
      .render("    ");
}

void write_json(const std::string& path, const ModelDescription<double>& d, const LoopReport& loops,
                const std::vector<VariantResult>& variants, const Budget& budget) {
  std::vector<std::string> runs, fits, vs, ratios;
  for (const auto& s : loops.runs) runs.push_back(loop_json(s));
  for (const auto& f : loops.fits) fits.push_back(JsonObject().str("work", f.work).num("characters", f.k_fit).render("    "));
  for (const auto& r : variants)
    vs.push_back(JsonObject()
                     .str("name", r.name)
                     .str("problem", r.problem)
                     .str("unit", r.unit)
                     .str("scalar", r.scalar)
                     .str("engine", r.engine)
                     .str("states", r.workload)
                     .num("state_count", r.error.states)
                     .num("ns_per_call", r.ns_per_call)
                     .num("max_abs_error", r.error.max_abs)
                     .num("rms_abs_error", r.error.rms_abs)
                     .num("max_rel_error", r.error.max_rel)
                     .render("    "));
  for (const auto& [label, ratio] : headline_ratios(variants))
    ratios.push_back(JsonObject().str("ratio", label).num("value", ratio).render("    "));
  const std::string doc = JsonObject()
                              .raw("machine", JsonObject()
                                                  .str("cpu", cpu_model())
                                                  .str("compiler", __VERSION__)
                                                  .str("flags", HUMANDYN_CXX_FLAGS)
                                                  .str("march_native", march_native())
                                                  .render("  "))
                              .str("model", d.name)
                              .num("joints", double(d.joints.size()))
                              .raw("loop", JsonObject()
                                               .raw("runs", json_array(runs, "  "))
                                               .raw("largest_k_with_half_period_free", json_array(fits, "  "))
                                               .render("  "))
                              .raw("variants", json_array(vs, "  "))
                              .raw("ratios", json_array(ratios, "  "))
                              .num("variant_seconds", budget.variant_seconds)
                              .render();
  std::ofstream f(path);
  f << doc << '\n';
  if (!f) throw InputError("cannot write " + path);
}

void write_csv(const std::string& dir, const LoopReport& loops, const std::vector<VariantResult>& variants) {
  std::filesystem::create_directories(dir);
  {
    std::ofstream f(dir + "/bench_loop.csv");
    f << "work,characters,ticks,misses,p50_us,p99_us,p999_us,max_us,compute_mean_us,compute_p99_us,share,scheduling\n";
    for (const auto& s : loops.runs)
      f << csv_cell(s.work) << ',' << s.characters << ',' << s.ticks << ',' << s.misses << ',' << csv_number(s.p50_us) << ','
        << csv_number(s.p99_us) << ',' << csv_number(s.p999_us) << ',' << csv_number(s.max_us) << ','
        << csv_number(s.compute_mean_us) << ',' << csv_number(s.compute_p99_us) << ',' << csv_number(s.share) << ','
        << s.scheduling << '\n';
    if (!f) throw InputError("cannot write " + dir + "/bench_loop.csv");
  }
  {
    std::ofstream f(dir + "/bench_variants.csv");
    f << "variant,problem,unit,scalar,engine,states,ns_per_call,max_abs_error,rms_abs_error,max_rel_error\n";
    for (const auto& r : variants)
      f << csv_cell(r.name) << ',' << csv_cell(r.problem) << ',' << csv_cell(r.unit) << ',' << r.scalar << ',' << r.engine
        << ',' << r.workload << ',' << csv_number(r.ns_per_call) << ',' << csv_number(r.error.max_abs) << ','
        << csv_number(r.error.rms_abs) << ',' << csv_number(r.error.max_rel) << '\n';
    if (!f) throw InputError("cannot write " + dir + "/bench_variants.csv");
  }
}

// The error-against-run-time chart: one point per variant, per state set; the Pareto front of each set.
void write_plots(const std::string& dir, const std::string& model_name, const std::vector<VariantResult>& variants) {
  std::filesystem::create_directories(dir);
  Chart c;
  c.title = "Error against run time (" + model_name.substr(0, model_name.find(' ')) + " model)";
  c.x_label = "time per call (ns)";
  c.y_label = "max relative error vs long double full model";
  const std::pair<const char*, const char*> sets[] = {{"motions", "#d62728"}, {"random", "#1f77b4"}};
  for (const auto& [set, color] : sets) {
    ChartSeries s;
    s.name = std::string(set == std::string("motions") ? "realistic motions" : "random states");
    s.color = color;
    s.pareto = true;
    s.hollow = set == std::string("random");
    for (const auto& r : variants)
      if (r.workload == set) s.points.push_back({r.ns_per_call, r.error.max_rel, s.hollow ? "" : r.name});
    if (!s.points.empty()) c.series.push_back(s);
  }
  write_svg(c, dir + "/error_vs_time.svg");
}

void usage() {
  std::printf(
      "usage: humandyn bench [--model %s] [--seconds N] [--characters K] [--quick]\n"
      "                      [--json FILE] [--csv DIR] [--plot DIR]\n\n"
      "  The 1 kHz loop (K characters per 1 ms tick, N seconds each run; default K = 100, N = 5), the\n"
      "  error-against-run-time table of every variant, on stdout; --json, --csv and --plot also write\n"
      "  them as JSON, CSV files and SVG charts. --quick: a few seconds in all (a smoke run; its timings\n"
      "  mean nothing).\n",
      builtin_models);
}

}  // namespace

int run_bench(Args& args) {
  if (args.flag("--help")) {
    usage();
    return 0;
  }
  const ModelDescription<double> d = load_model(args);
  Budget budget;
  const bool quick = args.flag("--quick");
  if (quick) budget = Budget{0.2, 0.005, 200, 100};
  budget.loop_seconds = args.number("--seconds", budget.loop_seconds);
  const long characters = args.integer("--characters", 100);
  const auto json = args.get("--json");
  const auto csv = args.get("--csv");
  const auto plot = args.get("--plot");
  args.finish();
  if (budget.loop_seconds <= 0 || budget.loop_seconds > 3600) throw UsageError("--seconds must be in (0, 3600]");
  if (characters < 1 || characters > 100000) throw UsageError("--characters must be in [1, 100000]");

  std::printf("humandyn bench: model '%s', %zu joints\n", d.name.c_str(), d.joints.size());
  std::printf("cpu: %s; compiler: %s; flags: %s; -march=native: %s\n", cpu_model().c_str(), __VERSION__,
              HUMANDYN_CXX_FLAGS, march_native());
  if (quick) std::printf("--quick: a smoke run, the timings below mean nothing\n");

  const LoopReport loops = run_loops(d, int(characters), budget);
  print_loops(loops);
  const std::vector<VariantResult> variants = run_variants(d, budget);
  print_variants(variants);
  std::printf("\n== headline ratios (random states, same binary, same flags)\n");
  for (const auto& [label, ratio] : headline_ratios(variants)) std::printf("%-44s %6.2f x\n", label.c_str(), ratio);

  if (json) write_json(*json, d, loops, variants, budget);
  if (csv) write_csv(*csv, loops, variants);
  if (plot) write_plots(*plot, d.name, variants);
  return 0;
}

}  // namespace humandyn::cli
