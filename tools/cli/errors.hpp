// The two kinds of error the command line reports, each with its exit code (main.cpp).
#pragma once

#include <stdexcept>

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

}  // namespace humandyn::cli
