#include "cli/wrench_option.hpp"

#include "cli/options.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/algorithm/rnea.hpp"

#include <fmt/format.h>

namespace humandyn::cli {

namespace {

// "X,Y,Z": three finite numbers; UsageError quoting the spec and naming `part`.
Vec3<double> read_triple(const std::string& text, const std::string& spec, const char* part) {
  Vec3<double> v;
  std::string why;
  if (!read_numbers(text, v.data(), 3, &why))
    throw UsageError(fmt::format("--wrench '{}': the {} '{}' must be three finite numbers X,Y,Z: {}", shown(spec), part,
                                 shown(text), why));
  return v;
}

}  // namespace

CLI::Option* add_wrench_option(CLI::App& command, std::vector<std::string>& specs, const std::string& effect) {
  return command
      .add_option("--wrench", specs,
                  "an external force on link L, repeatable: F = FX,FY,FZ (N, world frame,\n"
                  "keeps its direction), applied at P = PX,PY,PZ (m, world coordinates in\n"
                  "the first state, then fixed on the link; default: the origin of the\n"
                  "link's DH frame, at the far joint of its row, which for a URDF body is\n"
                  "not the URDF link's origin), e.g. a 10 kg load hanging at the left\n"
                  "wrist (the left forearm's frame): --wrench l_forearm:0,0,-98.1\n" +
                      effect)
      ->option_text("L:F[@P]")
      ->allow_extra_args(false);
}

ExternalWrenches::ExternalWrenches(const std::vector<std::string>& specs, const M& model)
    : fext_(std::size_t(model.size())), tau_(Eigen::VectorXd::Zero(model.size())) {
  const auto& joints = model.description().joints;
  for (const std::string& text : specs) {
    const std::size_t at = text.find('@');
    const std::string head = text.substr(0, at);
    const std::size_t colon = head.rfind(':');
    if (colon == std::string::npos || colon == 0)
      throw UsageError(fmt::format("--wrench '{}': expected LINK:FX,FY,FZ[@PX,PY,PZ]", shown(text)));
    Spec s;
    const std::string link = head.substr(0, colon);
    s.link = -1;
    for (std::size_t i = 0; i < joints.size(); ++i)
      if (joints[i].link_name == link) s.link = int(i);
    if (s.link < 0) {
      std::string names;
      for (const auto& j : joints) names += (names.empty() ? "" : ", ") + j.link_name;
      throw UsageError(fmt::format("--wrench '{}': unknown link '{}'{} (the links that move: {})", shown(text),
                                   shown(link), link == model.description().base_link_name ? ", the fixed base" : "",
                                   names));
    }
    s.force = read_triple(head.substr(colon + 1), text, "force");
    if (at != std::string::npos) s.point_world = read_triple(text.substr(at + 1), text, "point");
    specs_.push_back(s);
  }
}

void ExternalWrenches::attach(const M& model, Data<M>& data, const Eigen::VectorXd& q) {
  forward_kinematics(model, data, q);
  for (auto& s : specs_)
    if (s.point_world) {
      const auto& X = data.oMi[std::size_t(s.link)];
      s.point_link = X.R.transpose() * (*s.point_world - X.p);
    }
}

const LinkWrenches<ExternalWrenches::M>& ExternalWrenches::at(const M& model, Data<M>& data, const Eigen::VectorXd& q) {
  forward_kinematics(model, data, q);
  for (auto& w : fext_) w = {};
  for (const auto& s : specs_) {
    auto& w = fext_[std::size_t(s.link)];
    const Vec3<double> f = data.oMi[std::size_t(s.link)].R.transpose() * s.force;
    w.force += f;
    w.moment += s.point_link.cross(f);
  }
  return fext_;
}

const Eigen::VectorXd& ExternalWrenches::joint_torques(const M& model, Data<M>& data, const Eigen::VectorXd& q) {
  // rnea subtracts J^T w from the static torques: the difference with and without the wrenches is -J^T w
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.size());
  tau_ = gravity_torques(model, data, q);
  tau_ -= rnea<Terms::GravityOnly>(model, data, q, zero, zero, at(model, data, q));
  return tau_;
}

}  // namespace humandyn::cli
