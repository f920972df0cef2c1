// humandyn fd: forward dynamics of every state in a CSV file, one row of joint accelerations per state.
#include "cli/commands.hpp"
#include "cli/csv.hpp"
#include "cli/joint_table.hpp"
#include "cli/model_source.hpp"
#include "cli/scene_option.hpp"
#include "cli/wrench_option.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/data.hpp"
#include "humandyn/model.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <optional>
#include <string>
#include <vector>

namespace humandyn::cli {

namespace {

void print_usage() {
  std::printf(
      "usage: humandyn fd [--model %s|FILE.json] [--method mass-matrix|articulated]\n"
      "                   [--terms full|no-coriolis | --scene NAME [--lock J=A,...]] --in STATES.csv\n"
      "                   [--wrench LINK:FX,FY,FZ[@PX,PY,PZ] ...] [--out ACCELERATIONS.csv]\n\n"
      "Forward dynamics of every row of STATES.csv: the joint accelerations that the joint torques produce\n"
      "at each state under gravity (the inverse of `humandyn id`).\n\n"
      "%s"
      "  --method M    mass-matrix: the mass matrix by composite rigid bodies and its tree-sparse L^T D L\n"
      "                factorisation (default); articulated: the articulated-body algorithm\n"
      "  --terms T     full: every term (default); no-coriolis: without the velocity products, as the seed\n"
      "                paper does (the qd_ columns are then not needed)\n"
      "  --scene NAME  a named scene of the seed body instead of --terms: its terms (static_pose steps without\n"
      "                the velocity products), its locked joints held at the first row's angles (their tau_\n"
      "                columns are not read), accelerations written for its moving joints only:\n%s"
      "  --lock J=A,..  with --scene: hold these locked joints at these angles (rad) instead of the first row's\n"
      "%s"
      "                The accelerations then include the wrenches' push. Not with --scene\n"
      "  --in FILE     the states, '-' for standard input. Header: q_<joint> (rad), qd_<joint> (rad/s) and\n"
      "                tau_<joint> (N m) for every joint; an optional time column t is copied\n"
      "  --out FILE    the accelerations, qdd_<joint> (rad/s^2), one row per input row (default: standard\n"
      "                output); written only when every row is valid\n\n"
      "The mass matrix must be regular. The paper's model is not: Table 1's pelvis link is massless and the\n"
      "right hip pitch, the waist pitch and the left hip pitch turn about one line, so no torque fixes the\n"
      "pelvis's turn about that line. Such a state is reported as an error, naming the joint.\n",
      builtin_models, model_options_help().c_str(), scene_help().c_str(), wrench_help);
}

// The smallest pivot below this fraction of the largest marks a singular mass matrix: round-off of a
// zero pivot sits near 1e-16 of the largest, a light hand's real pivot near 1e-7.
constexpr double singular_pivot = 1e-10;

template <FdMethod method, Terms terms>
const Eigen::VectorXd& accelerations(const AnyModel<double>& model, Data<AnyModel<double>>& data,
                                     const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& tau,
                                     const LinkWrenches<AnyModel<double>>* fext) {
  return fext ? forward_dynamics<method, terms>(model, data, q, qd, tau, *fext)
              : forward_dynamics<method, terms>(model, data, q, qd, tau);
}

}  // namespace

int run_fd(Args& args) {
  if (args.flag("--help")) {
    print_usage();
    return 0;
  }
  const std::string method_name = args.get_or("--method", "mass-matrix");
  if (method_name != "articulated" && method_name != "mass-matrix")
    throw UsageError("unknown --method '" + method_name + "' (expected articulated or mass-matrix)");
  const bool articulated = method_name == "articulated";
  const std::optional<std::string> terms_option = args.get("--terms");
  const std::string scene_name = read_scene(args);
  const std::string lock = read_lock(args, scene_name);
  if (terms_option && !scene_name.empty()) throw UsageError("--terms and --scene both choose the terms: give one");
  const std::string terms_name = terms_option.value_or("full");
  if (terms_name != "full" && terms_name != "no-coriolis")
    throw UsageError("unknown --terms '" + terms_name + "' (expected full or no-coriolis)");
  const bool full = scene_name.empty() ? terms_name == "full" : scene_terms(scene_name) == Terms::Full;
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

  // the columns: q and tau always, qd where the terms read it, an optional time t
  const JointTable states(in_path, names, {{"q_", true}, {"qd_", full}, {"tau_", true}});

  // a scene: its locked joints held at the first row's angles, or where --lock says
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.size()), qd(model.size()), tau(model.size());
  if (states.rows() > 0) states.read(0, 0, q);
  wrenches.attach(model, data, q);
  std::optional<SceneRunner> scene = make_scene(scene_name, lock, description, q);
  std::vector<std::size_t> written;  // the joints whose accelerations are written
  for (int i = 0; i < model.size(); ++i)
    if (!scene || !scene->locked(i)) written.push_back(std::size_t(i));

  std::vector<std::string> header;
  if (states.has_time()) header.push_back("t");
  const auto qdd_names = joint_columns(names, "qdd_");
  for (const std::size_t i : written) header.push_back(qdd_names[i]);
  CsvWriter out(out_path, header);

  std::vector<double> row;
  for (std::size_t r = 0; r < states.rows(); ++r) {
    states.read(r, 0, q);
    states.read(r, 1, qd);
    states.read(r, 2, tau);
    const FdMethod method = articulated ? FdMethod::Articulated : FdMethod::MassMatrix;
    const LinkWrenches<AnyModel<double>>* fext = wrenches.empty() ? nullptr : &wrenches.at(model, data, q);
    const Eigen::VectorXd scene_qdd = scene ? scene->forward_dynamics(q, qd, tau, method) : Eigen::VectorXd();
    const Eigen::VectorXd& qdd =
        scene         ? scene_qdd
        : articulated ? (full ? accelerations<FdMethod::Articulated, Terms::Full>(model, data, q, qd, tau, fext)
                              : accelerations<FdMethod::Articulated, Terms::NoCoriolis>(model, data, q, qd, tau, fext))
                      : (full ? accelerations<FdMethod::MassMatrix, Terms::Full>(model, data, q, qd, tau, fext)
                              : accelerations<FdMethod::MassMatrix, Terms::NoCoriolis>(model, data, q, qd, tau, fext));

    // the pivots: the articulated inertia about each joint axis, or D of M = L^T D L
    const Eigen::VectorXd pivots = scene         ? scene->pivots(method)
                                   : articulated ? Eigen::VectorXd(data.D_inv.cwiseInverse())
                                                 : Eigen::VectorXd(data.D);
    // looked at in the order the elimination meets them, tips inwards: the first that is not clearly
    // positive is where M is singular (a zero pivot turns those after it into NaN)
    double largest = 0;
    for (Eigen::Index i = 0; i < pivots.size(); ++i)
      if (std::isfinite(pivots[i])) largest = std::max(largest, std::abs(pivots[i]));
    const std::string where = states.where(r);
    for (Eigen::Index i = pivots.size() - 1; i >= 0; --i)
      if (!(pivots[i] > singular_pivot * largest))
        throw InputError(where + "the mass matrix is singular at joint '" + names[std::size_t(i)] + "' (pivot " +
                         (std::isfinite(pivots[i]) ? format_number(pivots[i]) : std::string("not finite")) +
                         " kg m^2, largest " + format_number(largest) +
                         "): the motion this joint adds moves no mass; forward dynamics is undefined");
    row.clear();
    if (states.has_time()) row.push_back(states.time(r));
    for (const std::size_t i : written) {
      const double x = qdd[Eigen::Index(i)];
      if (!std::isfinite(x))
        throw InputError(where + "the acceleration of joint '" + names[i] +
                         "' overflows at this state (its numbers are too large)");
      row.push_back(x);
    }
    out.row(row);
  }
  out.commit();
  return 0;
}

}  // namespace humandyn::cli
