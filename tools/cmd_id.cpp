// humandyn id: inverse dynamics of every state in a CSV file, one row of joint torques per state.
#include "cli/commands.hpp"
#include "cli/csv.hpp"
#include "cli/joint_table.hpp"
#include "cli/model_source.hpp"
#include "cli/scene_option.hpp"
#include "cli/wrench_option.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/data.hpp"
#include "humandyn/model.hpp"

#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace humandyn::cli {

namespace {

void print_usage() {
  std::printf(
      "usage: humandyn id [--model %s|FILE.json] [--terms full|no-coriolis|gravity | --scene NAME [--lock J=A,...]]\n"
      "                   [--wrench LINK:FX,FY,FZ[@PX,PY,PZ] ...] --in STATES.csv [--out TORQUES.csv]\n\n"
      "Inverse dynamics (recursive Newton-Euler) of every row of STATES.csv: the joint torques that hold or\n"
      "move the body through each state under gravity.\n\n"
      "%s"
      "  --terms T     full: every term (default); no-coriolis: without the velocity products, as the seed\n"
      "                paper does; gravity: the static torques only\n"
      "  --scene NAME  a named scene of the seed body instead of --terms (its terms, its locked joints held at\n"
      "                the first row's angles, only its output torques written):\n%s"
      "  --lock J=A,..  with --scene: hold these locked joints at these angles (rad) instead, e.g.\n"
      "                --lock r_knee_pitch=-1.57,l_knee_pitch=-1.57\n"
      "%s"
      "                The torques then also hold the wrenches (a load in the hand raises the arm's). Not\n"
      "                with --scene\n"
      "  --in FILE     the states, '-' for standard input. Header: q_<joint> (rad) for every joint, and\n"
      "                qd_<joint> (rad/s) and qdd_<joint> (rad/s^2) for every joint where the terms use them\n"
      "                (full: both; no-coriolis: qdd; gravity: neither); an optional time column t is copied\n"
      "  --out FILE    the torques, tau_<joint> (N m), one row per input row (default: standard output);\n"
      "                written only when every row is valid\n",
      builtin_models, model_options_help().c_str(), scene_help().c_str(), wrench_help);
}

enum class TermsChoice { Full, NoCoriolis, Gravity };

TermsChoice parse_terms(const std::string& s) {
  if (s == "full") return TermsChoice::Full;
  if (s == "no-coriolis") return TermsChoice::NoCoriolis;
  if (s == "gravity") return TermsChoice::Gravity;
  throw UsageError("unknown --terms '" + s + "' (expected full, no-coriolis or gravity)");
}

using M = AnyModel<double>;

const Eigen::VectorXd& with_wrenches(TermsChoice terms, const M& model, Data<M>& data, const Eigen::VectorXd& q,
                                     const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                     const LinkWrenches<M>& fext) {
  return terms == TermsChoice::Full         ? rnea<Terms::Full>(model, data, q, qd, qdd, fext)
         : terms == TermsChoice::NoCoriolis ? rnea<Terms::NoCoriolis>(model, data, q, qd, qdd, fext)
                                            : rnea<Terms::GravityOnly>(model, data, q, qd, qdd, fext);
}

}  // namespace

int run_id(Args& args) {
  if (args.flag("--help")) {
    print_usage();
    return 0;
  }
  const std::optional<std::string> terms_option = args.get("--terms");
  const std::string scene_name = read_scene(args);
  const std::string lock = read_lock(args, scene_name);
  if (terms_option && !scene_name.empty()) throw UsageError("--terms and --scene both choose the terms: give one");
  TermsChoice terms = parse_terms(terms_option.value_or("full"));
  if (!scene_name.empty()) {
    const Terms t = scene_terms(scene_name);
    terms = t == Terms::Full         ? TermsChoice::Full
            : t == Terms::NoCoriolis ? TermsChoice::NoCoriolis
                                     : TermsChoice::Gravity;
  }
  const std::string in_path = args.require("--in");
  const std::string out_path = args.get_or("--out", "-");
  const std::vector<std::string> wrench_specs = args.all("--wrench");
  const ModelDescription<double> description = load_model(args);
  args.finish();
  if (!wrench_specs.empty() && !scene_name.empty()) throw UsageError("--wrench does not go with --scene");
  if (in_path != "-" && in_path == out_path) throw UsageError("--in and --out name the same file");

  const AnyModel<double> model(description);
  Data<AnyModel<double>> data(model);
  ExternalWrenches wrenches(wrench_specs, model);
  std::vector<std::string> names;
  for (int i = 0; i < model.size(); ++i) names.push_back(model.joint_name(i));

  // the columns: q always, qd and qdd where the chosen terms read them, an optional time t
  const JointTable states(in_path, names,
                          {{"q_", true}, {"qd_", terms == TermsChoice::Full}, {"qdd_", terms != TermsChoice::Gravity}});

  // a scene: its locked joints held at the first row's angles, or where --lock says
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.size()), qd(model.size()), qdd(model.size());
  if (states.rows() > 0) states.read(0, 0, q);
  wrenches.attach(model, data, q);
  std::optional<SceneRunner> scene = make_scene(scene_name, lock, description, q);
  std::vector<std::size_t> written;  // the joints whose torques are written
  for (int i = 0; i < model.size(); ++i)
    if (!scene || scene->output(i)) written.push_back(std::size_t(i));

  // every row is valid now (the reader checked each cell): compute and write, all or nothing
  std::vector<std::string> header;
  if (states.has_time()) header.push_back("t");
  const auto tau_names = joint_columns(names, "tau_");
  for (const std::size_t i : written) header.push_back(tau_names[i]);
  CsvWriter out(out_path, header);

  std::vector<double> row;
  for (std::size_t r = 0; r < states.rows(); ++r) {
    states.read(r, 0, q);
    states.read(r, 1, qd);
    states.read(r, 2, qdd);
    const Eigen::VectorXd& tau = scene ? scene->inverse_dynamics(q, qd, qdd)
                                 : !wrenches.empty()
                                     ? with_wrenches(terms, model, data, q, qd, qdd, wrenches.at(model, data, q))
                                 : terms == TermsChoice::Full       ? rnea<Terms::Full>(model, data, q, qd, qdd)
                                 : terms == TermsChoice::NoCoriolis ? rnea<Terms::NoCoriolis>(model, data, q, qd, qdd)
                                                                    : rnea<Terms::GravityOnly>(model, data, q, qd, qdd);
    row.clear();
    if (states.has_time()) row.push_back(states.time(r));
    for (const std::size_t i : written) {
      const double x = tau[Eigen::Index(i)];
      // finite inputs give finite torques unless a number overflowed (e.g. qd = 1e200)
      if (!std::isfinite(x))
        throw InputError(states.where(r) + "the torque of joint '" + names[i] +
                         "' overflows at this state (its numbers are too large)");
      row.push_back(x);
    }
    out.row(row);
  }
  out.commit();
  return 0;
}

}  // namespace humandyn::cli
