// The subcommands of the humandyn command line. Each is `int run_<name>(Args&)`, returning the exit
// code; each lives in tools/cmd_<name>.cpp and is listed in main.cpp's table.
#pragma once

#include "cli/args.hpp"

#include <set>
#include <string>

namespace humandyn::cli {

struct Command {
  const char* name;
  int (*run)(Args&);
  const char* summary;
  std::set<std::string> flags;  // the options of this command that take no value, e.g. {"--help", "--json"}
};

}  // namespace humandyn::cli
