// Command-line arguments: `--key value`, `--flag` and positionals. Every option a subcommand reads is
// marked used; whatever is left is reported as unknown, so a typo never passes silently.
#pragma once

#include <map>
#include <optional>
#include <set>
#include <stdexcept>
#include <string>
#include <vector>

namespace humandyn::cli {

// An error the user made: printed as "humandyn <command>: <message>", exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// An error in an input file: the message names the file, line and column; exit code 1.
class InputError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class Args {
 public:
  // `flags` lists the options that take no value (e.g. "--json", "--quick").
  Args(std::vector<std::string> argv, const std::set<std::string>& flags);

  bool flag(const std::string& name);                               // --name present?
  std::optional<std::string> get(const std::string& name);          // --name VALUE (UsageError if repeated)
  std::vector<std::string> all(const std::string& name);            // every --name VALUE, in order
  std::string get_or(const std::string& name, const std::string& fallback);
  std::string require(const std::string& name);                     // UsageError if absent
  double number(const std::string& name, double fallback);          // UsageError if not a finite number
  long integer(const std::string& name, long fallback);
  std::vector<std::string> positionals();
  void finish() const;  // UsageError for any option or positional no one asked for

 private:
  std::map<std::string, std::vector<std::string>> values_;
  std::set<std::string> flags_set_;
  std::vector<std::string> positionals_;
  std::set<std::string> used_;
  bool positionals_used_ = false;
};

}  // namespace humandyn::cli
