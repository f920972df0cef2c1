#include "cli/states_command.hpp"

#include "cli/errors.hpp"
#include "cli/wrench_option.hpp"

#include <system_error>

namespace humandyn::cli {

CLI::Option* add_states_options(CLI::App& command, StatesOptions& o, const StatesHelp& help) {
  CLI::Option* floating = add_floating_option(command, o.model, help.floating);
  CLI::Option* scene = add_scene_options(command, o.scene, help.scene, help.lock);
  CLI::Option* wrench = add_wrench_option(
      command, o.wrenches, help.wrench + ". Not with --scene, --floating, or a stance or base_ column in the states");
  wrench->excludes(scene);
  floating->excludes(scene)->excludes(wrench);
  command.add_option("--in", o.in, help.in)->option_text("FILE")->required();
  command.add_option("--out", o.out, help.out)->option_text("FILE");
  return scene;
}

JointColumns::JointColumns(const StatesOptions& options, const ModelDescription<double>& description,
                           ColumnGroup::Use qd_use, std::string_view third, ColumnGroup::Use third_use,
                           std::vector<ColumnGroup>& groups)
    : joints_(scene_joints(options.scene, description)), first_(groups.size()) {
  const std::vector<std::string> names = joint_names(description);
  for (const auto& read_and_not : {joint_column_groups(names, "q_", joints_.angles, ColumnGroup::Required),
                                   joint_column_groups(names, "qd_", joints_.moving, qd_use),
                                   joint_column_groups(names, third, joints_.moving, third_use)})
    groups.insert(groups.end(), read_and_not.begin(), read_and_not.end());
}

void JointColumns::read_angles(const JointTable& states, std::size_t row, Eigen::Ref<Eigen::VectorXd> q) const {
  states.read(row, first_, joints_.angles, q);
}

void JointColumns::read(const JointTable& states, std::size_t row, Eigen::Ref<Eigen::VectorXd> q,
                        Eigen::Ref<Eigen::VectorXd> qd, Eigen::Ref<Eigen::VectorXd> x) const {
  states.read(row, first_, joints_.angles, q);
  states.read(row, first_ + 2, joints_.moving, qd);
  states.read(row, first_ + 4, joints_.moving, x);
}

std::vector<std::string> joint_names(const ModelDescription<double>& description) {
  std::vector<std::string> names;
  for (const auto& j : description.joints) names.push_back(j.name);
  return names;
}

}  // namespace humandyn::cli
