#include "cli/base_columns.hpp"

#include <Eigen/Geometry>

#include <cmath>
#include <utility>

namespace humandyn::cli {

std::vector<std::string> base_columns(BaseGroup group) {
  switch (group) {
    case BaseGroup::Position:
      return {"base_x", "base_y", "base_z"};
    case BaseGroup::Orientation:
      return {"base_qw", "base_qx", "base_qy", "base_qz"};
    case BaseGroup::AngularVelocity:
      return {"base_wx", "base_wy", "base_wz"};
    case BaseGroup::Velocity:
      return {"base_vx", "base_vy", "base_vz"};
    case BaseGroup::AngularAcceleration:
      return {"base_wdx", "base_wdy", "base_wdz"};
    case BaseGroup::Acceleration:
      return {"base_ax", "base_ay", "base_az"};
  }
  return {};
}

std::vector<std::string> state_columns(std::initializer_list<BaseGroup> base, const std::vector<std::string>& joints,
                                       std::initializer_list<std::string_view> prefixes) {
  std::vector<std::string> columns;
  for (const BaseGroup g : base)
    for (auto& c : base_columns(g)) columns.push_back(std::move(c));
  for (const std::string_view prefix : prefixes)
    for (auto& c : joint_columns(joints, prefix)) columns.push_back(std::move(c));
  return columns;
}

std::vector<double> stance_state_values(const BaseMotion<double>& base, const Eigen::Ref<const Eigen::VectorXd>& q,
                                        const Eigen::Ref<const Eigen::VectorXd>& qd,
                                        const Eigen::Ref<const Eigen::VectorXd>& qdd) {
  const Eigen::Quaterniond r(base.pose.R);
  std::vector<double> values;
  const auto put = [&](const auto& v) { values.insert(values.end(), v.data(), v.data() + v.size()); };
  put(base.pose.p);
  put(Eigen::Vector4d(r.w(), r.x(), r.y(), r.z()));
  put(base.w);
  put(base.wd);
  put(base.a);
  put(q);
  put(qd);
  put(qdd);
  return values;
}

namespace {
constexpr BaseGroup all_groups[] = {BaseGroup::Position, BaseGroup::Orientation,         BaseGroup::AngularVelocity,
                                    BaseGroup::Velocity, BaseGroup::AngularAcceleration, BaseGroup::Acceleration};
}

BaseColumns::BaseColumns(std::vector<ColumnGroup>& groups) : first_(groups.size()) {
  for (const BaseGroup g : all_groups) groups.push_back({base_columns(g), ColumnGroup::Optional});
}

bool BaseColumns::any(const JointTable& table) const {
  for (std::size_t k = 0; k < std::size(all_groups); ++k)
    if (table.has(first_ + k)) return true;
  return false;
}

BaseState BaseColumns::read(const JointTable& table, std::size_t row, const Pose<double>& home) const {
  BaseState b;
  b.pose = home;
  const auto group = [&](BaseGroup g) { return first_ + std::size_t(g); };
  if (table.has(group(BaseGroup::Position))) table.read(row, group(BaseGroup::Position), b.pose.p);
  if (table.has(group(BaseGroup::Orientation))) {
    Eigen::Vector4d wxyz;
    table.read(row, group(BaseGroup::Orientation), wxyz);
    // a unit quaternion as written to 1e-6 (six digits); renormalised to the last bit
    if (!(std::abs(wxyz.stableNorm() - 1) <= 1e-6))
      table.fail_at(row, "base_qw",
                    "the orientation quaternion (base_qw, base_qx, base_qy, base_qz) has norm " +
                        format_number(wxyz.stableNorm()) + ", not 1");
    b.pose.R = Eigen::Quaterniond(wxyz[0], wxyz[1], wxyz[2], wxyz[3]).normalized().toRotationMatrix();
  }
  table.read(row, group(BaseGroup::AngularVelocity), b.w);
  table.read(row, group(BaseGroup::Velocity), b.v);
  table.read(row, group(BaseGroup::AngularAcceleration), b.wd);
  table.read(row, group(BaseGroup::Acceleration), b.a);
  return b;
}

}  // namespace humandyn::cli
