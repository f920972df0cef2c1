// The two kinds of error the command line reports, each with its exit code (main.cpp).
#pragma once

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>

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

// Whether standard output was closed when the command started (>&-): main then opens it on /dev/full, so
// that a result written there fails, as on a full disk, instead of vanishing.
inline bool standard_output_closed = false;

// Whether standard error was closed when the command started (2>&-): main then opens it on /dev/null, where
// messages go unread, but an output named as standard error's file (/dev/stderr) is refused when written.
inline bool standard_error_closed = false;

// Why writing standard output failed: its closing, or errno's reason.
inline std::string standard_output_failure() {
  return std::string("standard output: writing failed: ") +
         (standard_output_closed ? "it is closed (>&-)" : std::strerror(errno));
}

}  // namespace humandyn::cli
