#include "cli/joint_table.hpp"

#include <cmath>

namespace humandyn::cli {

JointTable::JointTable(const std::string& path, const std::vector<std::string>& joint_names,
                       const std::vector<ColumnGroup>& groups)
    : columns_(groups.size()) {
  std::vector<std::vector<std::string>> names;
  std::vector<std::string> allowed{"t"};
  for (const auto& g : groups) {
    names.push_back(joint_columns(joint_names, g.prefix));
    allowed.insert(allowed.end(), names.back().begin(), names.back().end());
  }
  // the header is checked before any row is read, so a missing column is reported first
  csv_ = read_csv(path, [&](const CsvTable& table) {
    table.reject_unknown_columns(allowed);
    for (std::size_t g = 0; g < groups.size(); ++g)
      if (groups[g].required) columns_[g] = require_columns(table, names[g]);
  });
  t_col_ = csv_.column("t");
}

std::string JointTable::where(std::size_t row) const {
  return csv_.source + ": line " + std::to_string(csv_.lines[row]) + ": ";
}

void JointTable::read(std::size_t row, std::size_t group, Eigen::VectorXd& v) const {
  const auto& cols = columns_[group];
  if (cols.empty()) {
    v.setZero();
    return;
  }
  const auto& cells = csv_.rows[row];
  for (std::size_t i = 0; i < cols.size(); ++i) v[Eigen::Index(i)] = cells[std::size_t(cols[i])];
}

void JointTable::write(CsvWriter& out, std::size_t row, const std::vector<std::size_t>& written,
                       const std::vector<std::string>& joint_names, const Eigen::VectorXd& values,
                       const char* quantity) const {
  std::vector<double> cells;
  cells.reserve(written.size() + 1);
  if (has_time()) cells.push_back(time(row));
  for (const std::size_t i : written) {
    const double x = values[Eigen::Index(i)];
    // finite inputs give finite results unless a number overflowed (e.g. qd = 1e200)
    if (!std::isfinite(x))
      throw InputError(where(row) + "the " + quantity + " of joint '" + joint_names[i] +
                       "' overflows at this state (its numbers are too large)");
    cells.push_back(x);
  }
  out.row(cells);
}

}  // namespace humandyn::cli
