// What `id` and `fd` share: a model (stance-rooted or --floating), a named scene or external wrenches,
// a states file in and a results file out, each row of results computed from a row of states.
#pragma once

#include "cli/joint_table.hpp"
#include "cli/model_source.hpp"
#include "cli/scene_option.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace humandyn::cli {

struct StatesOptions {
  ModelOptions model;
  SceneOptions scene;
  std::vector<std::string> wrenches;
  std::string in, out = "-";
};

// The help texts of the shared options, in the words of one command.
struct StatesHelp {
  std::string floating;     // what --floating changes
  std::string scene, lock;  // --scene and --lock
  std::string wrench;       // what --wrench changes
  std::string in, out;      // the files' columns
};

// Registers --floating, --scene, --lock, --wrench, --in and --out, after the command's --model (add_model_options)
// and its --terms. Returns --scene, which --terms excludes.
CLI::Option* add_states_options(CLI::App& command, StatesOptions& options, const StatesHelp& help);

// The model's joint names, in order.
std::vector<std::string> joint_names(const ModelDescription<double>& description);

// The joint columns of a states file: q_, qd_ and a third prefix (qdd_ for id, tau_ for fd), each read for
// the joints the scene lets the command read (scene_joints: a locked joint's angle only when --lock does not
// give it, its other columns never) and allowed, unread, for the others.
class JointColumns {
 public:
  // Appends the six groups to `groups` (the base's, BaseColumns, may follow); q_ columns are Required.
  JointColumns(const StatesOptions& options, const ModelDescription<double>& description, ColumnGroup::Use qd_use,
               std::string_view third, ColumnGroup::Use third_use, std::vector<ColumnGroup>& groups);
  // Row `row`'s angles into q (nj); the joints not read keep their values.
  void read_angles(const JointTable& states, std::size_t row, Eigen::Ref<Eigen::VectorXd> q) const;
  // Row `row`'s angles, rates and third quantity (zero where its group is Ignored) into q, qd, x (nj each).
  void read(const JointTable& states, std::size_t row, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd,
            Eigen::Ref<Eigen::VectorXd> x) const;

 private:
  SceneJoints joints_;
  std::size_t first_ = 0;  // the index of the q_ group
};

// The results' columns a command writes, and what its messages call each ("torque of joint 'r_knee_pitch'").
struct ResultColumns {
  std::vector<std::string> names, what;
  void add(std::string name, std::string description) {
    names.push_back(std::move(name));
    what.push_back(std::move(description));
  }
};

// Every row of `states` through `compute(row, cells)`, which appends that row's results, into the file `path`:
// the input's t and passed-through columns, then the results'; all or nothing (InputError naming the row and
// the result that is not finite).
template <class Compute>
void write_results(const JointTable& states, const std::string& path, const ResultColumns& results, Compute&& compute) {
  CsvWriter out(path, states.header(results.names));
  std::vector<std::optional<double>> cells;
  for (std::size_t r = 0; r < states.rows(); ++r) {
    cells.clear();
    compute(r, cells);
    states.write(out, r, cells, results.what);
  }
  out.commit();
}

}  // namespace humandyn::cli
