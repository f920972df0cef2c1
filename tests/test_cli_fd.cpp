// `humandyn fd` inverts `humandyn id` on a CSV file, with both methods and both sets of terms; the seed
// body's singular mass matrix and bad input are clear errors with non-zero exit codes.
#include "cli/csv.hpp"
#include "cli/model_json.hpp"
#include "humandyn/builders.hpp"
#include "support/cli_run.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

namespace test_cli_fd {

namespace {

namespace fs = std::filesystem;
namespace hd = humandyn;
namespace ht = humandyn::testing;
using ht::CliRun;
using ht::csv_columns;
using ht::humandyn_cli;
using ht::joint_csv;
using ht::joint_names;
using ht::Scratch;
using ht::write_text;

constexpr double pi = 3.14159265358979323846;

class CliFd : public ::testing::Test {
 protected:
  void SetUp() override {
    // the default body (a regular mass matrix), as a model file
    write_text(scratch / "pelvis.json", hd::cli::write_model_json(desc));
    for (const auto& s : ht::random_states(16, 200, 41, pi, 10, 50)) {
      q.push_back(s.q);
      qd.push_back(s.qd);
      qdd.push_back(s.qdd);
    }
    write_text(scratch / "states.csv", joint_csv(names, {{"q_", q}, {"qd_", qd}, {"qdd_", qdd}}));
  }

  // id of the states with `terms`, then fd of the torques with `method`: the worst relative error.
  double round_trip(const std::string& method, const std::string& terms, const std::string& model = "pelvis.json") {
    const CliRun id =
        humandyn_cli(scratch, "id --model " + model + " --terms " + terms + " --in states.csv --out tau.csv");
    EXPECT_EQ(id.exit_code, 0) << id.err;
    const auto tau = csv_columns(scratch / "tau.csv", names, "tau_");
    write_text(scratch / "fd_in.csv", joint_csv(names, {{"q_", q}, {"qd_", qd}, {"tau_", tau}}));
    const CliRun fd = humandyn_cli(
        scratch, "fd --model " + model + " --method " + method + " --terms " + terms + " --in fd_in.csv --out qdd.csv");
    EXPECT_EQ(fd.exit_code, 0) << fd.err;
    const auto back = csv_columns(scratch / "qdd.csv", names, "qdd_");
    EXPECT_EQ(back.size(), qdd.size());
    double worst = 0;
    for (std::size_t r = 0; r < std::min(back.size(), qdd.size()); ++r)
      worst = std::max(worst, (back[r] - qdd[r]).cwiseAbs().maxCoeff() / qdd[r].cwiseAbs().maxCoeff());
    return worst;
  }

  Scratch scratch;
  hd::ModelDescription<double> desc = hd::human_description(hd::default_parameters());
  std::vector<std::string> names = joint_names(desc);
  std::vector<Eigen::VectorXd> q, qd, qdd;
};

TEST_F(CliFd, InvertsIdBothMethodsBothTerms) {
  EXPECT_LE(round_trip("articulated", "full"), 1e-9);
  EXPECT_LE(round_trip("mass-matrix", "full"), 1e-9);
  EXPECT_LE(round_trip("articulated", "no-coriolis"), 1e-9);
  EXPECT_LE(round_trip("mass-matrix", "no-coriolis"), 1e-9);
  EXPECT_LE(round_trip("articulated", "full", "default"), 1e-9);
  EXPECT_LE(round_trip("mass-matrix", "full", "default"), 1e-9);
}

// Table 1's body (the paper model, massless pelvis): its mass matrix is singular, which fd reports
// (exit 1) instead of writing meaningless accelerations; no output file appears.
TEST_F(CliFd, SingularSeedBodyIsAnError) {
  const std::vector<Eigen::VectorXd> tau(q.size(), Eigen::VectorXd::Zero(16));
  write_text(scratch / "fd_in.csv", joint_csv(names, {{"q_", q}, {"qd_", qd}, {"tau_", tau}}));
  for (const char* method : {"articulated", "mass-matrix"}) {
    const CliRun r =
        humandyn_cli(scratch, std::string("fd --model paper --method ") + method + " --in fd_in.csv --out qdd.csv");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find("fd_in.csv: line 2"), std::string::npos) << r.err;
    EXPECT_NE(r.err.find("singular at joint 'r_hip_pitch'"), std::string::npos) << r.err;
    EXPECT_FALSE(fs::exists(scratch / "qdd.csv"));
  }
  // a chain whose tip moves no mass: its zero pivot, the first met, leaves none after it finite (once said as
  // "largest 0")
  hd::ModelDescription<double> chain = hd::human_description(hd::default_parameters());
  chain.joints.resize(2);  // the right ankle and knee
  chain.joints[1].body = {};
  write_text(scratch / "chain.json", hd::cli::write_model_json(chain));
  const std::vector<std::string> two{chain.joints[0].name, chain.joints[1].name};
  const std::vector<Eigen::VectorXd> zero(1, Eigen::VectorXd::Zero(2));
  write_text(scratch / "chain_in.csv", joint_csv(two, {{"q_", zero}, {"qd_", zero}, {"tau_", zero}}));
  const CliRun tip = humandyn_cli(scratch, "fd --model chain.json --in chain_in.csv --out qdd.csv");
  EXPECT_EQ(tip.exit_code, 1);
  EXPECT_NE(tip.err.find("the mass matrix is singular at joint '" + two[1] +
                         "' (pivot 0 kg m^2, no pivot positive and finite): a turn of this joint"),
            std::string::npos)
      << tip.err;
  // simulate warns naming the same joint, and an explicit step that fails there is blamed on it, not on
  // the first angle the NaN reached; backward Euler steps on
  for (const char* integrator : {"rk4", "backward-euler"}) {
    const CliRun r =
        humandyn_cli(scratch, std::string("simulate --model paper --duration 0.01 --integrator ") + integrator);
    EXPECT_NE(r.err.find("warning: the mass matrix is singular at the start at joint 4 'r_hip_pitch' (its pivot there "
                         "is below 1e-10 of the largest): a turn of this joint, with the joints beyond it turning "
                         "along, moves no mass"),
              std::string::npos)
        << r.err;
    if (std::string(integrator) == "rk4") {
      EXPECT_EQ(r.exit_code, 3);
      EXPECT_NE(
          r.err.find(": the mass matrix is singular at joint 4 'r_hip_pitch' (a turn of it, with the joints beyond "
                     "it turning along, moves no mass): the step's accelerations are not finite"),
          std::string::npos)
          << r.err;
    } else {
      EXPECT_EQ(r.exit_code, 0) << r.err;
    }
  }
}

// Its floating form, hung from the massless pelvis: each joint alone moves mass, but the base turning
// about the line of the hips and the waist as those three joints turn back moves none. fd names them
// (exit 1, no output) instead of writing an arbitrary motion along that line; simulate warns of it.
// The default body's floating form is regular at the same states.
TEST_F(CliFd, SingularFloatingBodyIsAnErrorNamingTheJoints) {
  const std::vector<Eigen::VectorXd> zero(3, Eigen::VectorXd::Zero(16));
  write_text(scratch / "rest.csv", joint_csv(names, {{"q_", zero}, {"qd_", zero}, {"tau_", zero}}));
  for (const char* method : {"articulated", "mass-matrix"}) {
    const CliRun r = humandyn_cli(
        scratch, std::string("fd --model paper --floating --method ") + method + " --in rest.csv --out qdd.csv");
    EXPECT_EQ(r.exit_code, 1);
    for (const char* part : {"rest.csv: line 2: the floating body's mass matrix is singular: turning the base with "
                             "joints 'r_hip_pitch', 'waist_pitch', 'l_hip_pitch' moves no mass; forward dynamics is "
                             "undefined"})
      EXPECT_NE(r.err.find(part), std::string::npos) << part << " not in: " << r.err;
    EXPECT_FALSE(fs::exists(scratch / "qdd.csv"));
    const CliRun regular = humandyn_cli(
        scratch, std::string("fd --model default --floating --method ") + method + " --in rest.csv --out qdd.csv");
    EXPECT_EQ(regular.exit_code, 0) << regular.err;
    fs::remove(scratch / "qdd.csv");
  }
  const CliRun sim = humandyn_cli(scratch, "simulate --model paper --floating --duration 0.01");
  EXPECT_NE(sim.err.find("warning: the floating body's mass matrix is singular at the start"), std::string::npos)
      << sim.err;
  const CliRun regular = humandyn_cli(scratch, "simulate --model default --floating --duration 0.01");
  EXPECT_EQ(regular.exit_code, 0) << regular.err;
  EXPECT_EQ(regular.err.find("singular"), std::string::npos) << regular.err;
}

// A floating body whose whole mass lies on one line: three point masses, on the base (behind its origin)
// and on two links turning about z, at home on a line parallel to the base's x axis at height y. The base turning about
// that line moves no mass, whatever the joints do, and fd says so naming no joint. On the x axis itself
// (y = 0) the base's own diagonal entry is zero; off it the motion mixes the base's turn and shift (found
// by the eigen check). Each joint alone moves mass, so the fixed form is regular; turned off the line,
// the floating form is too.
TEST_F(CliFd, FloatingBodyOnALineIsAnErrorNamingTheBaseAlone) {
  for (const double y : {0.0, 0.3}) {
    hd::ModelDescription<double> line;
    line.name = "line";
    line.base_body = hd::RigidBodyInertia<double>::point_mass(1.0, {-0.5, y, 0});
    for (int i = 0; i < 2; ++i) {
      hd::JointDescription<double> j;
      j.name = "j" + std::to_string(i + 1);
      j.link_name = "link" + std::to_string(i + 1);
      j.parent = i - 1;
      j.dh = {0.5, 0, 0, 0};
      j.body = hd::RigidBodyInertia<double>::point_mass(1.0, {0, y, 0});
      line.joints.push_back(j);
    }
    write_text(scratch / "line.json", hd::cli::write_model_json(line, true));
    write_text(scratch / "fixed.json", hd::cli::write_model_json(line));
    const auto rows = [](double q1, double q2) {
      const std::vector<Eigen::VectorXd> angles(1, Eigen::Vector2d(q1, q2)), zero(1, Eigen::VectorXd::Zero(2));
      return joint_csv({"j1", "j2"}, {{"q_", angles}, {"qd_", zero}, {"tau_", zero}});
    };
    write_text(scratch / "home.csv", rows(0, 0));
    write_text(scratch / "bent.csv", rows(0.3, -0.2));
    const CliRun r = humandyn_cli(scratch, "fd --model line.json --floating --in home.csv --out qdd.csv");
    EXPECT_EQ(r.exit_code, 1) << "y = " << y;
    EXPECT_NE(r.err.find("home.csv: line 2: the floating body's mass matrix is singular: a motion of the base alone "
                         "moves no mass; forward dynamics is undefined"),
              std::string::npos)
        << "y = " << y << ": " << r.err;
    EXPECT_FALSE(fs::exists(scratch / "qdd.csv"));
    for (const char* run : {"fd --model fixed.json --in home.csv --out qdd.csv",
                            "fd --model line.json --floating --in bent.csv --out qdd.csv"}) {
      const CliRun regular = humandyn_cli(scratch, run);
      EXPECT_EQ(regular.exit_code, 0) << run << ", y = " << y << ": " << regular.err;
      fs::remove(scratch / "qdd.csv");
    }
  }
}

// A stance column, as `humandyn id` and `motion import` write it: fd inverts id row by row on either foot,
// the left rows through the left-stance model standing where its foot is. Read without the column, the
// left rows' accelerations are another motion's (the right foot nailed down).
TEST_F(CliFd, StanceColumnInvertsIdOnEitherFoot) {
  // every line's first cell followed by a stance cell: right and left in turn
  const auto with_stance = [](const std::string& text) {
    std::string out;
    std::size_t line = 0;
    for (std::size_t a = 0; a < text.size(); ++line) {
      const std::size_t b = text.find('\n', a), comma = text.find(',', a);
      const char* stance = line == 0 ? "stance" : line % 2 ? "right" : "l";
      out += text.substr(a, comma - a) + "," + stance + text.substr(comma, b + 1 - comma);
      a = b + 1;
    }
    return out;
  };
  write_text(scratch / "walk.csv", with_stance(joint_csv(names, {{"q_", q}, {"qd_", qd}, {"qdd_", qdd}})));
  const CliRun id = humandyn_cli(scratch, "id --model pelvis.json --in walk.csv --out tau.csv");
  ASSERT_EQ(id.exit_code, 0) << id.err;
  const auto tau = csv_columns(scratch / "tau.csv", names, "tau_");
  const std::string fd_in = joint_csv(names, {{"q_", q}, {"qd_", qd}, {"tau_", tau}});
  write_text(scratch / "fd_walk.csv", with_stance(fd_in));
  write_text(scratch / "fd_right.csv", fd_in);
  for (const char* method : {"articulated", "mass-matrix"}) {
    const std::string fd = std::string("fd --model pelvis.json --method ") + method;
    const CliRun both = humandyn_cli(scratch, fd + " --in fd_walk.csv --out qdd.csv");
    const CliRun right = humandyn_cli(scratch, fd + " --in fd_right.csv --out qdd_right.csv");
    ASSERT_EQ(both.exit_code, 0) << both.err;
    ASSERT_EQ(right.exit_code, 0) << right.err;
    const auto back = csv_columns(scratch / "qdd.csv", names, "qdd_");
    const auto nailed = csv_columns(scratch / "qdd_right.csv", names, "qdd_");
    ASSERT_EQ(back.size(), qdd.size());
    double worst = 0, least_left = 1e300;
    for (std::size_t r = 0; r < qdd.size(); ++r) {
      const double scale = qdd[r].cwiseAbs().maxCoeff();
      worst = std::max(worst, (back[r] - qdd[r]).cwiseAbs().maxCoeff() / scale);
      if (r % 2) least_left = std::min(least_left, (nailed[r] - qdd[r]).cwiseAbs().maxCoeff() / scale);
    }
    EXPECT_LE(worst, 1e-9) << method;
    EXPECT_GT(least_left, 1e-3) << method << ": the left rows read as right rows";
  }

  // a stance that is no foot: the cell named; with the floating form: a usage error
  std::string bad = with_stance(fd_in);
  bad.replace(bad.find(",l,"), 3, ",x,");
  write_text(scratch / "fd_bad.csv", bad);
  CliRun r = humandyn_cli(scratch, "fd --model pelvis.json --in fd_bad.csv --out qdd_bad.csv");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("fd_bad.csv: line 3, column 2 'stance': 'x' is not a stance foot (right, left, r or l)"),
            std::string::npos)
      << r.err;
  EXPECT_FALSE(fs::exists(scratch / "qdd_bad.csv"));
  // a no-break space glued to "l" shows as such
  std::string nbsp = with_stance(fd_in);
  nbsp.replace(nbsp.find(",l,"), 3, ",l\u00A0,");
  write_text(scratch / "fd_nbsp.csv", nbsp);
  const CliRun shown = humandyn_cli(scratch, "fd --model pelvis.json --in fd_nbsp.csv --out qdd_bad.csv");
  EXPECT_NE(shown.err.find("'l<U+00A0>' is not a stance foot"), std::string::npos) << shown.err;
  r = humandyn_cli(scratch, "fd --model pelvis.json --in fd_bad.csv");  // on standard output: nothing printed
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_EQ(r.out, "");
  r = humandyn_cli(scratch, "fd --model pelvis.json --floating --in fd_walk.csv");
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_NE(r.err.find("the stance column of fd_walk.csv goes with the stance-rooted form, not --floating"),
            std::string::npos)
      << r.err;
}

TEST_F(CliFd, BadInput) {
  // a missing torque column: exit 1, naming it
  write_text(scratch / "no_tau.csv", joint_csv(names, {{"q_", q}, {"qd_", qd}}));
  CliRun r = humandyn_cli(scratch, "fd --model pelvis.json --in no_tau.csv");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("tau_r_ankle_pitch"), std::string::npos) << r.err;
  // a bad cell: exit 1, naming line and column
  std::string text = joint_csv(names, {{"q_", q}, {"qd_", qd}, {"tau_", qdd}});
  text.replace(text.find('\n') + 1, 1, "x");
  write_text(scratch / "bad.csv", text);
  r = humandyn_cli(scratch, "fd --model pelvis.json --in bad.csv");
  EXPECT_EQ(r.exit_code, 1);
  EXPECT_NE(r.err.find("line 2"), std::string::npos) << r.err;
  // usage errors: exit 2
  EXPECT_EQ(humandyn_cli(scratch, "fd --model pelvis.json --method euler --in states.csv").exit_code, 2);
  EXPECT_EQ(humandyn_cli(scratch, "fd --model pelvis.json --terms gravity --in states.csv").exit_code, 2);
  EXPECT_EQ(humandyn_cli(scratch, "fd --model pelvis.json").exit_code, 2);
  EXPECT_EQ(humandyn_cli(scratch, "fd --help").exit_code, 0);
}

}  // namespace

}  // namespace test_cli_fd
