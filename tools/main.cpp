// humandyn: the command line. `humandyn <command> [options]`; `humandyn help` lists the commands.
#include "cli/commands.hpp"
#include "cli/urdf_source.hpp"
#include "humandyn/model.hpp"

#include <cstdio>
#include <exception>
#include <set>
#include <string>
#include <vector>

namespace humandyn::cli {
// One declaration per subcommand (tools/cmd_<name>.cpp); add it to the table below too.
int run_bench(Args& args);
int run_model(Args& args);
int run_id(Args& args);
int run_simulate(Args& args);
int run_stability(Args& args);
int run_fd(Args& args);
#ifdef HUMANDYN_WITH_URDF
int run_urdf2dh(Args& args);
#endif
int run_demo(Args& args);
}  // namespace humandyn::cli

namespace {

using humandyn::cli::Command;

// The table of subcommands, in the order `help` lists them.
const std::vector<Command>& commands() {
  static const std::vector<Command> table{
      {"bench",
       humandyn::cli::run_bench,
       "the main job: 1 kHz loop, error against run time, charts",
       {"--help", "--balance-inertia", "--quick"}},
      {"model",
       humandyn::cli::run_model,
       "print a model (joints, DH rows, masses, inertias) as a table or as JSON",
       {"--help", "--balance-inertia", "--json"}},
      {"id",
       humandyn::cli::run_id,
       "inverse dynamics: joint torques for every state of a CSV file",
       {"--help", "--balance-inertia"}},
      {"simulate",
       humandyn::cli::run_simulate,
       "step the body through time (euler, rk4, implicit), passive or tracking a motion with PD servos",
       {"--help", "--balance-inertia"}},
      {"stability",
       humandyn::cli::run_stability,
       "the stiff-and-extreme suite: stiff servos, light and heavy bodies, fast motion, long swings",
       {"--help", "--json", "--quick"}},
      {"fd",
       humandyn::cli::run_fd,
       "forward dynamics: joint accelerations for every state and torque of a CSV file",
       {"--help", "--balance-inertia"}},
#ifdef HUMANDYN_WITH_URDF
      {"urdf2dh",
       humandyn::cli::run_urdf2dh,
       "a URDF file as DH chains: the table of every chain, or --json",
       {"--help", "--balance-inertia", "--json"}},
#endif
      {"demo",
       humandyn::cli::run_demo,
       "the seed paper's scenarios beside its Table 2, with SVG drawings",
       {"--help", "--balance-inertia"}},
  };
  return table;
}

int help() {
  std::printf("usage: humandyn <command> [options]\n\ncommands:\n");
  for (const auto& c : commands()) std::printf("  %-10s %s\n", c.name, c.summary);
  std::printf("\n`humandyn <command> --help` describes a command's options.\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc < 2 || std::string(argv[1]) == "help" || std::string(argv[1]) == "--help") return help();
  const std::string name = argv[1];
  for (const auto& c : commands()) {
    if (name != c.name) continue;
    try {
      std::set<std::string> flags = c.flags;
      flags.insert(humandyn::cli::urdf_flags.begin(), humandyn::cli::urdf_flags.end());
      humandyn::cli::Args args(std::vector<std::string>(argv + 2, argv + argc), flags);
      return c.run(args);
    } catch (const humandyn::cli::UsageError& e) {
      std::fprintf(stderr, "humandyn %s: %s\n", name.c_str(), e.what());
      return 2;
    } catch (const humandyn::cli::InputError& e) {
      std::fprintf(stderr, "humandyn %s: %s\n", name.c_str(), e.what());
      return 1;
    } catch (const humandyn::ModelError& e) {
      std::fprintf(stderr, "humandyn %s: invalid model: %s\n", name.c_str(), e.what());
      return 1;
    } catch (const std::exception& e) {
      std::fprintf(stderr, "humandyn %s: %s\n", name.c_str(), e.what());
      return 1;
    }
  }
  std::fprintf(stderr, "humandyn: unknown command '%s' (try `humandyn help`)\n", name.c_str());
  return 2;
}
