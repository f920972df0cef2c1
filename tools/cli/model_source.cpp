#include "cli/model_source.hpp"

#include "cli/csv.hpp"
#include "cli/model_json.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/data.hpp"
#include "humandyn/floating.hpp"
#include "text/shown.hpp"

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <array>
#include <cmath>
#include <utility>

namespace humandyn::cli {

namespace {

// The built-in bodies `--model NAME` names (builders.hpp).
struct BuiltinBody {
  const char* name;
  SeedParameters (*parameters)();
};
constexpr std::array<BuiltinBody, 3> builtin_bodies{
    {{"default", default_parameters}, {"female", female_parameters}, {"paper", paper_parameters}}};

const BuiltinBody* find_builtin(const std::string& name) {
  for (const BuiltinBody& b : builtin_bodies)
    if (name == b.name) return &b;
  return nullptr;
}

}  // namespace

std::string builtin_model_names(const std::string& separator, const std::string& last) {
  std::string names;
  for (std::size_t k = 0; k < builtin_bodies.size(); ++k)
    names += (k == 0 ? "" : k + 1 == builtin_bodies.size() ? last : separator) + builtin_bodies[k].name;
  return names;
}

CLI::Option* add_model_options(CLI::App& command, ModelOptions& options) {
  const std::string group = "the model";
#ifdef HUMANDYN_WITH_URDF
  CLI::Option* model = command.add_option("--model", options.model,
                                          builtin_model_names(", ", " or ") +
                                              " (built in; default: default, de Leva's\n"
                                              "reference male), a FILE.json written by `humandyn model --json`, or\n"
                                              "a FILE.urdf, imported with the options below");
  add_urdf_options(command, options.urdf, group);  // (without --model FILE.urdf: refused by read_model, naming it)
#else
  CLI::Option* model = command.add_option("--model", options.model,
                                          builtin_model_names(", ", " or ") +
                                              " (built in; default: default, de Leva's\n"
                                              "reference male) or a FILE.json written by `humandyn model --json`");
#endif
  return model->option_text("M")->group(group);
}

CLI::Option* add_floating_option(CLI::App& command, ModelOptions& options, const std::string& effect) {
  options.floating_offered = true;
  return command
      .add_flag("--floating", options.floating,
                "the floating form of the body: a free (6-DOF) base at the pelvis, the legs,\n"
                "waist and arms hanging from it (docs/base.md; a built-in body, or a\n"
                "FILE.json or FILE.urdf of the seed's shape, or a FILE.json written by\n"
                "`humandyn model --json --floating`). " +
                    effect)
      ->group("the model");
}

ModelSource read_model(const ModelOptions& options) {
  const std::string& name = options.model;
  const auto stance_rooted = [](ModelDescription<double> d) {
    ModelSource m;
    m.description = std::move(d);
    return m;
  };
#ifdef HUMANDYN_WITH_URDF
  // a URDF file, imported as DH chains (--root, --joints, --up or --gravity, --balance-inertia go with it)
  if (is_urdf_path(name)) return stance_rooted(import_urdf(name, options.urdf).model);
  if (options.urdf.given())
    throw UsageError(
        "the URDF importer's options (--root, --joints, the up axis, --gravity, --balance-inertia) go "
        "with --model FILE.urdf");
#endif
  if (const BuiltinBody* b = find_builtin(name)) return stance_rooted(human_description(b->parameters()));
  // a model file written by `humandyn model --json` (or by hand in that format)
  if (has_ending(name, ".json")) {
    const json::Json file = json::read_file(name);
    ModelSource m;
    const std::string shown_name = text::shown(name);  // the name as messages show it
    m.description = model_from_json(file, shown_name, &m.floating);
    if (const auto l = json::Node(file, shown_name).find("landmarks")) m.landmarks = l->value();
    return m;
  }
  throw UsageError("unknown model '" + text::shown(name) + "' (expected " + builtin_model_names("|", "|") +
                   " or a FILE.json or FILE.urdf)");
}

bool is_builtin_model(const std::string& name) { return find_builtin(name) != nullptr; }

ModelDescription<double> load_model(const ModelOptions& options, std::optional<json::Json>* landmarks) {
  ModelSource source = read_model(options);
  const bool floating_file = source.floating;
  ModelDescription<double>& d = source.description;
  if (landmarks) *landmarks = std::move(source.landmarks);
  if (floating_file && !options.floating)
    throw UsageError(options.model + " describes the floating form of a body: " +
                     (options.floating_offered ? std::string("give --floating too")
                                               : "this command takes the stance-rooted one (`humandyn model "
                                                 "--json` without --floating writes it)"));
  if (!options.floating || floating_file) return d;
  // the floating form is built from the seed's shape: the stance leg re-hung from the pelvis
  try {
    const HumanModel<double> seed(d);
  } catch (const ModelError& e) {
    throw UsageError("--floating re-roots a body of the seed's shape (five chains from the stance foot), which '" +
                     options.model + "' is not: " + e.what());
  }
  return floating_description(d);
}

namespace {
double largest_pivot(const Eigen::VectorXd& pivots) {
  double largest = 0;
  for (Eigen::Index i = 0; i < pivots.size(); ++i)
    if (std::isfinite(pivots[i])) largest = std::max(largest, std::abs(pivots[i]));
  return largest;
}
}  // namespace

Eigen::Index singular_joint(const Eigen::VectorXd& pivots) {
  return singular_pivot_joint(
      int(pivots.size()), [&](int i) { return pivots[i]; }, singular_pivot);
}

void check_pivots(const Eigen::VectorXd& pivots, const AnyModel<double>& model, const std::string& where) {
  const Eigen::Index i = singular_joint(pivots);
  if (i < 0) return;
  // (the pivots after a zero one come out not finite: where it is met first, none is positive)
  const double largest = largest_pivot(pivots);
  throw InputError(where + "the mass matrix is singular at joint '" + model.joint_name(int(i)) + "' (pivot " +
                   (std::isfinite(pivots[i]) ? format_number(pivots[i]) : std::string("not finite")) + " kg m^2, " +
                   (largest > 0 ? "largest " + format_number(largest) : std::string("no pivot positive and finite")) +
                   "): a turn of this joint, with the joints beyond it turning along, moves no mass; forward dynamics "
                   "is undefined");
}

std::string floating_null_motion(const AnyModel<double>& model, const Eigen::VectorXd& q) {
  FloatingData<AnyModel<double>> fd(model);
  floating_crba(model, fd, q);
  const Eigen::Index n = model.size();
  Eigen::MatrixXd M(6 + n, 6 + n);
  M << fd.Mbb, fd.Mbj, fd.Mbj.transpose(), fd.data.M;
  const Eigen::VectorXd d = M.diagonal();
  if (!d.allFinite()) return "";                                              // (an overflow: the dynamics say so)
  if (!(d.head<6>().array() > 0).all()) return "a motion of the base alone";  // (all the mass on a line, or none)
  if (!(d.tail(n).array() > 0).all()) return "";  // a joint that moves no mass: check_pivots names it
  // scaled by the diagonal, the motion is unitless: the joints it turns measured against its largest part
  const Eigen::VectorXd scale = d.cwiseSqrt().cwiseInverse();
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(scale.asDiagonal() * M * scale.asDiagonal());
  const Eigen::VectorXd& ev = eigen.eigenvalues();  // ascending
  if (ev[0] > singular_pivot * ev[6 + n - 1]) return "";
  const Eigen::VectorXd v = eigen.eigenvectors().col(0).cwiseAbs();
  std::string joints;
  for (Eigen::Index i = 0; i < n; ++i)
    if (v[6 + i] >= 0.1 * v.maxCoeff()) joints += (joints.empty() ? "'" : ", '") + model.joint_name(int(i)) + "'";
  return joints.empty() ? "a motion of the base alone" : "turning the base with joints " + joints;
}

void check_mass_matrix_at_home(const AnyModel<double>& model) {
  Data<AnyModel<double>> data(model);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.size());
  forward_dynamics<FdMethod::MassMatrix, Terms::Full>(model, data, zero, zero, zero);
  check_pivots(data.D, model, "model '" + text::shown(model.description().name) + "' at the home pose: ");
}

}  // namespace humandyn::cli
