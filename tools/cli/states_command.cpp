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

std::vector<std::string> joint_names(const ModelDescription<double>& description) {
  std::vector<std::string> names;
  for (const auto& j : description.joints) names.push_back(j.name);
  return names;
}

}  // namespace humandyn::cli
