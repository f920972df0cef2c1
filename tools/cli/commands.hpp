// The subcommands of the humandyn command line, each in tools/cmd_<name>.cpp: `add_<name>` registers the
// subcommand and its options (CLI11 writes its --help from them) and returns what runs it once the command
// line is parsed. Adding a command is a line in the table below; adding an option, a line in its add_<name>.
#pragma once

#include "cli/errors.hpp"
#include "cli/options.hpp"

#include <CLI/CLI.hpp>

#include <functional>

namespace humandyn::cli {

struct Command {
  CLI::App* app;             // the subcommand, with its options
  std::function<int()> run;  // runs it on the parsed options; returns the exit code
};

Command add_bench(CLI::App& humandyn);
Command add_model(CLI::App& humandyn);
Command add_id(CLI::App& humandyn);
Command add_simulate(CLI::App& humandyn);
Command add_stability(CLI::App& humandyn);
Command add_fd(CLI::App& humandyn);
Command add_motion(CLI::App& humandyn);
#ifdef HUMANDYN_WITH_URDF
Command add_urdf2dh(CLI::App& humandyn);
#endif
Command add_demo(CLI::App& humandyn);
Command add_view(CLI::App& humandyn);

// The table of subcommands, in the order `humandyn help` lists them.
inline constexpr Command (*commands[])(CLI::App&) = {
    add_bench,   add_model, add_id, add_simulate, add_stability, add_fd, add_motion,
#ifdef HUMANDYN_WITH_URDF
    add_urdf2dh,
#endif
    add_demo,    add_view,
};

}  // namespace humandyn::cli
