// Running the humandyn binary from a test: a scratch folder per test, the binary's exit code and
// output, text files in and out, a description's joint names (the CSV column suffixes), the CSV files it
// reads and the columns of those it writes, and the messages of the command line's InputError.
// The binary is HUMANDYN_CLI, which the test target defines.
#pragma once

#include "cli/csv.hpp"
#include "humandyn/model.hpp"
#include "support/random_states.hpp"

#include <Eigen/Core>

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#ifndef HUMANDYN_CLI
#error "cli_run.hpp needs HUMANDYN_CLI, the path of the humandyn binary"
#endif

namespace humandyn::testing {

inline std::string read_text(const std::filesystem::path& p) {
  std::ifstream in(p, std::ios::binary);
  std::ostringstream s;
  s << in.rdbuf();
  return s.str();
}

inline void write_text(const std::filesystem::path& p, const std::string& text) {
  std::ofstream(p, std::ios::binary) << text;
}

// A scratch folder for the current test, removed afterwards: humandyn_<suite>_<test>_<pid> in the
// system's temporary folder.
class Scratch {
 public:
  Scratch() {
    const auto* test = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name =
        std::string("humandyn_") + test->test_suite_name() + "_" + test->name() + "_" + std::to_string(::getpid());
    std::replace(name.begin(), name.end(), '/', '_');  // parameterised tests' names
    dir_ = std::filesystem::temp_directory_path() / name;
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
  }
  ~Scratch() { std::filesystem::remove_all(dir_); }
  Scratch(const Scratch&) = delete;
  Scratch& operator=(const Scratch&) = delete;
  std::filesystem::path operator/(const std::string& name) const { return dir_ / name; }
  const std::filesystem::path& dir() const { return dir_; }

 private:
  std::filesystem::path dir_;
};

struct CliRun {
  int exit_code;
  std::string out, err;
};

// Runs the humandyn binary with `arguments` (a shell fragment) in `where`.
inline CliRun humandyn_cli(const Scratch& where, const std::string& arguments) {
  const std::filesystem::path out = where / "stdout.txt", err = where / "stderr.txt";
  const std::string command = "cd '" + where.dir().string() + "' && '" HUMANDYN_CLI "' " + arguments + " > '" +
                              out.string() + "' 2> '" + err.string() + "'";
  const int status = std::system(command.c_str());
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_text(out), read_text(err)};
}

inline std::vector<std::string> joint_names(const ModelDescription<double>& d) {
  std::vector<std::string> names;
  for (const auto& j : d.joints) names.push_back(j.name);
  return names;
}

// A CSV of joint quantities: a t column (rows 1 ms apart) and, per (prefix, rows) block, the columns
// `<prefix><joint>` of every joint, one vector a row, in full precision.
using CsvBlock = std::pair<std::string, std::vector<Eigen::VectorXd>>;
inline std::string joint_csv(const std::vector<std::string>& names, const std::vector<CsvBlock>& blocks) {
  std::string text = "t";
  for (const auto& [prefix, rows] : blocks)
    for (const auto& c : cli::joint_columns(names, prefix)) text.append(",").append(c);
  text += "\n";
  for (std::size_t r = 0; r < blocks.front().second.size(); ++r) {
    text += cli::format_number(0.001 * double(r));
    for (const auto& [prefix, rows] : blocks)
      for (int i = 0; i < rows[r].size(); ++i) text.append(",").append(cli::format_number(rows[r][i]));
    text += "\n";
  }
  return text;
}

// The q_, qd_ and qdd_ columns of `states` in such a CSV.
inline std::string states_csv(const std::vector<std::string>& names, const std::vector<support::JointState>& states) {
  std::vector<Eigen::VectorXd> q, qd, qdd;
  for (const auto& s : states) {
    q.push_back(s.q);
    qd.push_back(s.qd);
    qdd.push_back(s.qdd);
  }
  return joint_csv(names, {{"q_", q}, {"qd_", qd}, {"qdd_", qdd}});
}

// The columns `<prefix><joint>` of a CSV file, one vector per row.
inline std::vector<Eigen::VectorXd> csv_columns(const std::filesystem::path& file,
                                                const std::vector<std::string>& names, const std::string& prefix) {
  const auto table = cli::read_csv(file.string());
  const auto cols = cli::require_columns(table, cli::joint_columns(names, prefix));
  std::vector<Eigen::VectorXd> out;
  for (const auto& row : table.rows) {
    Eigen::VectorXd v(Eigen::Index(cols.size()));
    for (std::size_t i = 0; i < cols.size(); ++i) v[Eigen::Index(i)] = row[std::size_t(cols[i])];
    out.push_back(v);
  }
  return out;
}

// The message of the cli::InputError that `f` throws ("" if it throws none).
template <class F>
std::string input_error(F&& f) {
  try {
    f();
  } catch (const cli::InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace humandyn::testing
