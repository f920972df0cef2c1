// `--scene NAME`: the named scenes behind one runtime interface for the subcommands.
#include "cli/scene_option.hpp"

#include "cli/options.hpp"
#include "cli/print.hpp"
#include "humandyn/scene.hpp"
#include "text/shown.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <array>
#include <functional>
#include <optional>

namespace humandyn::cli {

struct SceneRunner::Impl {
  std::string name;
  Terms terms = Terms::Full;
  std::array<bool, SeedShape::nj> output{}, locked{};
  Eigen::VectorXd q_lock;
  Terms forward_terms = Terms::Full;
  std::function<Eigen::VectorXd(const Eigen::VectorXd&, const Eigen::VectorXd&, const Eigen::VectorXd&)> id;
  std::function<Eigen::VectorXd(const Eigen::VectorXd&, const Eigen::VectorXd&, const Eigen::VectorXd&, FdMethod)> fd;
  std::function<Eigen::VectorXd(FdMethod)> pivots;
  std::function<StepStatus(Integrator, FdMethod, Eigen::VectorXd&, Eigen::VectorXd&, const Eigen::VectorXd&,
                           const PdServo<AnyModel<double>>*, double)>
      step;
};

SceneRunner::SceneRunner(const std::string& name, const ModelDescription<double>& description,
                         const Eigen::VectorXd& q_lock)
    : impl_(std::make_shared<Impl>()) {
  impl_->q_lock = q_lock;
  try {
    (void)HumanModel<double>(description);
  } catch (const ModelError& e) {
    throw UsageError("--scene works on bodies of the seed's shape (16 joints in five chains); model '" +
                     text::shown(description.name) + "' is not one: " + e.what());
  }
  const bool found = with_named_scene(name, [&](auto scene) {
    using SceneT = decltype(scene);
    using SceneModel = typename SceneT::template model_type<double>;
    auto model = std::make_shared<const SceneModel>(SceneT::template model<double>(description, q_lock));
    auto data = std::make_shared<Data<SceneModel>>(*model);
    impl_->name = std::string(SceneT::name);
    impl_->terms = SceneT::terms;
    impl_->forward_terms = forward_terms<SceneT>;
    for (int i = 0; i < SeedShape::nj; ++i) {
      impl_->output[std::size_t(i)] = SceneT::outputs(i);
      impl_->locked[std::size_t(i)] = SceneT::spec.locked[std::size_t(i)];
    }
    impl_->id = [model, data](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd) {
      const auto tau = scene_rnea<SceneT>(*model, *data, SceneT::reduce(q), SceneT::reduce(qd), SceneT::reduce(qdd));
      return Eigen::VectorXd(SceneT::expand(tau));
    };
    impl_->fd = [model, data](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& tau,
                              FdMethod method) {
      const auto qr = SceneT::reduce(q), qdr = SceneT::reduce(qd), taur = SceneT::reduce(tau);
      if (method == FdMethod::Articulated)
        return Eigen::VectorXd(
            SceneT::expand(scene_forward_dynamics<SceneT, FdMethod::Articulated>(*model, *data, qr, qdr, taur)));
      return Eigen::VectorXd(
          SceneT::expand(scene_forward_dynamics<SceneT, FdMethod::MassMatrix>(*model, *data, qr, qdr, taur)));
    };
    auto ws = std::make_shared<StepWorkspace<SceneModel>>(*model);
    impl_->step = [model, ws, q_lock](Integrator integrator, FdMethod method, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                                      const Eigen::VectorXd& tau, const PdServo<AnyModel<double>>* servo, double h) {
      State<SceneModel> x(*model);
      x.q = SceneT::reduce(q);
      x.qd = SceneT::reduce(qd);
      const typename SceneModel::JointVector tau_scene = SceneT::reduce(tau);
      std::optional<PdServo<SceneModel>> scene_servo;
      if (servo) {
        scene_servo.emplace(*model);
        scene_servo->kp = SceneT::reduce(servo->kp);
        scene_servo->kd = SceneT::reduce(servo->kd);
        scene_servo->q_ref = SceneT::reduce(servo->q_ref);
        scene_servo->qd_ref = SceneT::reduce(servo->qd_ref);
        scene_servo->damping = SceneT::reduce(servo->damping);
        scene_servo->q_min = SceneT::reduce(servo->q_min);
        scene_servo->q_max = SceneT::reduce(servo->q_max);
        scene_servo->limit_stiffness = SceneT::reduce(servo->limit_stiffness);
      }
      const PdServo<SceneModel>* s = scene_servo ? &*scene_servo : nullptr;
      const bool aba = method == FdMethod::Articulated;
      StepStatus status;
      switch (integrator) {
        case Integrator::SemiImplicitEuler:
          status = aba ? scene_step<SceneT, Integrator::SemiImplicitEuler, FdMethod::Articulated>(*model, *ws, x,
                                                                                                  tau_scene, s, h)
                       : scene_step<SceneT, Integrator::SemiImplicitEuler, FdMethod::MassMatrix>(*model, *ws, x,
                                                                                                 tau_scene, s, h);
          break;
        case Integrator::RungeKutta4:
          status =
              aba ? scene_step<SceneT, Integrator::RungeKutta4, FdMethod::Articulated>(*model, *ws, x, tau_scene, s, h)
                  : scene_step<SceneT, Integrator::RungeKutta4, FdMethod::MassMatrix>(*model, *ws, x, tau_scene, s, h);
          break;
        case Integrator::ImplicitPD:
          status = scene_step<SceneT, Integrator::ImplicitPD>(*model, *ws, x, tau_scene, s, h);
          break;
        case Integrator::BackwardEuler:  // the command line refuses it with a scene
          status = {StepError::BadInput, Quantity::None, -1};
          break;
      }
      if (status.joint >= 0) status.joint = SceneT::full_index[std::size_t(status.joint)];
      if (!status.ok()) return status;
      // back to full size: locked joints at their lock angles, still
      const Eigen::VectorXd q_new = SceneT::expand(x.q), qd_new = SceneT::expand(x.qd);
      for (int i = 0; i < SceneT::full_nj; ++i) {
        const bool locked = SceneT::spec.locked[std::size_t(i)];
        q[i] = locked ? q_lock[i] : q_new[i];
        qd[i] = locked ? 0.0 : qd_new[i];
      }
      return status;
    };
    impl_->pivots = [data](FdMethod method) {
      const typename SceneT::template vector<double> p =
          method == FdMethod::Articulated ? typename SceneT::template vector<double>(data->D_inv.cwiseInverse())
                                          : typename SceneT::template vector<double>(data->D);
      Eigen::VectorXd out = Eigen::VectorXd::Constant(SceneT::full_nj, p.cwiseAbs().maxCoeff());
      for (int k = 0; k < SceneT::nj; ++k) out[SceneT::full_index[std::size_t(k)]] = p[k];
      return out;
    };
  });
  if (!found) throw UsageError("unknown --scene '" + shown(name) + "' (expected " + named_scene_list() + ")");
}

const std::string& SceneRunner::name() const { return impl_->name; }
Terms SceneRunner::terms() const { return impl_->terms; }
bool SceneRunner::output(int joint) const { return impl_->output[std::size_t(joint)]; }
bool SceneRunner::locked(int joint) const { return impl_->locked[std::size_t(joint)]; }
const Eigen::VectorXd& SceneRunner::lock_angles() const { return impl_->q_lock; }

Eigen::VectorXd SceneRunner::inverse_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                              const Eigen::VectorXd& qdd) {
  return impl_->id(q, qd, qdd);
}

Eigen::VectorXd SceneRunner::forward_dynamics(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                                              const Eigen::VectorXd& tau, FdMethod method) {
  return impl_->fd(q, qd, tau, method);
}

Eigen::VectorXd SceneRunner::pivots(FdMethod method) const { return impl_->pivots(method); }

bool SceneRunner::forward_uses_rates() const { return impl_->forward_terms == Terms::Full; }

StepStatus SceneRunner::step(Integrator integrator, FdMethod method, Eigen::VectorXd& q, Eigen::VectorXd& qd,
                             const Eigen::VectorXd& tau, const PdServo<AnyModel<double>>* servo, double h) {
  return impl_->step(integrator, method, q, qd, tau, servo, h);
}

CLI::Option* add_scene_options(CLI::App& command, SceneOptions& options, const std::string& scene_help,
                               const std::string& lock_help) {
  std::string scenes;
  for_each_named_scene([&](auto scene) {
    using SceneT = decltype(scene);
    scenes += "\n  " + std::string(SceneT::name) + ": drops " + std::string(SceneT::drops);
  });
  CLI::Option* scene = command.add_option("--scene", options.scene, scene_help + scenes)
                           ->option_text("NAME")
                           ->check([](const std::string& name) {
                             return with_named_scene(name, [](auto) {})
                                        ? std::string()
                                        : "unknown scene '" + shown(name) + "' (expected " + named_scene_list() + ")";
                           });
  command
      .add_option_function<std::string>(
          "--lock",
          [&options](const std::string& text) {
            // an empty text would read as the option left out
            if (text.empty()) throw UsageError("--lock needs JOINT=ANGLE,..., got ''");
            options.lock = text;
          },
          lock_help)
      ->option_text("J=A,...")
      ->needs(scene);
  return scene;
}

namespace {

// The angles --lock gives (JOINT=ANGLE pairs, comma-separated), per joint of `description`.
std::vector<std::optional<double>> lock_angles(const SceneOptions& options,
                                               const ModelDescription<double>& description) {
  const std::string& scene_name = options.scene;
  const std::string& lock = options.lock;
  std::array<bool, SeedShape::nj> locked{};
  with_named_scene(scene_name, [&](auto scene) { locked = decltype(scene)::spec.locked.flags(); });
  std::vector<std::optional<double>> angles(description.joints.size());
  std::size_t start = 0;
  while (start < lock.size()) {
    const std::size_t end = std::min(lock.find(',', start), lock.size());
    const std::string pair = lock.substr(start, end - start);
    start = end + 1;
    if (pair.empty() || end + 1 == lock.size())
      throw UsageError("--lock: an empty JOINT=ANGLE item in '" + shown(lock) + "'");
    const std::size_t eq = pair.find('=');
    if (eq == std::string::npos) throw UsageError("--lock: '" + shown(pair) + "' is not JOINT=ANGLE");
    const std::string joint = pair.substr(0, eq), angle_text = pair.substr(eq + 1);
    const auto it = std::find_if(description.joints.begin(), description.joints.end(),
                                 [&](const auto& j) { return j.name == joint; });
    if (it == description.joints.end())
      throw UsageError("--lock: model '" + shown(description.name) + "' has no joint '" + shown(joint) + "'");
    const auto i = std::size_t(it - description.joints.begin());
    if (i >= locked.size() || !locked[i])
      throw UsageError("--lock: scene '" + scene_name + "' does not lock joint '" + joint + "'");
    if (angles[i]) throw UsageError("--lock: joint '" + joint + "' is given twice");
    std::string why;
    angles[i] = read_number(angle_text, &why);
    if (!angles[i]) throw UsageError("--lock: the angle of joint '" + joint + "': " + why);
  }
  return angles;
}

}  // namespace

std::optional<SceneRunner> make_scene(const SceneOptions& options, const ModelDescription<double>& description,
                                      const Eigen::VectorXd& q_start) {
  if (options.scene.empty()) return std::nullopt;
  Eigen::VectorXd q_lock = q_start;
  const std::vector<std::optional<double>> given = lock_angles(options, description);
  for (std::size_t i = 0; i < given.size(); ++i)
    if (given[i]) q_lock[Eigen::Index(i)] = *given[i];
  return SceneRunner(options.scene, description, q_lock);
}

SceneJoints scene_joints(const SceneOptions& options, const ModelDescription<double>& description) {
  SceneJoints joints;
  std::array<bool, SeedShape::nj> locked{};
  with_named_scene(options.scene, [&](auto scene) { locked = decltype(scene)::spec.locked.flags(); });
  const std::vector<std::optional<double>> given = lock_angles(options, description);
  for (std::size_t i = 0; i < description.joints.size(); ++i) {
    const bool held = i < locked.size() && locked[i];
    if (!held) joints.moving.push_back(i);
    if (!held || !given[i]) joints.angles.push_back(i);
  }
  return joints;
}

std::array<ColumnGroup, 2> joint_column_groups(const std::vector<std::string>& joint_names, std::string_view prefix,
                                               const std::vector<std::size_t>& read, ColumnGroup::Use use) {
  std::array<ColumnGroup, 2> groups{ColumnGroup{{}, use}, ColumnGroup{{}, ColumnGroup::Ignored}};
  const std::vector<std::string> columns = joint_columns(joint_names, prefix);
  for (std::size_t i = 0; i < columns.size(); ++i)
    groups[std::find(read.begin(), read.end(), i) == read.end() ? 1 : 0].columns.push_back(columns[i]);
  return groups;
}

Terms scene_terms(const std::string& name) {
  Terms terms = Terms::Full;
  if (!with_named_scene(name, [&](auto scene) { terms = decltype(scene)::terms; }))
    throw UsageError("unknown --scene '" + shown(name) + "' (expected " + named_scene_list() + ")");
  return terms;
}

void warn_locked_motion(const SceneRunner& scene, const CsvTable& csv, const std::vector<std::string>& joint_names,
                        const std::string& command) {
  for (std::size_t i = 0; i < joint_names.size(); ++i) {
    if (!scene.locked(int(i))) continue;
    const double held = scene.lock_angles()[Eigen::Index(i)];
    for (const char* prefix : {"q_", "qd_", "qdd_"}) {
      const std::string name = prefix + joint_names[i];
      const int c = csv.column(name);
      if (c < 0 || csv.is_text(c)) continue;
      const double expected = prefix == std::string("q_") ? held : 0.0;
      for (std::size_t r = 0; r < csv.rows.size(); ++r)
        if (const double v = csv.rows[r][std::size_t(c)]; v != expected) {
          cli::print(stderr,
                     "humandyn {}: warning: {}: line {}: {} is {}, not used: the scene '{}' holds joint '{}' still at "
                     "{} rad\n",
                     command, csv.source, csv.lines[r], name, format_number(v), scene.name(), joint_names[i],
                     format_number(held));
          break;
        }
    }
  }
}

}  // namespace humandyn::cli
