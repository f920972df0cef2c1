// A CSV file of joint states for the subcommands that read one row per state (id, fd): column groups
// such as q_<joint>, qd_<joint>, tau_<joint> for every joint of the model, and an optional time t. Every
// group named is allowed in the header; the required ones must be complete; anything else is an error
// naming the column.
#pragma once

#include "cli/csv.hpp"

#include <Eigen/Core>

#include <string>
#include <vector>

namespace humandyn::cli {

struct ColumnGroup {
  std::string prefix;  // e.g. "q_": the columns q_<joint>
  bool required;       // must be present; otherwise ignored even when present
};

class JointTable {
 public:
  // Reads `path` ("-": standard input); InputError naming the file, line and column on any error.
  JointTable(const std::string& path, const std::vector<std::string>& joint_names,
             const std::vector<ColumnGroup>& groups);

  const CsvTable& csv() const { return csv_; }
  std::size_t rows() const { return csv_.rows.size(); }
  bool has_time() const { return t_col_ >= 0; }
  double time(std::size_t row) const { return csv_.rows[row][std::size_t(t_col_)]; }
  // "<file>: line <n>: ", to start a message about one row
  std::string where(std::size_t row) const;

  // Group g of row `row` into v (one value per joint); zeros when the group is not required.
  void read(std::size_t row, std::size_t group, Eigen::VectorXd& v) const;

  // Writes the result for row `row`: its time (when the file has one), then values[i] for each joint i
  // of `written`. A value that is not finite (a number overflowed) is an InputError naming the row and
  // the joint's `quantity` ("torque", "acceleration").
  void write(CsvWriter& out, std::size_t row, const std::vector<std::size_t>& written,
             const std::vector<std::string>& joint_names, const Eigen::VectorXd& values, const char* quantity) const;

 private:
  CsvTable csv_;
  int t_col_ = -1;
  std::vector<std::vector<int>> columns_;  // per group, each joint's column (empty: not required)
};

}  // namespace humandyn::cli
