// Running the humandyn binary from a test: a scratch folder per test, the binary's exit code and
// output, text files in and out, and a description's joint names (the CSV column suffixes).
// The binary is HUMANDYN_CLI, which the test target defines.
#pragma once

#include "humandyn/model.hpp"

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
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

}  // namespace humandyn::testing
