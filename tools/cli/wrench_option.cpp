#include "cli/wrench_option.hpp"

#include "cli/args.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/algorithm/rnea.hpp"

#include <fmt/format.h>

#include <cmath>
#include <cstdlib>

namespace humandyn::cli {

namespace {

// "X,Y,Z": three finite numbers; UsageError quoting the spec and naming `part`.
Vec3<double> read_triple(const std::string& text, const std::string& spec, const char* part) {
  Vec3<double> v;
  std::size_t from = 0;
  for (int k = 0; k < 3; ++k) {
    const std::size_t comma = k < 2 ? text.find(',', from) : text.size();
    const std::string cell = text.substr(from, comma == std::string::npos ? std::string::npos : comma - from);
    char* end = nullptr;
    v[k] = std::strtod(cell.c_str(), &end);
    if (comma == std::string::npos || cell.empty() || *end != '\0' || !std::isfinite(v[k]))
      throw UsageError(fmt::format("--wrench '{}': the {} '{}' must be three finite numbers X,Y,Z", spec, part, text));
    from = comma + 1;
  }
  return v;
}

}  // namespace

ExternalWrenches::ExternalWrenches(const std::vector<std::string>& specs, const M& model)
    : fext_(std::size_t(model.size())), tau_(Eigen::VectorXd::Zero(model.size())) {
  const auto& joints = model.description().joints;
  for (const std::string& text : specs) {
    const std::size_t at = text.find('@');
    const std::string head = text.substr(0, at);
    const std::size_t colon = head.rfind(':');
    if (colon == std::string::npos || colon == 0)
      throw UsageError(fmt::format("--wrench '{}': expected LINK:FX,FY,FZ[@PX,PY,PZ]", text));
    Spec s;
    const std::string link = head.substr(0, colon);
    s.link = -1;
    for (std::size_t i = 0; i < joints.size(); ++i)
      if (joints[i].link_name == link) s.link = int(i);
    if (s.link < 0) {
      std::string names;
      for (const auto& j : joints) names += (names.empty() ? "" : ", ") + j.link_name;
      throw UsageError(fmt::format("--wrench '{}': unknown link '{}'{} (the links that move: {})", text, link,
                                   link == model.description().base_link_name ? ", the fixed base" : "", names));
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
