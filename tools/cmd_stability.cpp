// humandyn stability: the stiff-and-extreme suite (tools/stability/stability_suite.hpp) as a table
// or as JSON, one row per case, method and time step. The test suites assert the same rows.
#include "cli/commands.hpp"
#include "cli/json.hpp"
#include "stability_suite.hpp"

#include <cmath>
#include <cstdio>
#include <memory>
#include <string>

#include <fmt/format.h>

namespace humandyn::cli {

namespace {

const char* expect_name(stability::Expect e) {
  return e == stability::Expect::Stable ? "stable" : e == stability::Expect::Unstable ? "unstable" : "-";
}

// A number with three significant digits (run times: three decimals), "-" when there is none.
std::string cell(double v, bool decimals = false) {
  if (std::isnan(v)) return "-";
  return decimals ? fmt::format("{:.3f}", v) : fmt::format("{:.3g}", v);
}

// 1/N for time steps that are one, else seconds
std::string step_cell(double h) {
  if (std::isnan(h)) return "-";
  const double n = 1 / h;
  if (std::abs(n - std::round(n)) < 1e-9 * n) return "1/" + std::to_string(long(std::lround(n)));
  return cell(h);
}

// One row as JSON (a non-finite number, e.g. the error of a run that diverged, is written as null).
json::Json to_json(const stability::Row& r) {
  return {{"group", r.group},
          {"case", r.name},
          {"method", r.method},
          {"scalar", r.scalar},
          {"dt", r.dt},
          {"stable", r.stable},
          {"expect", expect_name(r.expect)},
          {"status", r.status},
          {"t_end", r.t_end},
          {"error_measure", r.error_name},
          {"error", r.error},
          {"energy_drift", r.energy_drift},
          {"energy_rise", r.energy_rise},
          {"dissipation_w", r.dissipation},
          {"run_time_s", r.run_time},
          {"note", r.note}};
}

struct StabilityOptions {
  bool json = false, quick = false;
};

int run_stability(const StabilityOptions& o) {
  const bool as_json = o.json;
  stability::Options options;
  options.full = !o.quick;

  json::Json rows = json::Json::array();
  int unexpected = 0;
  // one row's columns, wide enough for every value (the method up to backward-euler)
  constexpr std::string_view row = "{:<13} {:<34} {:<14} {:<6} {:<7} {:<6} {:<8} {:<9} {:<9} {:<8} {}\n";
  if (!as_json)
    fmt::print(row, "group", "case", "method", "scalar", "dt", "stable", "expect", "error", "drift", "time(s)",
               "status / note");
  stability::run_suite(options, [&](const stability::Row& r) {
    const bool surprise =
        (r.expect == stability::Expect::Stable && !r.stable) || (r.expect == stability::Expect::Unstable && r.stable);
    unexpected += surprise ? 1 : 0;
    if (as_json) {
      rows.push_back(to_json(r));
      return;
    }
    std::string tail = r.status;
    if (!r.note.empty()) tail += "; " + r.note;
    if (surprise) tail += "  <-- not as expected";
    fmt::print(row, r.group, r.name, r.method, r.scalar, step_cell(r.dt), r.stable ? "yes" : "NO",
               expect_name(r.expect), cell(r.error), cell(r.energy_drift), cell(r.run_time, true), tail);
    std::fflush(stdout);
  });
  if (as_json) {
    std::fputs(json::write(rows).c_str(), stdout);
  } else {
    fmt::print(
        "\nerror: the case's error measure (stiff servo: max |q - q_ref| over the last third, rad; light/heavy\n"
        "and fast round trip: |FD(ID(qdd)) - qdd| / max(1, |qdd|); swing and flail: max |qd| reached, rad/s;\n"
        "convergence: max over 0.5 s of |q - q_ref| against RK4 at h = 1/8000). drift: max |E(t) - E(0)| over\n"
        "the run divided by the case's energy scale (swing: E(0) - V(home); flail: m g z_com; fast: E_kin(0)).\n"
        "swing and flail notes: rise = max (E(t) - E(0)) over the same scale, dissipation = (E(0) - E(end)) / t_end\n"
        "(W); a backward-euler row is stable only with no failed step and rise <= 1e-6.\n");
    fmt::print("{} row(s) not as expected\n", unexpected);
  }
  return unexpected == 0 ? 0 : 1;
}

}  // namespace

Command add_stability(CLI::App& humandyn) {
  const auto o = std::make_shared<StabilityOptions>();
  CLI::App* c = humandyn.add_subcommand(
      "stability",
      "the stiff-and-extreme suite: stiff servos, light and heavy bodies, fast motion, long swings\n\n"
      "Runs the stiff-and-extreme suite on the default model and prints one row per case, method and time\n"
      "step: stiff PD servos (kp 1e2..1e6, h 1/1000..1/30), light and heavy bodies, fast motion (float and\n"
      "double), the 60 s passive swing, the falling upright body (backward Euler: both at h 1/1000..1/30),\n"
      "convergence order, and bad input. 'stable'\n"
      "means every step was accepted (and a servo converged), and for a bad state that its step\n"
      "was refused as it should be, the state untouched; 'expect' is what theory predicts\n"
      "(stable / unstable / '-' for no prediction). A failed step is a reported status, never a NaN.");
  c->add_flag("--json", o->json, "the rows as a JSON array");
  c->add_flag("--quick", o->quick, "fewer time steps for the passive swing (the ones the tests run)");
  return {c, [o] { return run_stability(*o); }};
}

}  // namespace humandyn::cli
