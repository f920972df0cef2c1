// A CSV file of states for the subcommands that read one row per state (id, fd): groups of columns such
// as q_<joint>, qd_<joint>, tau_<joint> for every joint of the model or base_x, base_y, base_z, text
// columns the command reads (e.g. stance), an optional time t, and columns the command does not use.
//
// A column whose name starts with a reserved prefix (q_, qd_, base_, ...) must be one the command knows:
// anything else there is a misspelling, an error naming the column. Every other column is passed
// through: its cells are copied, as written, to the output after t, so that a phase or a label rides
// along with its row.
#pragma once

#include "cli/csv.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace humandyn::cli {

// Which form of the body a file's states are read in. A file that says its form (a column `form`, every
// cell `floating`, as `simulate --floating` writes it) is read in that form only: its base_ columns are
// the pelvis's and its re-hung leg's angles turn the other way, so read as the stance-rooted form's they
// would be another motion.
enum class StateForm {
  Any,           // not states (a torques file): `form` is a column like any other
  StanceRooted,  // the stance foot's form: a `form` column is refused
  Floating,      // --floating: a `form` column must say `floating`
};

struct ColumnGroup {
  enum Use { Required, Optional, Ignored };
  std::vector<std::string> columns;  // e.g. q_<joint> for every joint, or base_x, base_y, base_z
  Use use;                           // Optional: all or none; Ignored: allowed, not read
};

class JointTable {
 public:
  // Reads `path` ("-": standard input); InputError naming the file, line and column on any error.
  // `reserved`: the prefixes of the command's own columns; `read_as_text`: the text columns it reads; `form`: the
  // form its states are read in (a `form` column that says another is an error naming its cell); `written`: the
  // columns the command writes, each an error naming its column when the file has it.
  JointTable(const std::string& path, const std::vector<ColumnGroup>& groups, const std::vector<std::string>& reserved,
             const std::vector<std::string>& read_as_text, StateForm form,
             const std::vector<std::string>& written = {});

  const CsvTable& csv() const { return csv_; }
  std::size_t rows() const { return csv_.rows.size(); }
  bool has_time() const { return t_col_ >= 0; }
  double time(std::size_t row) const { return csv_.rows[row][std::size_t(t_col_)]; }
  // "<file>: line <n>: ", to start a message about one row
  std::string where(std::size_t row) const;

  // Whether group g is read (required, or optional and present).
  bool has(std::size_t group) const { return !columns_[group].empty(); }
  // Group g of row `row` into v (one value per column); zeros when the group is not read.
  void read(std::size_t row, std::size_t group, Eigen::Ref<Eigen::VectorXd> v) const;
  // The same into v[joints[k]] (one joint per column); the entries of v not named are left as they are.
  void read(std::size_t row, std::size_t group, const std::vector<std::size_t>& joints,
            Eigen::Ref<Eigen::VectorXd> v) const;
  // Text column `name` of row `row`; nullptr when the file has no such column.
  const std::string* text(std::size_t row, const std::string& name) const;
  // InputError "<file>: line <n>, column <c> '<name>': <message>" about a cell of column `name`.
  [[noreturn]] void fail_at(std::size_t row, const std::string& name, const std::string& message) const;
  // As fail_at, a UsageError (exit code 2): a cell that does not go with the options or the model given.
  [[noreturn]] void refuse_at(std::size_t row, const std::string& name, const std::string& message) const;

  // The output's header: t (when the file has it), the passed-through columns, then `results`;
  // InputError when a passed-through column has the name of a result.
  std::vector<std::string> header(const std::vector<std::string>& results) const;

  // Writes the row for input row `row`: its t and passed-through cells, then `values` (none: an empty
  // cell). A value that is not finite (a number overflowed) is an InputError naming the row and what[k]
  // ("torque of joint 'r_knee_pitch'").
  void write(CsvWriter& out, std::size_t row, const std::vector<std::optional<double>>& values,
             const std::vector<std::string>& what) const;

 private:
  CsvTable csv_;
  int t_col_ = -1;
  std::vector<int> passed_;                // the passed-through columns
  std::vector<std::vector<int>> columns_;  // per group, each column (empty: not read)
};

}  // namespace humandyn::cli
