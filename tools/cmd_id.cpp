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
#include "humandyn/poses.hpp"

#include <cmath>
#include <memory>
#include <optional>
#include <string>
#include <vector>

namespace humandyn::cli {

namespace {

enum class TermsChoice { Full, NoCoriolis, Gravity };

using M = AnyModel<double>;

struct IdOptions {
  ModelOptions model;
  TermsChoice terms = TermsChoice::Full;
  SceneOptions scene;
  std::vector<std::string> wrenches;
  std::string in, out = "-";
};

const Eigen::VectorXd& with_wrenches(TermsChoice terms, const M& model, Data<M>& data, const Eigen::VectorXd& q,
                                     const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                                     const LinkWrenches<M>& fext) {
  return terms == TermsChoice::Full         ? rnea<Terms::Full>(model, data, q, qd, qdd, fext)
         : terms == TermsChoice::NoCoriolis ? rnea<Terms::NoCoriolis>(model, data, q, qd, qdd, fext)
                                            : rnea<Terms::GravityOnly>(model, data, q, qd, qdd, fext);
}

int run_id(const IdOptions& o) {
  TermsChoice terms = o.terms;
  if (!o.scene.scene.empty()) {
    const Terms t = scene_terms(o.scene.scene);
    terms = t == Terms::Full         ? TermsChoice::Full
            : t == Terms::NoCoriolis ? TermsChoice::NoCoriolis
                                     : TermsChoice::Gravity;
  }
  if (o.in != "-" && o.in == o.out) throw UsageError("--in and --out name the same file");
  const ModelDescription<double> description = load_model(o.model);

  const AnyModel<double> model(description);
  Data<AnyModel<double>> data(model);
  ExternalWrenches wrenches(o.wrenches, model);
  std::vector<std::string> names;
  for (int i = 0; i < model.size(); ++i) names.push_back(model.joint_name(i));

  // the columns: q always, qd and qdd where the chosen terms read them, an optional time t
  const JointTable states(o.in, names,
                          {{"q_", true}, {"qd_", terms == TermsChoice::Full}, {"qdd_", terms != TermsChoice::Gravity}});

  // a scene: its locked joints held at the first row's angles, or where --lock says
  Eigen::VectorXd q = Eigen::VectorXd::Zero(model.size()), qd(model.size()), qdd(model.size());
  if (states.rows() > 0) states.read(0, 0, q);
  wrenches.attach(model, data, q);
  std::optional<SceneRunner> scene = make_scene(o.scene, description, q);
  std::vector<std::size_t> written;  // the joints whose torques are written
  for (int i = 0; i < model.size(); ++i)
    if (!scene || scene->output(i)) written.push_back(std::size_t(i));

  // every row is valid now (the reader checked each cell): compute and write, all or nothing
  std::vector<std::string> header;
  if (states.has_time()) header.push_back("t");
  const auto tau_names = joint_columns(names, "tau_");
  for (const std::size_t i : written) header.push_back(tau_names[i]);
  CsvWriter out(o.out, header);

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
    states.write(out, r, written, names, tau, "torque");
  }
  out.commit();
  return 0;
}

}  // namespace

Command add_id(CLI::App& humandyn) {
  const auto o = std::make_shared<IdOptions>();
  CLI::App* c = humandyn.add_subcommand(
      "id",
      "inverse dynamics: joint torques for every state of a CSV file\n\n"
      "Inverse dynamics (recursive Newton-Euler) of every row of STATES.csv: the joint torques that hold or\n"
      "move the body through each state under gravity.");
  add_model_options(*c, o->model);
  CLI::Option* terms =
      add_choice(
          *c, "--terms", o->terms,
          {{"full", TermsChoice::Full}, {"no-coriolis", TermsChoice::NoCoriolis}, {"gravity", TermsChoice::Gravity}},
          "full: every term (default); no-coriolis: without the velocity\n"
          "products, as the seed paper does; gravity: the static torques only")
          ->option_text("T");
  CLI::Option* scene =
      add_scene_options(*c, o->scene,
                        "a named scene of the seed body instead of --terms (its terms, its\n"
                        "locked joints held at the first row's angles, only its output\n"
                        "torques written):",
                        std::string("with --scene: hold these locked joints at these angles (rad) instead,\n"
                                    "e.g. seated, with --scene upper_body:\n--lock ") +
                            poses::lock_text(poses::seated));
  terms->excludes(scene);
  add_wrench_option(*c, o->wrenches,
                    "The torques then also hold the wrenches (a load in the hand raises the\n"
                    "arm's). Not with --scene")
      ->excludes(scene);
  c->add_option("--in", o->in,
                "the states, '-' for standard input. Header: q_<joint> (rad) for every\n"
                "joint, and qd_<joint> (rad/s) and qdd_<joint> (rad/s^2) for every joint\n"
                "where the terms use them (full: both; no-coriolis: qdd; gravity:\n"
                "neither); an optional time column t is copied")
      ->option_text("FILE")
      ->required();
  c->add_option("--out", o->out,
                "the torques, tau_<joint> (N m), one row per input row (default:\n"
                "standard output); written only when every row is valid")
      ->option_text("FILE");
  return {c, [o] { return run_id(*o); }};
}

}  // namespace humandyn::cli
