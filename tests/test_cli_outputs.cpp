// What the command line leaves on disk, and the external wrenches it takes (runs the binary):
//   - outputs are atomic: a run that fails half-way (bad input in row 3, an overflow after rows were
//     written) or is killed leaves a previous output file intact and no temporary file behind, and
//     outputs committed together are put back when a later one's rename fails;
//     `simulate` stopping at a divergence writes its partial trajectory on purpose, and says where;
//   - `--wrench LINK:F[@P]` on id, fd and simulate gives what the C++ API gives with the same wrenches,
//     and a 10 kg load in the hand of a horizontal arm adds 98.1 N times the reach at the shoulder.
#include "cli/atomic_file.hpp"
#include "cli/csv.hpp"
#include "cli/errors.hpp"
#include "cli/model_json.hpp"
#include "humandyn/algorithm/forward_dynamics.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/builders.hpp"
#include "support/cli_run.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

namespace test_cli_outputs {

namespace {

namespace fs = std::filesystem;
namespace hd = humandyn;
namespace ht = humandyn::testing;
using hd::cli::joint_columns;
using ht::csv_columns;
using ht::humandyn_cli;
using ht::joint_csv;
using ht::read_text;
using ht::Scratch;
using ht::states_csv;
using ht::write_text;
using M = hd::AnyModel<double>;

constexpr double pi = 3.14159265358979323846;
const std::string old_content = "this file was here before\n";

// The files of a folder whose names start with `stem` and are not `stem` itself (temporary files).
std::vector<std::string> leftovers(const fs::path& dir, const std::string& stem) {
  std::vector<std::string> found;
  for (const auto& e : fs::directory_iterator(dir)) {
    const std::string name = e.path().filename().string();
    if (name != stem && name.rfind(stem, 0) == 0) found.push_back(name);
  }
  return found;
}

class CliOutputs : public ::testing::Test {
 protected:
  hd::ModelDescription<double> desc = hd::human_description(hd::default_parameters());
  std::vector<std::string> names = ht::joint_names(desc);
};

// ---- the tracked reference ---------------------------------------------------------------------------

// simulate --track holds the reference at rest outside its rows: before the first row's t (here 5 s) the
// servo sees that row's pose with no velocity, whatever velocity the row gives, so two tracks that differ
// only in their rows' qd_ give the same trajectory up to then, bit for bit; from the first row on they
// differ.
TEST_F(CliOutputs, ATrackIsAtRestBeforeItsFirstRow) {
  Scratch dir;
  const auto rows = ht::random_states(int(names.size()), 2, 9, 0.3, 2.0, 5.0);
  const auto track = [&](bool moving) {
    std::string text = "t";
    for (const char* prefix : {"q_", "qd_"})
      for (const auto& c : joint_columns(names, prefix)) text += "," + c;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      text += "\n" + std::to_string(5 + r);
      for (const double x : rows[r].q) text += "," + hd::exact_number(x);
      for (const double x : rows[r].qd) text += "," + hd::exact_number(moving ? x : 0.0);
    }
    return text + "\n";
  };
  write_text(dir / "moving.csv", track(true));
  write_text(dir / "still.csv", track(false));
  for (const char* duration : {"4.9", "5.1"}) {
    for (const char* which : {"moving", "still"})
      ASSERT_EQ(humandyn_cli(dir, std::string("simulate --integrator implicit --dt 0.01 --duration ") + duration +
                                      " --track " + which + ".csv --out " + which + "_out.csv")
                    .exit_code,
                0);
    if (std::string(duration) == "4.9")
      EXPECT_EQ(read_text(dir / "moving_out.csv"), read_text(dir / "still_out.csv"));
    else
      EXPECT_NE(read_text(dir / "moving_out.csv"), read_text(dir / "still_out.csv"));
  }
}

// A track is read as id reads states: qdd_, tau_ and other columns (a phase) pass over without changing
// the run; a misspelt q_ column, a row on the left foot, rows too close in time for their slope and a
// reference beyond a step's bounds are input errors naming the cell, and leave an existing output as it
// was; base_ columns go unused, said so.
TEST_F(CliOutputs, ATrackReadsAsIdReadsStates) {
  Scratch dir;
  const auto rows = ht::random_states(int(names.size()), 3, 12, 0.3, 2.0, 5.0);
  // the rows' times, extra columns and their cells, and what row 2's cells of them say
  const auto track = [&](const std::vector<std::string>& times, const std::string& extra_header,
                         const std::string& extra_cells) {
    std::string text = "t";
    for (const auto& c : joint_columns(names, "q_")) text += "," + c;
    text += extra_header;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      text += "\n" + times[r];
      for (const double x : rows[r].q) text += "," + hd::exact_number(x);
      text += extra_cells;
    }
    return text + "\n";
  };
  const std::vector<std::string> times{"0", "0.1", "0.2"};
  std::string qdd_tau_header, qdd_tau_cells;
  for (const auto& c : joint_columns(names, "qdd_")) qdd_tau_header += "," + c, qdd_tau_cells += ",7";
  for (const auto& c : joint_columns(names, "tau_")) qdd_tau_header += "," + c, qdd_tau_cells += ",1e300";
  write_text(dir / "plain.csv", track(times, "", ""));
  write_text(dir / "extra.csv", track(times, ",phase,stance" + qdd_tau_header, ",swing,right" + qdd_tau_cells));
  const std::string run = "simulate --integrator implicit --dt 0.01 --duration 0.3 --track ";
  ASSERT_EQ(humandyn_cli(dir, run + "plain.csv --out plain_out.csv").exit_code, 0);
  const auto extra = humandyn_cli(dir, run + "extra.csv --out extra_out.csv");
  ASSERT_EQ(extra.exit_code, 0) << extra.err;
  EXPECT_EQ(extra.err.find("warning"), std::string::npos) << extra.err;
  EXPECT_EQ(read_text(dir / "plain_out.csv"), read_text(dir / "extra_out.csv"));

  write_text(dir / "base.csv", track(times, ",base_x,base_y,base_z", ",0.1,0,0"));
  const auto base = humandyn_cli(dir, run + "base.csv --out base_out.csv");
  ASSERT_EQ(base.exit_code, 0) << base.err;
  EXPECT_NE(base.err.find("humandyn simulate: warning: base.csv: the base_ columns are not used"), std::string::npos)
      << base.err;
  EXPECT_EQ(read_text(dir / "plain_out.csv"), read_text(dir / "base_out.csv"));

  write_text(dir / "kept.csv", "kept\n");
  const auto refused = [&](const std::string& file, const std::string& text, const std::string& message) {
    write_text(dir / file, text);
    const auto r = humandyn_cli(dir, run + file + " --out kept.csv");
    EXPECT_EQ(r.exit_code, 1) << file << ": " << r.err;
    EXPECT_NE(r.err.find(message), std::string::npos) << file << ": " << r.err;
    EXPECT_EQ(read_text(dir / "kept.csv"), "kept\n") << file;
  };
  refused("misspelt.csv", track(times, ",q_nose", ",0"), "misspelt.csv: line 1, column 18 'q_nose': unknown column");
  refused("left.csv", track(times, ",stance", ",left"),
          "left.csv: line 2, column 18 'stance': the simulated body stands on its right foot throughout");
  refused("close.csv", track({"0", "5e-324", "1e-323"}, "", ""),
          "close.csv: line 3, column 2 'q_" + names[0] +
              "': the velocity from the slope between the rows at t = 0 and 5e-324 s (");
  // a reference beyond what a step allows, given or from the slopes: refused by its cell, not a runaway
  // that names another joint once the run has begun
  const auto pose_rows = [&](const std::string& header_extra, const std::vector<std::string>& rows_text) {
    std::string text = "t";
    for (const auto& c : joint_columns(names, "q_")) text += "," + c;
    text += header_extra;
    for (const auto& row : rows_text) text += "\n" + row;
    return text + "\n";
  };
  std::string zeros;
  for (std::size_t i = 1; i < names.size(); ++i) zeros += ",0";
  refused("far.csv", pose_rows("", {"0,0" + zeros, "0.1,2e4" + zeros}),
          "far.csv: line 3, column 2 'q_" + names[0] + "': 20000 rad is beyond the 10000 rad a step allows");
  refused("fast.csv", pose_rows("", {"0,0" + zeros, "1e-6,1" + zeros}),
          "fast.csv: line 3, column 2 'q_" + names[0] +
              "': the velocity from the slope between the rows at t = 0 and 1e-06 s (1 rad over 1e-06 s) is 1e+06 "
              "rad/s, beyond the 10000 rad/s a step allows");
  std::string qd_header, qd_cells;
  for (const auto& c : joint_columns(names, "qd_")) qd_header += "," + c, qd_cells += qd_cells.empty() ? ",-1e5" : ",0";
  refused("spin.csv", pose_rows(qd_header, {"0,0" + zeros + qd_cells}),
          "spin.csv: line 2, column " + std::to_string(names.size() + 2) + " 'qd_" + names[0] +
              "': -1e+05 rad/s is beyond the 10000 rad/s a step allows");
}

// ---- atomic outputs -----------------------------------------------------------------------------------

// With a scene, the track's columns of a locked joint go unused: they may be left out, and where they
// would move the joint stderr says so (as id and fd do). The trajectory is the same either way.
TEST_F(CliOutputs, ATrackThroughAScenesLockedJoints) {
  Scratch dir;
  const auto rows = ht::random_states(int(names.size()), 3, 11, 0.3, 2.0, 5.0);
  // the legs (the scene's locked joints: 1-4 and 13-16, 1-based) with or without their columns
  const auto leg = [](std::size_t i) { return i < 4 || i >= 12; };
  const auto track = [&](bool legs) {
    std::string text = "t";
    for (std::size_t i = 0; i < names.size(); ++i)
      if (legs || !leg(i)) text += ",q_" + names[i];
    for (std::size_t r = 0; r < rows.size(); ++r) {
      text += "\n" + hd::exact_number(0.1 * double(r));
      for (std::size_t i = 0; i < names.size(); ++i)
        if (legs || !leg(i)) text += "," + hd::exact_number(r == 0 && leg(i) ? 0.0 : rows[r].q[Eigen::Index(i)]);
    }
    return text + "\n";
  };
  write_text(dir / "full.csv", track(true));
  write_text(dir / "arms.csv", track(false));
  const auto with = humandyn_cli(dir, "simulate --scene upper_body --duration 0.3 --track full.csv --out a.csv");
  ASSERT_EQ(with.exit_code, 0) << with.err;
  EXPECT_NE(with.err.find("humandyn simulate: warning: full.csv: line 3: q_" + names[0] + " is " +
                          hd::exact_number(rows[1].q[0]) + ", not used: the scene 'upper_body' holds joint '" +
                          names[0] + "' still at 0 rad"),
            std::string::npos)
      << with.err;
  const auto without = humandyn_cli(dir, "simulate --scene upper_body --duration 0.3 --track arms.csv --out b.csv");
  ASSERT_EQ(without.exit_code, 0) << without.err;
  EXPECT_EQ(without.err.find("warning"), std::string::npos) << without.err;
  EXPECT_EQ(read_text(dir / "a.csv"), read_text(dir / "b.csv"));
  // without a scene, every joint's column is needed
  const auto unscened = humandyn_cli(dir, "simulate --duration 0.3 --track arms.csv");
  EXPECT_EQ(unscened.exit_code, 1);
  EXPECT_NE(unscened.err.find("missing column 'q_" + names[0] + "'"), std::string::npos) << unscened.err;
}

TEST_F(CliOutputs, AFailingIdLeavesThePreviousOutputIntact) {
  Scratch dir;
  auto states = ht::random_states(int(names.size()), 5, 11, 1.0, 2.0, 5.0);
  // a NaN in row 3 (its first angle, after t): refused while reading
  std::string text = states_csv(names, states);
  std::size_t cell = 0;
  for (int line = 0; line < 3; ++line) cell = text.find('\n', cell) + 1;
  cell = text.find(',', cell) + 1;
  text.replace(cell, text.find(',', cell) - cell, "nan");
  write_text(dir / "nan.csv", text);
  write_text(dir / "tau.csv", old_content);
  const auto run = humandyn_cli(dir, "id --in nan.csv --out tau.csv");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_NE(run.err.find("nan.csv: line 4"), std::string::npos) << run.err;
  EXPECT_EQ(read_text(dir / "tau.csv"), old_content);
  EXPECT_TRUE(leftovers(dir.dir(), "tau.csv").empty());

  // a velocity whose torque overflows in row 3: found after rows 1 and 2 were written
  states[2].qd[3] = 1e200;
  write_text(dir / "huge.csv", states_csv(names, states));
  const auto late = humandyn_cli(dir, "id --in huge.csv --out tau.csv");
  EXPECT_EQ(late.exit_code, 1) << late.err;
  EXPECT_NE(late.err.find("overflows"), std::string::npos) << late.err;
  EXPECT_EQ(read_text(dir / "tau.csv"), old_content);
  EXPECT_TRUE(leftovers(dir.dir(), "tau.csv").empty());

  // the same states without the fault replace the file
  states[2].qd[3] = 0.5;
  write_text(dir / "good.csv", states_csv(names, states));
  EXPECT_EQ(humandyn_cli(dir, "id --in good.csv --out tau.csv").exit_code, 0);
  EXPECT_EQ(csv_columns(dir / "tau.csv", names, "tau_").size(), 5u);
  EXPECT_TRUE(leftovers(dir.dir(), "tau.csv").empty());
}

// Outputs committed together whose last rename fails (a folder put where its file goes, after the check):
// the renames before it are put back, a file replaced with its old text and a new one removed, and no
// second name is left behind. Once, they stayed replaced beside the old second output.
TEST_F(CliOutputs, ALaterRenameThatFailsPutsTheEarlierOutputsBack) {
  Scratch dir;
  for (const bool replaces : {true, false}) {
    const std::string first = replaces ? "a.csv" : "new.csv", second = replaces ? "a.json" : "new.json";
    if (replaces) write_text(dir / first, old_content);
    {
      hd::cli::AtomicFile csv((dir / first).string()), json((dir / second).string());
      csv.write("t\n0\n");
      json.write("{}\n");
      fs::create_directories(dir / second / "in");  // a folder that holds something: no file replaces it
      EXPECT_THROW(hd::cli::commit_together({&csv, &json}), hd::cli::InputError) << first;
    }
    if (replaces)
      EXPECT_EQ(read_text(dir / first), old_content);
    else
      EXPECT_FALSE(fs::exists(dir / first));
    EXPECT_TRUE(leftovers(dir.dir(), first).empty()) << first;
    EXPECT_TRUE(leftovers(dir.dir(), second).empty()) << second;
  }
  // with nothing in the way, both take their places and the replaced file's second name goes
  write_text(dir / "b.csv", old_content);
  {
    hd::cli::AtomicFile csv((dir / "b.csv").string()), json((dir / "b.json").string());
    csv.write("t\n0\n");
    json.write("{}\n");
    hd::cli::commit_together({&csv, &json});
  }
  EXPECT_EQ(read_text(dir / "b.csv"), "t\n0\n");
  EXPECT_EQ(read_text(dir / "b.json"), "{}\n");
  EXPECT_TRUE(leftovers(dir.dir(), "b.csv").empty());
}

// A stop (SIGINT, SIGTERM) while a command writes its outputs is held: before the commit, the outputs and
// the folder made are rolled back and the process then ends by the stop (bench --csv's path); during the
// commit, every output is put in place first. Each case runs in a child process, which the stop ends.
TEST_F(CliOutputs, AStopWhileOutputsAreWrittenRollsThemBackThenEndsTheProcess) {
  Scratch dir;
  for (const int stop : {SIGINT, SIGTERM})
    for (const bool before_commit : {true, false}) {
      const fs::path folder = dir / "results" / "deep";
      const pid_t child = fork();
      ASSERT_GE(child, 0);
      if (child == 0) {  // (the child: no gtest assertion, its exit status says it all)
        [&] {
          const hd::cli::HeldStops stops;
          hd::cli::MadeFolders made;
          if (!made.make(folder.string()).empty()) std::_Exit(10);
          hd::cli::AtomicFile csv((folder / "a.csv").string()), json((folder / "a.json").string());
          csv.write("t\n0\n");
          json.write("{}\n");
          if (before_commit) std::raise(stop);
          if (stops.held() != before_commit) std::_Exit(11);
          if (!hd::cli::commit_together({&csv, &json}, &stops)) return;
          if (before_commit) std::_Exit(12);  // (published though a stop was held)
          std::raise(stop);                   // (while the files take their names, as it were: held until the end)
          if (!stops.held()) std::_Exit(13);
          made.keep();
        }();
        std::_Exit(0);  // (not reached when the stop ended the process)
      }
      int status = 0;
      ASSERT_EQ(waitpid(child, &status, 0), child);
      EXPECT_TRUE(WIFSIGNALED(status) && WTERMSIG(status) == stop)
          << "stop " << stop << ", before the commit " << before_commit << ": status " << status;
      if (before_commit) {
        EXPECT_FALSE(fs::exists(dir / "results")) << stop;  // every folder made, and every file, gone
      } else {
        EXPECT_EQ(read_text(folder / "a.csv"), "t\n0\n") << stop;
        EXPECT_EQ(read_text(folder / "a.json"), "{}\n") << stop;
        fs::remove_all(dir / "results");
      }
    }
  // and with none held, the actions are the process's own again: an ignored stop stays ignored
  const pid_t child = fork();
  ASSERT_GE(child, 0);
  if (child == 0) {
    std::signal(SIGTERM, SIG_IGN);
    { const hd::cli::HeldStops stops; }
    std::raise(SIGTERM);
    std::_Exit(0);
  }
  int status = 0;
  ASSERT_EQ(waitpid(child, &status, 0), child);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << status;
}

TEST_F(CliOutputs, ALinkIsFollowedAndAPipeIsWrittenInPlace) {
  // a symbolic link: the file it points to is replaced, the link stays a link
  Scratch dir;
  write_text(dir / "good.csv", states_csv(names, ht::random_states(int(names.size()), 3, 5, 1.0, 2.0, 5.0)));
  ASSERT_EQ(humandyn_cli(dir, "id --in good.csv --out plain.csv").exit_code, 0);
  const std::string want = read_text(dir / "plain.csv");
  write_text(dir / "target.csv", old_content);
  fs::create_symlink("target.csv", dir / "link.csv");
  const auto linked = humandyn_cli(dir, "id --in good.csv --out link.csv");
  ASSERT_EQ(linked.exit_code, 0) << linked.err;
  EXPECT_TRUE(fs::is_symlink(dir / "link.csv"));
  EXPECT_EQ(read_text(dir / "target.csv"), want);
  EXPECT_TRUE(leftovers(dir.dir(), "target.csv").empty());

  // a pipe (FIFO) stays a pipe, and its reader gets the whole output
  ASSERT_EQ(::mkfifo((dir / "pipe").c_str(), 0644), 0);
  std::string got;
  std::thread reader([&] { got = read_text(dir / "pipe"); });
  const auto piped = humandyn_cli(dir, "id --in good.csv --out pipe");
  reader.join();
  EXPECT_EQ(piped.exit_code, 0) << piped.err;
  EXPECT_TRUE(fs::is_fifo(dir / "pipe"));
  EXPECT_EQ(got, want);

  // a folder is refused by name
  fs::create_directory(dir / "folder");
  const auto folder = humandyn_cli(dir, "id --in good.csv --out folder");
  EXPECT_EQ(folder.exit_code, 1);
  EXPECT_NE(folder.err.find("folder: is a folder, not a file"), std::string::npos) << folder.err;
  EXPECT_TRUE(fs::is_directory(dir / "folder"));
}

// An output never replaces a file the command reads (or another output), however the path is spelt; an
// empty value and standard input read twice are usage errors
TEST_F(CliOutputs, AnOutputNeverReplacesAnInput) {
  Scratch dir;
  const auto random = ht::random_states(int(names.size()), 3, 5, 1.0, 2.0, 5.0);
  write_text(dir / "good.csv", states_csv(names, random));
  std::vector<Eigen::VectorXd> q, qd;
  for (const auto& r : random) q.push_back(r.q), qd.push_back(r.qd);
  write_text(dir / "track.csv", joint_csv(names, {{"q_", q}, {"qd_", qd}}));
  write_text(dir / "tau.csv", joint_csv(names, {{"q_", q}, {"qd_", qd}, {"tau_", qd}}));
  write_text(dir / "body.json", hd::cli::write_model_json(desc));
  const std::string body = read_text(dir / "body.json"), states = read_text(dir / "good.csv"),
                    track = read_text(dir / "track.csv");
  fs::create_symlink("body.json", dir / "alias.json");
  fs::create_directory(dir / "sub");
  struct Case {
    std::string command, message;
  };
  const Case cases[] = {
      {"id --model body.json --in good.csv --out body.json", "body.json is given to --model and --out"},
      {"id --model body.json --in good.csv --out ./body.json", "./body.json is given to --model and --out"},
      {"fd --model body.json --in tau.csv --out alias.json", "alias.json is given to --model and --out"},
      {"view good.csv --model body.json --out body.json", "body.json is given to --model and --out"},
      {"simulate --track track.csv --duration 0.002 --out track.csv", "track.csv is given to --track and --out"},
      // two outputs to one file not yet made, however spelt: refused before either is written
      {"motion import clip.bvh --out new.csv --model-out ./new.csv", "new.csv is given to --out and --model-out"},
      {"model --model body.json --urdf sub/../body.json --json", "sub/../body.json is given to --model and --urdf"},
  };
  for (const auto& c : cases) {
    SCOPED_TRACE(c.command);
    const auto run = humandyn_cli(dir, c.command);
    EXPECT_EQ(run.exit_code, 2) << run.err;
    EXPECT_NE(run.err.find(c.message + ": an output may not replace another argument's file"), std::string::npos)
        << run.err;
    EXPECT_EQ(read_text(dir / "body.json"), body);
    EXPECT_EQ(read_text(dir / "good.csv"), states);
    EXPECT_EQ(read_text(dir / "track.csv"), track);
    EXPECT_FALSE(fs::exists(dir / "new.csv"));
  }
  const auto empty = humandyn_cli(dir, "id --in good.csv --out ''");
  EXPECT_EQ(empty.exit_code, 2);
  EXPECT_NE(empty.err.find("--out is given an empty value"), std::string::npos) << empty.err;
  const auto twice = humandyn_cli(dir, "view - --torques - --out page.html");
  EXPECT_EQ(twice.exit_code, 2);
  EXPECT_NE(twice.err.find("states and --torques both read standard input ('-'): only one may"), std::string::npos)
      << twice.err;
  // a file the command names itself (in its output folder) that is an input through a link: refused
  fs::create_directory(dir / "drawings");
  fs::create_symlink("../body.json", dir / "drawings/body_standing.csv");
  const auto planted = humandyn_cli(dir, "demo --model body.json --out drawings");
  EXPECT_EQ(planted.exit_code, 2);
  EXPECT_NE(planted.err.find("is given to --model: an output may not replace another argument's file"),
            std::string::npos)
      << planted.err;
  EXPECT_EQ(read_text(dir / "body.json"), body);
  // bench's outputs, checked before the run: --csv a folder, --json none of its files
  const auto csv_file = humandyn_cli(dir, "bench --quick --csv good.csv");
  EXPECT_EQ(csv_file.exit_code, 2);
  EXPECT_NE(csv_file.err.find("--csv good.csv is not a folder that can be made"), std::string::npos) << csv_file.err;
  // nor through a link to nothing, nor --json as a folder inside it (d/), once refused only after the run
  fs::create_symlink("nowhere", dir / "no_folder");
  const auto unmade = humandyn_cli(dir, "bench --quick --csv no_folder/results");
  EXPECT_EQ(unmade.exit_code, 2);
  EXPECT_NE(unmade.err.find("--csv no_folder/results is not a folder that can be made: "), std::string::npos)
      << unmade.err;
  EXPECT_NE(unmade.err.find("/no_folder is a symbolic link to nothing"), std::string::npos) << unmade.err;
  for (const char* json : {"d/", "d/.", "d/e/.."}) {
    const auto folder = humandyn_cli(dir, std::string("bench --quick --csv d/e --json ") + json);
    EXPECT_EQ(folder.exit_code, 2) << json;
    EXPECT_NE(folder.err.find(std::string("--json ") + json + " is a folder: the results go to a file"),
              std::string::npos)
        << folder.err;
    EXPECT_FALSE(fs::exists(dir / "d"));
  }
  // nor one where it may not be made (/proc/sys takes no new folder, root's included): said before the
  // run, which would otherwise be lost at its end
  if (::access("/proc/sys", W_OK) != 0) {
    const auto denied = humandyn_cli(dir, "bench --quick --csv /proc/sys/results");
    EXPECT_EQ(denied.exit_code, 2);
    EXPECT_NE(denied.err.find("--csv /proc/sys/results is not a folder that can be made: /proc/sys: Permission denied"),
              std::string::npos)
        << denied.err;
    EXPECT_EQ(denied.out, "") << "refused before the run";
  } else {
    std::cout << "(this system lets /proc/sys take folders: the refusal of an unwritable --csv folder is not tried)\n";
  }
  const auto inside = humandyn_cli(dir, "bench --quick --csv results --json results/bench_loop.csv");
  EXPECT_EQ(inside.exit_code, 2);
  EXPECT_NE(inside.err.find("results/bench_loop.csv are one file: one output would replace the other"),
            std::string::npos)
      << inside.err;
  EXPECT_FALSE(fs::exists(dir / "results")) << "a usage error makes no folder";
  const auto no_folder = humandyn_cli(dir, "bench --quick --json nowhere/bench.json");
  EXPECT_EQ(no_folder.exit_code, 2);
  EXPECT_NE(no_folder.err.find("--json nowhere/bench.json: no folder nowhere"), std::string::npos) << no_folder.err;
  const auto demo_stdout = humandyn_cli(dir, "demo --out -");
  EXPECT_EQ(demo_stdout.exit_code, 2);
  EXPECT_NE(demo_stdout.err.find("--out -: the drawings and tables go to a folder"), std::string::npos)
      << demo_stdout.err;
  EXPECT_FALSE(fs::exists(dir / "-"));
  // standard output on an input's file (appended to, or written in place): refused whatever the command
  // writes there, the input intact
  const std::string in_dir = "cd '" + dir.dir().string() + "' && ";
  for (const char* redirect : {">>", "1<>"})
    for (const char* out : {"", " --out /dev/stdout", " --out good.csv"}) {
      SCOPED_TRACE(std::string(redirect) + out);
      const int code = std::system((in_dir + "'" HUMANDYN_CLI "' id --model body.json --in good.csv" + out + " " +
                                    redirect + " good.csv 2> onto.txt")
                                       .c_str());
      EXPECT_EQ(WEXITSTATUS(code), 2);
      EXPECT_NE(read_text(dir / "onto.txt")
                    .find("good.csv is given to --in and standard output writes to it: an output may not replace "
                          "another argument's file"),
                std::string::npos)
          << read_text(dir / "onto.txt");
      EXPECT_EQ(read_text(dir / "good.csv"), states);
    }
  // standard input read from the file standard output writes to: refused alike
  const int stdin_code = std::system(
      (in_dir + "'" HUMANDYN_CLI "' id --model body.json --in - < good.csv >> good.csv 2> onto.txt").c_str());
  EXPECT_EQ(WEXITSTATUS(stdin_code), 2);
  EXPECT_NE(read_text(dir / "onto.txt").find("standard input's file is given to --in and standard output writes to it"),
            std::string::npos)
      << read_text(dir / "onto.txt");
  EXPECT_EQ(read_text(dir / "good.csv"), states);
  // a built-in body's name is no file: standard output may go to a file of that name
  ASSERT_EQ(std::system((in_dir + "'" HUMANDYN_CLI "' model --model female --json > female").c_str()), 0);
  EXPECT_NE(read_text(dir / "female").find("\"joints\""), std::string::npos);
  // /dev/stdout when standard output is a pipe: written into the pipe
  const std::string command =
      "cd '" + dir.dir().string() + "' && '" HUMANDYN_CLI "' id --model body.json --in good.csv --out /dev/stdout";
  std::FILE* pipe = ::popen(command.c_str(), "r");
  ASSERT_NE(pipe, nullptr);
  std::string piped;
  for (int c; (c = std::fgetc(pipe)) != EOF;) piped.push_back(char(c));
  EXPECT_EQ(::pclose(pipe), 0);
  EXPECT_EQ(piped.rfind("t,tau_", 0), 0u) << piped;
  // /dev/stdout when standard output is a file: written through it, not put in its place
  ASSERT_EQ(std::system((in_dir + "{ echo before; '" HUMANDYN_CLI
                                  "' model --urdf /dev/stdout --json; echo after; } > both.txt 2> /dev/null")
                            .c_str()),
            0);
  const std::string both = read_text(dir / "both.txt");
  EXPECT_EQ(both.rfind("before\n", 0), 0u) << both;
  EXPECT_NE(both.find("<robot"), std::string::npos) << both;
  EXPECT_NE(both.find("\"joints\""), std::string::npos) << both;
  EXPECT_EQ(both.substr(both.size() - 6), "after\n") << both;
  // a standard output that cannot take the result: an error, not silence
  const int full = std::system((in_dir + "'" HUMANDYN_CLI "' model --json > /dev/full 2> full.txt").c_str());
  EXPECT_TRUE(WIFEXITED(full) && WEXITSTATUS(full) == 1);
  EXPECT_NE(read_text(dir / "full.txt").find("humandyn model: standard output: writing failed"), std::string::npos);
  // nor a closed one (>&-), where the result once vanished with exit code 0; a command that writes
  // nothing there runs
  const int closed = std::system((in_dir + "'" HUMANDYN_CLI "' model --json >&- 2> closed.txt").c_str());
  EXPECT_TRUE(WIFEXITED(closed) && WEXITSTATUS(closed) == 1);
  EXPECT_EQ(read_text(dir / "closed.txt"), "humandyn model: standard output: writing failed: it is closed (>&-)\n");
  const int closed_id =
      std::system((in_dir + "'" HUMANDYN_CLI "' id --model body.json --in good.csv >&- 2> closed.txt").c_str());
  EXPECT_TRUE(WIFEXITED(closed_id) && WEXITSTATUS(closed_id) == 1);
  EXPECT_EQ(read_text(dir / "closed.txt"), "humandyn id: standard output: writing failed: it is closed (>&-)\n");
  // nor a closed standard error named as the output (2>&-, where the messages go unread): exit code 1, not
  // a result gone without a word
  const int closed_err = std::system(
      (in_dir + "'" HUMANDYN_CLI "' id --model body.json --in good.csv --out /dev/stderr 2>&- > closed_err.txt")
          .c_str());
  EXPECT_TRUE(WIFEXITED(closed_err) && WEXITSTATUS(closed_err) == 1);
  EXPECT_EQ(read_text(dir / "closed_err.txt"), "");
  // model always prints: with standard output closed it writes no URDF file either; simulate, whose
  // summary goes there beside its file, says it on stderr and runs
  const int closed_model =
      std::system((in_dir + "'" HUMANDYN_CLI "' model --model body.json --urdf closed.urdf >&- 2> /dev/null").c_str());
  EXPECT_TRUE(WIFEXITED(closed_model) && WEXITSTATUS(closed_model) == 1);
  EXPECT_FALSE(fs::exists(dir / "closed.urdf"));
  const int closed_run = std::system(
      (in_dir + "'" HUMANDYN_CLI "' simulate --integrator euler --duration 0.002 --out closed_run.csv >&- 2> run.txt")
          .c_str());
  EXPECT_TRUE(WIFEXITED(closed_run) && WEXITSTATUS(closed_run) == 0);
  EXPECT_TRUE(fs::exists(dir / "closed_run.csv"));
  EXPECT_NE(read_text(dir / "run.txt").find("euler, "), std::string::npos) << read_text(dir / "run.txt");
  const int to_file =
      std::system((in_dir + "'" HUMANDYN_CLI "' id --model body.json --in good.csv --out closed.csv >&-").c_str());
  EXPECT_TRUE(WIFEXITED(to_file) && WEXITSTATUS(to_file) == 0);
  EXPECT_TRUE(fs::exists(dir / "closed.csv"));
  // a dangling link among a command's own files names the file it would make: refused before any is written
  fs::create_directory(dir / "dangling");
  fs::create_symlink("default_standing.csv", dir / "dangling/paper_arm_forward.svg");
  const auto dangling = humandyn_cli(dir, "demo --out dangling");
  EXPECT_EQ(dangling.exit_code, 2);
  EXPECT_NE(dangling.err.find("are one file: one output would replace the other"), std::string::npos) << dangling.err;
  EXPECT_FALSE(fs::exists(dir / "dangling/default_standing.csv"));
  // a folder where one of them goes: refused before any is written
  fs::create_directories(dir / "clash/default_standing.svg");
  const auto clash = humandyn_cli(dir, "demo --out clash");
  EXPECT_EQ(clash.exit_code, 1);
  EXPECT_NE(clash.err.find("clash/default_standing.svg: is a folder, not a file"), std::string::npos) << clash.err;
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "clash"), fs::directory_iterator()), 1);
  // one that cannot be made (a link into a folder that does not exist), found only when it is written:
  // the files before it are not left behind either
  fs::create_directory(dir / "nowhere");
  fs::create_symlink("/nonexistent/x", dir / "nowhere/default_arm_forward.csv");
  const auto nowhere = humandyn_cli(dir, "demo --out nowhere");
  EXPECT_EQ(nowhere.exit_code, 1);
  EXPECT_NE(nowhere.err.find("nowhere/default_arm_forward.csv"), std::string::npos) << nowhere.err;
  EXPECT_EQ(std::distance(fs::directory_iterator(dir / "nowhere"), fs::directory_iterator()), 1);
  // a standard output that cannot take a command's report (fmt's writes): said as above
  const int report =
      std::system((in_dir + "'" HUMANDYN_CLI "' demo --out full_demo > /dev/full 2> report.txt").c_str());
  EXPECT_TRUE(WIFEXITED(report) && WEXITSTATUS(report) == 1);
  EXPECT_NE(
      read_text(dir / "report.txt").find("humandyn demo: standard output: writing failed: No space left on device"),
      std::string::npos)
      << read_text(dir / "report.txt");
  EXPECT_TRUE(fs::is_empty(dir / "full_demo"));  // its files are not written either
  // standard input read as '-' is an input too
  const auto from_stdin = humandyn_cli(dir, "id --model body.json --in - --out good.csv < good.csv");
  EXPECT_EQ(from_stdin.exit_code, 2);
  EXPECT_NE(from_stdin.err.find("good.csv is given to --in (standard input) and --out"), std::string::npos)
      << from_stdin.err;
  EXPECT_EQ(read_text(dir / "good.csv"), states);
  // values that name no file (a method, a title) are not outputs' rivals
  EXPECT_EQ(humandyn_cli(dir, "simulate --duration 0.002 --integrator euler --out euler").exit_code, 0);
  EXPECT_EQ(humandyn_cli(dir, "view good.csv --model body.json --title page.html --out page.html").exit_code, 0);
  // a replaced file keeps its permissions
  fs::permissions(dir / "euler", fs::perms::owner_read | fs::perms::owner_write);
  EXPECT_EQ(humandyn_cli(dir, "simulate --duration 0.002 --integrator euler --out euler").exit_code, 0);
  EXPECT_EQ(fs::status(dir / "euler").permissions(), fs::perms::owner_read | fs::perms::owner_write);
  // help that standard output does not take: an error
  const int help = std::system((in_dir + "'" HUMANDYN_CLI "' help id > /dev/full 2> help.txt").c_str());
  EXPECT_TRUE(WIFEXITED(help) && WEXITSTATUS(help) == 1);
  EXPECT_NE(read_text(dir / "help.txt").find("standard output: writing failed"), std::string::npos);
  // a fresh output, and one replacing an earlier output of its own, are written
  EXPECT_EQ(humandyn_cli(dir, "id --model body.json --in good.csv --out out.csv").exit_code, 0);
  EXPECT_EQ(humandyn_cli(dir, "id --model body.json --in good.csv --out out.csv").exit_code, 0);
}

TEST_F(CliOutputs, AKilledSimulateLeavesThePreviousOutputIntact) {
  Scratch dir;
  write_text(dir / "trajectory.csv", old_content);
  const pid_t pid = ::fork();
  ASSERT_GE(pid, 0);
  if (pid == 0) {
    // a run of many minutes, killed after a moment
    if (::chdir(dir.dir().c_str()) != 0) ::_exit(127);
    ::execl(HUMANDYN_CLI, HUMANDYN_CLI, "simulate", "--integrator", "rk4", "--dt", "1e-4", "--duration", "1e5", "--out",
            "trajectory.csv", static_cast<char*>(nullptr));
    ::_exit(127);
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(700));
  ASSERT_EQ(::kill(pid, SIGKILL), 0);
  int status = 0;
  ASSERT_EQ(::waitpid(pid, &status, 0), pid);
  ASSERT_TRUE(WIFSIGNALED(status)) << "the simulation ended before it was killed";
  EXPECT_EQ(read_text(dir / "trajectory.csv"), old_content);
  EXPECT_TRUE(leftovers(dir.dir(), "trajectory.csv").empty());
}

TEST_F(CliOutputs, AModelRefusedLeavesThePreviousUrdfIntact) {
  Scratch dir;
  write_text(dir / "model.urdf", old_content);
  // a negative mass: refused when the model is built, before anything is written
  hd::ModelDescription<double> bad = desc;
  bad.joints[3].body.mass = -1;
  write_text(dir / "bad.json", hd::cli::write_model_json(bad));
  const auto run = humandyn_cli(dir, "model --model bad.json --urdf model.urdf");
  EXPECT_EQ(run.exit_code, 1) << run.err;
  EXPECT_EQ(read_text(dir / "model.urdf"), old_content);
  EXPECT_TRUE(leftovers(dir.dir(), "model.urdf").empty());
}

TEST_F(CliOutputs, ASimulationThatDivergesWritesItsPartialTrajectoryAndSaysWhere) {
  Scratch dir;
  // an undamped servo with an explicit step too long for the light feet: the state runs away within a few steps
  std::string motion = "t";
  for (const auto& c : joint_columns(names, "q_")) motion += "," + c;
  motion += "\n0";
  for (std::size_t i = 0; i < names.size(); ++i) motion += ",0.3";
  write_text(dir / "motion.csv", motion + "\n");
  write_text(dir / "trajectory.csv", old_content);
  const auto run = humandyn_cli(
      dir,
      "simulate --integrator euler --dt 0.01 --duration 20 --track motion.csv --kp 1000 --kd 0 --out trajectory.csv");
  EXPECT_EQ(run.exit_code, 3) << run.err;
  EXPECT_NE(run.err.find("stopped at t = "), std::string::npos) << run.err;
  EXPECT_NE(run.err.find("trajectory.csv holds the partial trajectory"), std::string::npos) << run.err;
  // our own reader reads it; only its last row says the run stopped there
  const auto table = hd::cli::read_csv((dir / "trajectory.csv").string());
  const int stopped = table.require_column("stopped");
  ASSERT_GE(table.rows.size(), 2u);
  for (std::size_t r = 0; r + 1 < table.rows.size(); ++r) EXPECT_EQ(table.rows[r][std::size_t(stopped)], 0) << r;
  EXPECT_EQ(table.rows.back()[std::size_t(stopped)], 1);
  EXPECT_LT(table.rows.back()[0], 20.0);
  EXPECT_TRUE(leftovers(dir.dir(), "trajectory.csv").empty());

  // a trajectory that cannot be written: both the failed write and why the run stopped are said
  const auto full = humandyn_cli(
      dir, "simulate --integrator euler --dt 0.01 --duration 20 --track motion.csv --kp 1000 --kd 0 --out /dev/full");
  EXPECT_EQ(full.exit_code, 1) << full.err;
  EXPECT_NE(full.err.find("stopped at t = "), std::string::npos) << full.err;
  EXPECT_NE(full.err.find("/dev/full"), std::string::npos) << full.err;
  EXPECT_EQ(full.err.find("holds the partial trajectory"), std::string::npos) << full.err;

  // a run that finishes: stopped is 0 on every row
  EXPECT_EQ(humandyn_cli(dir, "simulate --duration 0.01 --out trajectory.csv").exit_code, 0);
  const auto done = hd::cli::read_csv((dir / "trajectory.csv").string());
  EXPECT_EQ(done.rows.size(), 11u);
  for (const auto& row : done.rows) EXPECT_EQ(row.back(), 0);
}

// ---- --wrench ------------------------------------------------------------------------------------------

// The wrenches as the API takes them: the force (world) at a point fixed on the link, whose world
// coordinates at the first state are `point0`, through wrench_from_world.
hd::LinkWrenches<M> api_wrenches(const M& model, hd::Data<M>& data, const Eigen::VectorXd& q0, const Eigen::VectorXd& q,
                                 int link, const hd::Vec3<double>& force, const hd::Vec3<double>& point0) {
  hd::forward_kinematics(model, data, q0);
  const hd::Vec3<double> on_link = data.oMi[std::size_t(link)].inverse() * point0;
  hd::forward_kinematics(model, data, q);
  hd::LinkWrenches<M> fext(std::size_t(model.size()));
  fext[std::size_t(link)] = hd::wrench_from_world(data, link, force, data.oMi[std::size_t(link)] * on_link);
  return fext;
}

TEST_F(CliOutputs, IdAndFdWithAWrenchGiveWhatTheApiGives) {
  Scratch dir;
  const M model(desc);
  hd::Data<M> data(model);
  const auto states = ht::random_states(int(names.size()), 6, 5, 1.0, 2.0, 5.0);
  write_text(dir / "states.csv", states_csv(names, states));
  const int link = 8;  // l_forearm
  const hd::Vec3<double> force(12.5, -40, -98.1), point(0.1, 0.35, 1.2);
  const std::string spec = "--wrench " + desc.joints[link].link_name + ":12.5,-40,-98.1@0.1,0.35,1.2 ";
  const auto id = humandyn_cli(dir, "id " + spec + "--in states.csv --out tau.csv");
  ASSERT_EQ(id.exit_code, 0) << id.err;
  const auto tau = csv_columns(dir / "tau.csv", names, "tau_");
  ASSERT_EQ(tau.size(), states.size());

  // fd on the same states with those torques must give back qdd, and match the API with the wrench
  std::vector<Eigen::VectorXd> q, qd;
  for (const auto& s : states) {
    q.push_back(s.q);
    qd.push_back(s.qd);
  }
  write_text(dir / "fd.csv", joint_csv(names, {{"q_", q}, {"qd_", qd}, {"tau_", tau}}));
  for (const char* method : {"mass-matrix", "articulated"}) {
    const auto fd = humandyn_cli(dir, "fd --method " + std::string(method) + " " + spec + "--in fd.csv --out qdd.csv");
    ASSERT_EQ(fd.exit_code, 0) << fd.err;
    const auto qdd = csv_columns(dir / "qdd.csv", names, "qdd_");
    for (std::size_t r = 0; r < states.size(); ++r) {
      const auto fext = api_wrenches(model, data, states[0].q, states[r].q, link, force, point);
      const Eigen::VectorXd expected_qdd =
          std::string(method) == "articulated"
              ? Eigen::VectorXd(hd::forward_dynamics<hd::FdMethod::Articulated>(model, data, states[r].q, states[r].qd,
                                                                                tau[r], fext))
              : Eigen::VectorXd(hd::forward_dynamics(model, data, states[r].q, states[r].qd, tau[r], fext));
      EXPECT_LT((qdd[r] - expected_qdd).norm(), 1e-9 * (1 + expected_qdd.norm())) << method << " row " << r;
      EXPECT_LT((qdd[r] - states[r].qdd).norm(), 1e-8 * (1 + states[r].qdd.norm())) << method << " row " << r;
    }
  }
  for (std::size_t r = 0; r < states.size(); ++r) {
    const auto fext = api_wrenches(model, data, states[0].q, states[r].q, link, force, point);
    const Eigen::VectorXd expected = hd::rnea(model, data, states[r].q, states[r].qd, states[r].qdd, fext);
    EXPECT_LT((tau[r] - expected).norm(), 1e-9 * expected.norm()) << "row " << r;
    // and the wrench changed something
    EXPECT_GT((expected - hd::rnea(model, data, states[r].q, states[r].qd, states[r].qdd)).norm(), 1.0);
  }
}

TEST_F(CliOutputs, ALoadInTheHandOfAHorizontalArmAddsItsWeightTimesTheReachAtTheShoulder) {
  Scratch dir;
  const M model(desc);
  hd::Data<M> data(model);
  const int shoulder = model.joint_index("l_shoulder_pitch"), elbow = model.joint_index("l_elbow_pitch");
  const int hand = 8;  // l_forearm: the forearm with the hand, its frame at the wrist, where the load hangs
  ASSERT_EQ(desc.joints[hand].link_name, "l_forearm");
  // the left arm raised forward to horizontal, elbow straight; at rest
  ht::JointState s{Eigen::VectorXd::Zero(16), Eigen::VectorXd::Zero(16), Eigen::VectorXd::Zero(16)};
  s.q[shoulder] = -pi / 2;
  write_text(dir / "pose.csv", states_csv(names, {s}));
  const auto plain = humandyn_cli(dir, "id --in pose.csv --out plain.csv");
  const auto loaded = humandyn_cli(dir, "id --wrench l_forearm:0,0,-98.1 --in pose.csv --out loaded.csv");
  ASSERT_EQ(plain.exit_code, 0) << plain.err;
  ASSERT_EQ(loaded.exit_code, 0) << loaded.err;
  const Eigen::VectorXd extra =
      csv_columns(dir / "loaded.csv", names, "tau_")[0] - csv_columns(dir / "plain.csv", names, "tau_")[0];

  // statics by hand: the weight's moment about each joint axis through a point on it
  hd::forward_kinematics(model, data, s.q);
  const hd::Vec3<double> load = data.oMi[std::size_t(hand)].p, weight(0, 0, -98.1);
  for (const int j : {shoulder, elbow}) {
    const auto& jc = model.joint(j);
    hd::Pose<double> axis = data.oMi[std::size_t(jc.parent)];
    if (jc.mounted) axis = axis * hd::Pose<double>{jc.mount_R, jc.mount_p};
    const hd::Vec3<double> a = axis.R.col(2), r = load - axis.p;
    // the axis is horizontal; the reach is the horizontal distance from it to the load
    ASSERT_LT(std::abs(a.z()), 1e-12);
    const double reach = std::abs(r.dot(a.cross(hd::Vec3<double>::UnitZ()).normalized()));
    EXPECT_NEAR(std::abs(extra[j]), 98.1 * reach, 1e-9 * 98.1 * reach) << names[std::size_t(j)];
    EXPECT_NEAR(extra[j], -a.dot(r.cross(weight)), 1e-9 * 98.1 * reach) << names[std::size_t(j)];
    if (j == shoulder) {
      EXPECT_GT(reach, 0.45);  // the upper arm and the forearm
      EXPECT_LT(reach, 0.8);
    }
  }
  // the other arm is a branch of its own: its torques do not change
  EXPECT_EQ(extra[model.joint_index("r_elbow_pitch")], 0);
}

TEST_F(CliOutputs, SimulateWithAWrenchStepsAsTheApiDoes) {
  Scratch dir;
  const M model(desc);
  hd::Data<M> data(model);
  const auto run = humandyn_cli(dir,
                                "simulate --integrator euler --dt 1e-3 --duration 1e-3 --wrench l_forearm:30,0,0 "
                                "--out trajectory.csv");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const auto qd = csv_columns(dir / "trajectory.csv", names, "qd_");
  ASSERT_EQ(qd.size(), 2u);
  // one semi-implicit Euler step from rest: qd1 = h qdd(q0, 0, tau = 0, the wrench)
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(16);
  hd::LinkWrenches<M> fext(16);
  hd::forward_kinematics(model, data, zero);
  fext[8] = hd::wrench_from_world(data, 8, hd::Vec3<double>(30, 0, 0), data.oMi[8].p);
  const Eigen::VectorXd expected = 1e-3 * hd::forward_dynamics(model, data, zero, zero, zero, fext);
  EXPECT_LT((qd[1] - expected).norm(), 1e-9 * expected.norm());
}

TEST_F(CliOutputs, BadWrenchesAreUsageErrorsNamingTheBadPart) {
  Scratch dir;
  write_text(dir / "s.csv", states_csv(names, ht::random_states(16, 1, 3, 1.0, 2.0, 5.0)));
  const struct {
    std::string spec, message;
  } cases[] = {
      {"l_forearm", "expected LINK:FX,FY,FZ[@PX,PY,PZ]"},
      {":1,2,3", "expected LINK:FX,FY,FZ[@PX,PY,PZ]"},
      {"l_forearm:1,2", "the force '1,2' must be three finite numbers"},
      {"l_forearm:1,2,3,4", "the force '1,2,3,4' must be three finite numbers"},
      {"l_forearm:1,x,3", "the force '1,x,3'"},
      {"l_forearm:1,2,inf", "the force '1,2,inf'"},
      {"l_forearm:1,2,3@0,0", "the point '0,0' must be three finite numbers"},
      {"l_forearm:1,2,3@", "the point ''"},
      {"l_hand:1,2,3", "unknown link 'l_hand' (the links that move: r_shank, "},
      {"r_foot:1,2,3", "unknown link 'r_foot', the fixed base"},
  };
  for (const auto& c : cases)
    for (const char* command : {"id", "fd"}) {
      const auto run = humandyn_cli(dir, std::string(command) + " --in s.csv --wrench '" + c.spec + "'");
      EXPECT_EQ(run.exit_code, 2) << command << " " << c.spec << ": " << run.err;
      EXPECT_NE(run.err.find(c.message), std::string::npos) << command << " " << c.spec << ": " << run.err;
    }
  const auto sim = humandyn_cli(dir, "simulate --duration 0.01 --wrench l_forearm:1,2");
  EXPECT_EQ(sim.exit_code, 2);
  EXPECT_NE(sim.err.find("the force '1,2'"), std::string::npos) << sim.err;
  const auto scene = humandyn_cli(dir, "id --in s.csv --scene upper_body --wrench l_forearm:1,2,3");
  EXPECT_EQ(scene.exit_code, 2);
  EXPECT_NE(scene.err.find("--wrench does not go with --scene"), std::string::npos) << scene.err;
  for (const char* command : {"id", "fd", "simulate"}) {
    const auto help = humandyn_cli(dir, std::string(command) + " --help");
    EXPECT_NE(help.out.find("--wrench L:F[@P]"), std::string::npos) << command;
  }
}

}  // namespace

}  // namespace test_cli_outputs
