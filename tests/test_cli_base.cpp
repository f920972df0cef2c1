// The command line on a moving and a floating base: `humandyn id` with base_ columns against the library's
// moving-base rnea, its ground reaction on a static pose (the body's weight, the centre of pressure under the
// centre of mass) and its flags counted on stderr; rows that switch the stance foot; columns passed through;
// `--floating` in model, id, fd and simulate: fd inverts id, and a body tossed through the air conserves its
// momentum (no gravity) or carries its centre of mass along the parabola (gravity). Runs the binary.
#include "cli/csv.hpp"
#include "cli/model_json.hpp"
#include "humandyn/floating.hpp"
#include "humandyn/humandyn.hpp"
#include "support/cli_run.hpp"
#include "support/random_state.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <random>
#include <string>
#include <vector>

namespace test_cli_base {

namespace {

using namespace humandyn;
using namespace humandyn::cli;
using humandyn::testing::CliRun;
using humandyn::testing::humandyn_cli;
using humandyn::testing::joint_names;
using humandyn::testing::read_text;
using humandyn::testing::Scratch;
using humandyn::testing::write_text;

const std::vector<std::string> base_pose_columns{"base_x",  "base_y",  "base_z", "base_qw",
                                                 "base_qx", "base_qy", "base_qz"};
const std::vector<std::string> base_motion_columns{"base_wx",  "base_wy",  "base_wz",  "base_vx", "base_vy", "base_vz",
                                                   "base_wdx", "base_wdy", "base_wdz", "base_ax", "base_ay", "base_az"};

// A CSV text: header, then rows of numbers in full precision.
std::string csv_text(const std::vector<std::string>& header, const std::vector<std::vector<double>>& rows) {
  std::string text;
  for (std::size_t c = 0; c < header.size(); ++c) text += (c ? "," : "") + header[c];
  text += "\n";
  for (const auto& r : rows) {
    for (std::size_t c = 0; c < r.size(); ++c) text += (c ? "," : "") + format_number(r[c]);
    text += "\n";
  }
  return text;
}

std::vector<std::string> concat(std::vector<std::vector<std::string>> parts) {
  std::vector<std::string> out;
  for (const auto& p : parts) out.insert(out.end(), p.begin(), p.end());
  return out;
}

// An output of `id --ground-reaction`, its cells that may be empty kept as text.
CsvTable read_output(const std::string& text) {
  return parse_csv(text, "out.csv", [](CsvTable& t) {
    for (const char* c : {"cop_x", "cop_y", "cop_z", "friction_ratio", "free_moment"})
      if (t.column(c) >= 0) t.keep_as_text(t.column(c));
  });
}

// A cell that may be empty, as a number (NaN when empty).
double maybe(const CsvTable& t, std::size_t row, const std::string& name) {
  const std::string& cell = t.text(row, t.require_column(name));
  return cell.empty() ? std::nan("") : std::stod(cell);
}

// Column `name` of `table`, every row.
std::vector<double> column(const CsvTable& table, const std::string& name) {
  const int c = table.require_column(name);
  std::vector<double> out;
  for (const auto& r : table.rows) out.push_back(r[std::size_t(c)]);
  return out;
}

Eigen::VectorXd joint_values(const CsvTable& table, std::size_t row, const std::vector<std::string>& names,
                             const std::string& prefix) {
  Eigen::VectorXd v(Eigen::Index(names.size()));
  for (std::size_t i = 0; i < names.size(); ++i)
    v[Eigen::Index(i)] = table.rows[row][std::size_t(table.require_column(prefix + names[i]))];
  return v;
}

// A random base pose and motion, as the base_ columns hold them (the quaternion unit to the last bit).
struct RandomBase {
  Eigen::Quaterniond r;
  Vec3<double> p, w, v, wd, a;
  Pose<double> pose() const { return {r.toRotationMatrix(), p}; }
  std::vector<double> cells() const {
    return {p.x(), p.y(), p.z(), r.w(),  r.x(),  r.y(),  r.z(), w.x(), w.y(), w.z(),
            v.x(), v.y(), v.z(), wd.x(), wd.y(), wd.z(), a.x(), a.y(), a.z()};
  }
};

RandomBase random_base(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  std::uniform_real_distribution<double> u(-1, 1);
  RandomBase b;
  b.r = Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized();
  b.p = Vec3<double>(u(rng), u(rng), 1 + u(rng));
  b.w = 3 * Vec3<double>(u(rng), u(rng), u(rng));
  b.v = 2 * Vec3<double>(u(rng), u(rng), u(rng));
  b.wd = 10 * Vec3<double>(u(rng), u(rng), u(rng));
  b.a = 10 * Vec3<double>(u(rng), u(rng), u(rng));
  return b;
}

class CliBase : public ::testing::Test {
 protected:
  Scratch dir;
  ModelDescription<double> d = human_description(default_parameters());
  std::vector<std::string> names = joint_names(d);
  std::vector<std::string> q_cols = joint_columns(names, "q_"), qd_cols = joint_columns(names, "qd_"),
                           qdd_cols = joint_columns(names, "qdd_"), tau_cols = joint_columns(names, "tau_");
};

// ---- a moving base ------------------------------------------------------------------------------------

TEST_F(CliBase, BaseColumnsGiveTheLibrarysMovingBaseTorques) {
  std::mt19937_64 rng(12);
  const auto states = humandyn::testing::random_states(16, 100, 3);
  std::vector<std::vector<double>> rows;
  std::vector<RandomBase> bases;
  for (const auto& s : states) {
    bases.push_back(random_base(rng));
    std::vector<double> row = bases.back().cells();
    for (const auto* v : {&s.q, &s.qd, &s.qdd}) row.insert(row.end(), v->data(), v->data() + 16);
    rows.push_back(row);
  }
  write_text(dir / "moving.csv",
             csv_text(concat({base_pose_columns, base_motion_columns, q_cols, qd_cols, qdd_cols}), rows));
  const CliRun run = humandyn_cli(dir, "id --in moving.csv --out tau.csv --ground-reaction --moment-about 0.1,0.2,0");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_NE(run.err.find("humandyn id: ground reaction: "), std::string::npos) << run.err;
  const CsvTable out = read_output(read_text(dir / "tau.csv"));
  ASSERT_EQ(out.rows.size(), states.size());

  const AnyModel<double> model(d);
  Data<AnyModel<double>> data(model);
  double worst = 0, worst_grf = 0;
  for (std::size_t r = 0; r < states.size(); ++r) {
    BaseMotion<double> base;
    base.pose = bases[r].pose();
    base.w = bases[r].w;
    base.wd = bases[r].wd;
    base.a = bases[r].a;
    const Eigen::VectorXd tau = rnea(model, data, base, states[r].q, states[r].qd, states[r].qdd);
    const auto g = ground_reaction(model, data, base);
    const Vec3<double> mp = g.moment_about(Vec3<double>(0.1, 0.2, 0));
    worst = std::max(worst, (joint_values(out, r, names, "tau_") - tau).cwiseAbs().maxCoeff());
    const double cells[] = {g.force.x(),  g.force.y(), g.force.z(), g.moment.x(), g.moment.y(),
                            g.moment.z(), mp.x(),      mp.y(),      mp.z()};
    const char* cols[] = {"grf_fx", "grf_fy", "grf_fz", "grf_mx", "grf_my", "grf_mz", "grf_px", "grf_py", "grf_pz"};
    for (int k = 0; k < 9; ++k)
      worst_grf = std::max(worst_grf, std::abs(out.rows[r][std::size_t(out.require_column(cols[k]))] - cells[k]));
  }
  EXPECT_LT(worst, 1e-9) << "N m";
  EXPECT_LT(worst_grf, 1e-9) << "N, N m";
}

TEST_F(CliBase, StandingStillTheFootCarriesTheWeightUnderTheCentreOfMass) {
  // a crouch on the right foot, the arms forward: still, no base columns
  Eigen::VectorXd q = Eigen::VectorXd::Zero(16);
  q[0] = 0.3;
  q[1] = -0.6;
  q[3] = 0.3;
  q[6] = q[9] = -1.2;
  std::vector<double> row(q.data(), q.data() + 16);
  row.resize(48, 0.0);
  write_text(dir / "still.csv", csv_text(concat({q_cols, qd_cols, qdd_cols}), {row}));
  const CliRun run = humandyn_cli(dir, "id --in still.csv --ground-reaction");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const CsvTable out = read_output(run.out);
  const AnyModel<double> model(d);
  Data<AnyModel<double>> data(model);
  forward_kinematics(model, data, q);
  const double weight = model.total_mass() * 9.81;
  EXPECT_NEAR(column(out, "grf_normal")[0], weight, 1e-9 * weight);
  EXPECT_NEAR(column(out, "grf_fz")[0], weight, 1e-9 * weight);
  EXPECT_NEAR(maybe(out, 0, "cop_x"), data.com.x(), 1e-12);
  EXPECT_NEAR(maybe(out, 0, "cop_y"), data.com.y(), 1e-12);
  EXPECT_EQ(maybe(out, 0, "cop_z"), 0.0);
  EXPECT_NEAR(maybe(out, 0, "friction_ratio"), 0.0, 1e-15);
  EXPECT_EQ(column(out, "foot_pulls")[0], 0.0);
  EXPECT_EQ(column(out, "foot_slips")[0], 0.0);
  // the centre of mass over the right foot's sole? The home pose's is between the feet: outside
  EXPECT_EQ(column(out, "cop_outside_sole")[0], data.com.y() < -0.09 + 0.048 ? 0.0 : 1.0);
}

TEST_F(CliBase, FlagsFireAndAreCountedOnStderr) {
  // row 1: still at home (the centre of mass between the feet: outside the right sole); row 2: the base
  // dropping faster than gravity (the foot would pull, straight down: no friction needed); row 3: the base
  // accelerating forward (the foot slips); row 4: falling freely (the foot carries nothing: no flag)
  std::vector<std::vector<double>> rows;
  for (const double ax : {0.0, 0.0, 9.0, 0.0}) {
    std::vector<double> row(3, 0.0);  // base_ax, base_ay, base_az
    row[0] = ax;
    row.resize(3 + 48, 0.0);
    rows.push_back(row);
  }
  rows[1][2] = -20;  // base_az
  rows[3][2] = -9.81;
  write_text(dir / "flags.csv", csv_text(concat({{"base_ax", "base_ay", "base_az"}, q_cols, qd_cols, qdd_cols}), rows));
  const CliRun run = humandyn_cli(dir, "id --in flags.csv --out out.csv --ground-reaction --mu 0.5");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.err,
            "humandyn id: ground reaction: 3 of 4 rows with a flag: the foot would have to pull on the ground in 1, "
            "the centre of pressure lies outside the sole in 2, the friction exceeds mu = 0.5 in 1 (one foot on the "
            "ground cannot produce those rows)\n");
  const CsvTable out = read_output(read_text(dir / "out.csv"));
  EXPECT_EQ(column(out, "foot_pulls"), (std::vector<double>{0, 1, 0, 0}));
  EXPECT_EQ(column(out, "foot_slips"), (std::vector<double>{0, 0, 1, 0}));
  EXPECT_EQ(column(out, "cop_outside_sole"), (std::vector<double>{1, 0, 1, 0}));
  EXPECT_EQ(column(out, "grf_normal")[3], 0.0);
  // the foot that pulls, and the one that carries nothing, have no centre of pressure: its cells are empty;
  // their friction ratio is 0 (no horizontal force)
  for (const int r : {1, 3}) {
    for (const char* c : {"cop_x", "cop_y", "cop_z", "free_moment"}) {
      EXPECT_EQ(out.text(std::size_t(r), out.column(c)), "") << c;
      EXPECT_NE(out.text(0, out.column(c)), "") << c;
    }
    EXPECT_EQ(out.text(std::size_t(r), out.column("friction_ratio")), "0");
  }
  // a sole given by hand, as large as a room: nothing outside it
  const CliRun big = humandyn_cli(dir, "id --in flags.csv --ground-reaction --sole 10,10,5,0.08");
  ASSERT_EQ(big.exit_code, 0) << big.err;
  EXPECT_EQ(column(read_output(big.out), "cop_outside_sole"), (std::vector<double>{0, 0, 0, 0}));
}

TEST_F(CliBase, StanceColumnSwitchesFeetThroughTheExactStateMap) {
  const auto states = humandyn::testing::random_states(16, 40, 8);
  std::vector<std::vector<double>> rows;
  std::string text = "stance,phase," + csv_text(concat({q_cols, qd_cols, qdd_cols}), {});
  text.pop_back();
  text += "\n";
  for (std::size_t r = 0; r < states.size(); ++r) {
    text += std::string(r % 2 ? "left" : "r") + "," + (r % 2 ? "\"single, left\"" : "right") + ",";
    std::vector<double> row;
    for (const auto* v : {&states[r].q, &states[r].qd, &states[r].qdd})
      row.insert(row.end(), v->data(), v->data() + 16);
    for (std::size_t c = 0; c < row.size(); ++c) text += (c ? "," : "") + format_number(row[c]);
    text += "\n";
  }
  write_text(dir / "walk.csv", text);
  const CliRun run = humandyn_cli(dir, "id --in walk.csv --out tau.csv");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const CsvTable out = read_csv((dir / "tau.csv").string(), [](CsvTable& t) { t.keep_as_text(0); });
  ASSERT_EQ(out.header[0], "phase");
  EXPECT_EQ(out.text(1, 0), "single, left");

  // right rows: the right-stance model's torques; left rows: the left-stance model's on the mapped state,
  // each joint's torque carried back by name with the sign that its angle rate takes in the map
  const HumanModel<double> right = human_model<double>(default_parameters());
  const HumanModel<double> left = left_stance_model<double>(default_parameters());
  Data<HumanModel<double>> dr(right), dl(left);
  const StanceSwitch<HumanModel<double>, HumanModel<double>> to_left(right, left);
  double worst = 0;
  for (std::size_t r = 0; r < states.size(); ++r) {
    const auto& s = states[r];
    const Eigen::VectorXd got = joint_values(out, r, names, "tau_");
    if (r % 2 == 0) {
      EXPECT_EQ(got, Eigen::VectorXd(rnea(right, dr, s.q, s.qd, s.qdd))) << "row " << r;
      continue;
    }
    StanceState<HumanModel<double>> m;
    to_left(right, left, HumanModel<double>::JointVector(s.q), HumanModel<double>::JointVector(s.qd), m);
    // the accelerations map as the rates do: qd of the left model's joint k is sign_k qd of its namesake
    HumanModel<double>::JointVector qdd;
    for (int k = 0; k < 16; ++k) {
      const int i = right.joint_index(left.joint_name(k));
      qdd[k] = (s.qd[i] != 0 ? m.qd[k] / s.qd[i] : 1.0) * s.qdd[i];
    }
    const Eigen::VectorXd tau_left = rnea(rebase(left, m.base_pose), dl, m.q, m.qd, qdd);
    for (int k = 0; k < 16; ++k) {
      const int i = right.joint_index(left.joint_name(k));
      const double sign = std::round(m.qd[k] / s.qd[i]);
      worst = std::max(worst, std::abs(got[i] - sign * tau_left[k]));
    }
  }
  EXPECT_LT(worst, 1e-9) << "N m";

  // standing still at home on either foot: mirror images, every torque the mirror joint's, up to its sign
  std::string header = "stance";
  for (const auto& c : concat({q_cols, qd_cols, qdd_cols})) header += "," + c;
  std::string zeros;
  for (int k = 0; k < 48; ++k) zeros += ",0";
  write_text(dir / "still.csv", header + "\nright" + zeros + "\nl" + zeros + "\n");
  const CliRun both = humandyn_cli(dir, "id --in still.csv");
  ASSERT_EQ(both.exit_code, 0) << both.err;
  const CsvTable feet = parse_csv(both.out, "stdout");
  const Eigen::VectorXd on_right = joint_values(feet, 0, names, "tau_"), on_left = joint_values(feet, 1, names, "tau_");
  for (std::size_t i = 0; i < 16; ++i) {
    const int mirror = right.joint_index(mirror_name(names[i]));
    EXPECT_NEAR(std::abs(on_left[mirror]), std::abs(on_right[Eigen::Index(i)]), 1e-9) << names[i];
  }
}

// The left-stance model is the body's mirror image: a body whose sides differ is refused for a stance
// column, naming the link, instead of giving a left row the other arm's mass.
TEST_F(CliBase, StanceColumnRefusesABodyWhoseSidesDiffer) {
  ModelDescription<double> body = human_description(default_parameters());
  for (auto& j : body.joints)
    if (j.link_name == "l_forearm") j.body.mass *= 2;
  write_text(dir / "asym.json", write_model_json(body));
  std::string header = "stance", zeros;
  for (const auto& c : q_cols) header += "," + c, zeros += ",0";
  write_text(dir / "still.csv", header + "\nright" + zeros + "\nleft" + zeros + "\n");
  const CliRun run = humandyn_cli(dir, "id --model asym.json --terms gravity --in still.csv");
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_NE(run.err.find("humandyn id: the stance column of still.csv switches to the left foot through the mirror "
                         "image of 'asym.json', which is not the same body: link 'l_forearm' has a mass of "),
            std::string::npos)
      << run.err;
  // without the column, or with every row on the right foot (as motion import writes a clip that never
  // leaves it), the body is a body like any other
  write_text(dir / "plain.csv", header.substr(7) + "\n" + zeros.substr(1) + "\n");
  EXPECT_EQ(humandyn_cli(dir, "id --model asym.json --terms gravity --in plain.csv").exit_code, 0);
  write_text(dir / "right.csv", header + "\nright" + zeros + "\nr" + zeros + "\n");
  const CliRun right = humandyn_cli(dir, "id --model asym.json --terms gravity --in right.csv");
  EXPECT_EQ(right.exit_code, 0) << right.err;
  std::string tau_header = "stance";
  for (const auto& c : q_cols) tau_header += "," + c + ",qd_" + c.substr(2) + ",tau_" + c.substr(2);
  std::string tau_zeros;
  for (std::size_t k = 0; k < 3 * q_cols.size(); ++k) tau_zeros += ",0";
  write_text(dir / "right_tau.csv", tau_header + "\nright" + tau_zeros + "\n");
  const CliRun fd = humandyn_cli(dir, "fd --model asym.json --in right_tau.csv");
  EXPECT_EQ(fd.exit_code, 0) << fd.err;
}

TEST_F(CliBase, OtherColumnsPassThroughAndMisspeltOnesAreNamed) {
  std::string zeros;
  for (int k = 0; k < 48; ++k) zeros += ",0";
  std::string header = "t,phase,frame";
  for (const auto& c : concat({q_cols, qd_cols, qdd_cols})) header += "," + c;
  write_text(dir / "s.csv", header + "\n0.5,flight,007" + zeros + "\n");
  CliRun run = humandyn_cli(dir, "id --in s.csv");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  EXPECT_EQ(run.out.substr(0, run.out.find(",tau_")), "t,phase,frame");
  EXPECT_EQ(run.out.substr(run.out.find('\n') + 1, 16), "0.5,flight,007,-");

  const std::pair<std::string, std::string> misspelt[] = {
      {"qdd_r_knee", "column 52 'qdd_r_knee': unknown column"},
      {"base_qw", "missing column 'base_qx'"},
      {"tau_r_knee_pitch",
       "column 52 'tau_r_knee_pitch': a column this command writes (its result), not one it "
       "reads"},
      {"stance", "line 2, column 52 'stance': '0' is not a stance foot (right, left, r or l)"},
      {"Stance", "column 52 'Stance': unknown column: the command reads 'stance'"},
  };
  for (const auto& [name, message] : misspelt) {
    write_text(dir / "bad.csv", header + "," + name + "\n0.5,flight,007" + zeros + ",0\n");
    run = humandyn_cli(dir, "id --in bad.csv");
    EXPECT_EQ(run.exit_code, 1) << name;
    EXPECT_NE(run.err.find(message), std::string::npos) << run.err;
  }
  // under a scene too, a result column is said to be one (it was called a misspelling), of id and of fd
  write_text(dir / "tau.csv", header + ",tau_r_knee_pitch\n0.5,flight,007" + zeros + ",0\n");
  run = humandyn_cli(dir, "id --scene full --in tau.csv");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("column 52 'tau_r_knee_pitch': a column this command writes (its result)"), std::string::npos)
      << run.err;
  std::string fd_header = "t";
  for (const auto& c : concat({q_cols, qd_cols})) fd_header += "," + c;
  for (const auto& c : q_cols) fd_header += ",tau_" + c.substr(2);
  write_text(dir / "qdd.csv", fd_header + ",qdd_r_knee_pitch\n0.5" + zeros + ",0\n");
  run = humandyn_cli(dir, "fd --scene full --in qdd.csv");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("column 50 'qdd_r_knee_pitch': a column this command writes (its result)"), std::string::npos)
      << run.err;
  // a quaternion that is not a rotation
  write_text(dir / "quat.csv", header + ",base_qw,base_qx,base_qy,base_qz\n0.5,flight,007" + zeros + ",1,0,0.1,0\n");
  run = humandyn_cli(dir, "id --in quat.csv");
  EXPECT_EQ(run.exit_code, 1);
  EXPECT_NE(run.err.find("column 52 'base_qw': the orientation quaternion (base_qw, base_qx, base_qy, base_qz) has "
                         "norm 1.004987562112089, not 1"),
            std::string::npos)
      << run.err;
}

// ---- the floating form --------------------------------------------------------------------------------

TEST_F(CliBase, FloatingModelJsonReadsBackAndSaysWhatItIs) {
  const CliRun json = humandyn_cli(dir, "model --json --floating");
  ASSERT_EQ(json.exit_code, 0) << json.err;
  EXPECT_NE(json.out.find("\"joint\": \"floating\""), std::string::npos);
  write_text(dir / "f.json", json.out);
  bool floating = false;
  const ModelDescription<double> back = parse_model_json(json.out, "f.json", &floating);
  EXPECT_TRUE(floating);
  EXPECT_EQ(back.base_link_name, floating_description(d).base_link_name);
  EXPECT_EQ(humandyn_cli(dir, "model --json --floating --model f.json").out, json.out);
  const CliRun fixed = humandyn_cli(dir, "model --model f.json");
  EXPECT_EQ(fixed.exit_code, 2);
  EXPECT_EQ(fixed.err, "humandyn model: f.json describes the floating form of a body: give --floating too\n");
  // a command without --floating is not told to give it
  const CliRun bench = humandyn_cli(dir, "bench --quick --model f.json");
  EXPECT_EQ(bench.exit_code, 2);
  EXPECT_EQ(bench.err,
            "humandyn bench: f.json describes the floating form of a body: this command takes the stance-rooted one "
            "(`humandyn model --json` without --floating writes it)\n");
  const CliRun table = humandyn_cli(dir, "model --floating");
  ASSERT_EQ(table.exit_code, 0) << table.err;
  EXPECT_NE(table.out.find("floating base"), std::string::npos) << table.out;
}

TEST_F(CliBase, FloatingFdInvertsFloatingId) {
  std::mt19937_64 rng(5);
  const auto states = humandyn::testing::random_states(16, 100, 21);
  const ModelDescription<double> f = floating_description(d);
  const auto fnames = joint_names(f);
  std::vector<std::vector<double>> rows;
  for (const auto& s : states) {
    std::vector<double> row = random_base(rng).cells();
    row.resize(13);  // pose and velocity
    for (const auto* v : {&s.q, &s.qd}) row.insert(row.end(), v->data(), v->data() + 16);
    const Eigen::VectorXd tau = 50 * s.qdd;
    row.insert(row.end(), tau.data(), tau.data() + 16);
    rows.push_back(row);
  }
  const std::vector<std::string> pose_velocity(base_motion_columns.begin(), base_motion_columns.begin() + 6);
  write_text(dir / "fd_in.csv", csv_text(concat({base_pose_columns, pose_velocity, joint_columns(fnames, "q_"),
                                                 joint_columns(fnames, "qd_"), joint_columns(fnames, "tau_")}),
                                         rows));
  // the base's accelerations are what fd finds: given, they are refused, not passed over
  const std::string fd_in = read_text(dir / "fd_in.csv");
  const std::size_t end_of_header = fd_in.find('\n');
  write_text(
      dir / "fd_wd.csv", fd_in.substr(0, end_of_header) + ",base_wdx,base_wdy,base_wdz" + [&] {
        std::string body = fd_in.substr(end_of_header), out;
        for (std::size_t p = 0, e; (e = body.find('\n', p + 1)) != std::string::npos; p = e)
          out += body.substr(p, e - p) + ",1,2,3";
        return out + "\n";
      }());
  const CliRun refused = humandyn_cli(dir, "fd --floating --in fd_wd.csv");
  EXPECT_EQ(refused.exit_code, 1);
  EXPECT_NE(refused.err.find("fd_wd.csv: line 1, column " + std::to_string(13 + 48 + 1) +
                             " 'base_wdx': a column this command writes (its result), not one it reads"),
            std::string::npos)
      << refused.err;
  for (const char* method : {"mass-matrix", "articulated"}) {
    SCOPED_TRACE(method);
    const CliRun fd =
        humandyn_cli(dir, std::string("fd --floating --method ") + method + " --in fd_in.csv --out a.csv");
    ASSERT_EQ(fd.exit_code, 0) << fd.err;
    const CsvTable acc = read_csv((dir / "a.csv").string());
    // the states with the accelerations found: inverse dynamics gives the torques back and no base wrench
    std::vector<std::vector<double>> id_rows;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      std::vector<double> row(rows[r].begin(), rows[r].begin() + 13 + 32);
      for (const char* c : {"base_wdx", "base_wdy", "base_wdz", "base_ax", "base_ay", "base_az"})
        row.push_back(acc.rows[r][std::size_t(acc.require_column(c))]);
      const Eigen::VectorXd qdd = joint_values(acc, r, fnames, "qdd_");
      row.insert(row.end(), qdd.data(), qdd.data() + 16);
      id_rows.push_back(row);
    }
    write_text(dir / "id_in.csv", csv_text(concat({base_pose_columns, base_motion_columns, joint_columns(fnames, "q_"),
                                                   joint_columns(fnames, "qd_"), joint_columns(fnames, "qdd_")}),
                                           [&] {
                                             // reorder: pose, velocity, accelerations, q, qd, qdd
                                             std::vector<std::vector<double>> out;
                                             for (const auto& r : id_rows) {
                                               std::vector<double> o(r.begin(), r.begin() + 13);
                                               o.insert(o.end(), r.begin() + 45, r.begin() + 51);
                                               o.insert(o.end(), r.begin() + 13, r.begin() + 45);
                                               o.insert(o.end(), r.begin() + 51, r.end());
                                               out.push_back(o);
                                             }
                                             return out;
                                           }()));
    const CliRun id = humandyn_cli(dir, "id --floating --in id_in.csv --out tau.csv");
    ASSERT_EQ(id.exit_code, 0) << id.err;
    const CsvTable tau = read_csv((dir / "tau.csv").string());
    double worst = 0, worst_base = 0;
    for (std::size_t r = 0; r < rows.size(); ++r) {
      const Eigen::VectorXd given = Eigen::Map<const Eigen::VectorXd>(rows[r].data() + 45, 16);
      const double scale = 1 + given.cwiseAbs().maxCoeff();
      worst = std::max(worst, (joint_values(tau, r, fnames, "tau_") - given).cwiseAbs().maxCoeff() / scale);
      for (const char* c : {"base_fx", "base_fy", "base_fz", "base_mx", "base_my", "base_mz"})
        worst_base = std::max(worst_base, std::abs(tau.rows[r][std::size_t(tau.require_column(c))]) / scale);
    }
    EXPECT_LT(worst, 1e-9) << "joint torques, relative";
    EXPECT_LT(worst_base, 1e-9) << "base wrench, relative";
  }
}

// The state of a floating trajectory's row: base pose, v_b, q, qd.
FloatingState<AnyModel<double>> row_state(const AnyModel<double>& model, const CsvTable& t, std::size_t r,
                                          const std::vector<std::string>& names) {
  FloatingState<AnyModel<double>> x(model);
  const auto at = [&](const char* c) { return t.rows[r][std::size_t(t.require_column(c))]; };
  x.base.R =
      Eigen::Quaterniond(at("base_qw"), at("base_qx"), at("base_qy"), at("base_qz")).normalized().toRotationMatrix();
  x.base.p = Vec3<double>(at("base_x"), at("base_y"), at("base_z"));
  x.v_b << x.base.R.transpose() * Vec3<double>(at("base_wx"), at("base_wy"), at("base_wz")),
      x.base.R.transpose() * Vec3<double>(at("base_vx"), at("base_vy"), at("base_vz"));
  x.q = joint_values(t, r, names, "q_");
  x.qd = joint_values(t, r, names, "qd_");
  return x;
}

// A floating trajectory as simulate writes it, its last column `form` read as text.
CsvTable read_trajectory(const std::filesystem::path& file) {
  return read_csv(file.string(), [](CsvTable& t) { t.keep_as_text(t.column("form")); });
}

// A somersault with a twist, the arms and knees swinging: the start of a toss, given to --start. The floating
// RK4 step carries the body's momentum as its state, so the rows keep it at 1 ms.

std::string toss(const std::vector<std::string>& names) {
  std::string header = "base_wx,base_wy,base_wz,base_vx,base_vy,base_vz";
  std::string row = "1,-6,2,1,0,4";
  for (const auto& n : names) {
    header += ",qd_" + n;
    row += n.find("shoulder") != std::string::npos ? ",3" : n.find("knee") != std::string::npos ? ",-2" : ",0.5";
  }
  return header + "\n" + row + "\n";
}

TEST_F(CliBase, ATossWithoutGravityConservesMomentum) {
  ModelDescription<double> space = d;
  space.gravity.setZero();
  write_text(dir / "space.json", write_model_json(space));
  const AnyModel<double> model(floating_description(space));
  const auto fnames = joint_names(model.description());
  write_text(dir / "toss.csv", toss(fnames));
  const CliRun run =
      humandyn_cli(dir, "simulate --model space.json --floating --start toss.csv --dt 1/1000 --out flight.csv");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const CsvTable t = read_trajectory(dir / "flight.csv");
  ASSERT_EQ(t.rows.size(), 1001u);
  FloatingData<AnyModel<double>> fd(model);
  // the momentum in the world: linear, and angular about the world origin
  const auto momentum = [&](std::size_t r) {
    const auto x = row_state(model, t, r, fnames);
    floating_crba(model, fd, x.q);
    const SpatialVector<double> h =
        fd.Mbb * x.v_b + fd.Mbj * x.qd;  // (angular about the base origin; linear), base frame
    const Vec3<double> P = x.base.R * h.tail<3>();
    const Vec3<double> L = x.base.R * h.head<3>() + x.base.p.cross(P);
    SpatialVector<double> out;
    out << L, P;
    return out;
  };
  const SpatialVector<double> h0 = momentum(0);
  ASSERT_GT(h0.head<3>().norm(), 10.0);
  double worst_L = 0, worst_P = 0;
  for (std::size_t r = 1; r < t.rows.size(); r += 50) {
    const SpatialVector<double> h = momentum(r);
    worst_L = std::max(worst_L, (h - h0).head<3>().norm() / h0.head<3>().norm());
    worst_P = std::max(worst_P, (h - h0).tail<3>().norm() / h0.tail<3>().norm());
  }
  EXPECT_LT(worst_L, 1e-9) << "angular momentum, relative";
  EXPECT_LT(worst_P, 1e-9) << "linear momentum, relative";
  EXPECT_GT(std::abs(column(t, "base_qw").back() - column(t, "base_qw").front()), 0.1) << "it turned";
}

TEST_F(CliBase, ARagdollsCentreOfMassFollowsTheParabola) {
  const AnyModel<double> model(floating_description(d));
  const auto fnames = joint_names(model.description());
  write_text(dir / "toss.csv", toss(fnames));
  const CliRun run = humandyn_cli(dir, "simulate --floating --start toss.csv --dt 1/1000 --out fall.csv");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const CsvTable t = read_trajectory(dir / "fall.csv");
  FloatingData<AnyModel<double>> fd(model);
  const auto com = [&](std::size_t r, Vec3<double>& velocity) {
    const auto x = row_state(model, t, r, fnames);
    floating_crba(model, fd, x.q);
    forward_kinematics(model, fd.data, x.q);
    const Pose<double> to_X = x.base * model.base_pose().inverse();
    velocity = x.base.R * (fd.Mbb * x.v_b + fd.Mbj * x.qd).tail<3>() / model.total_mass();
    return Vec3<double>(to_X.R * fd.data.com + to_X.p);
  };
  Vec3<double> v0, v;
  const Vec3<double> c0 = com(0, v0);
  double worst = 0;
  for (std::size_t r = 0; r < t.rows.size(); r += 50) {
    const double time = t.rows[r][0];
    const Vec3<double> c = com(r, v);
    worst = std::max(worst, (c - (c0 + v0 * time + 0.5 * d.gravity * time * time)).norm());
  }
  EXPECT_LT(worst, 1e-9) << "m";
  EXPECT_LT(column(t, "base_z").back(), column(t, "base_z").front()) << "it fell";
  // a toss spinning too fast for the step stops at a divergence, and says where its partial trajectory went
  write_text(dir / "spin.csv", "base_wx,base_wy,base_wz,base_vx,base_vy,base_vz\n1,-6,2,1,0,4\n");
  const CliRun spin = humandyn_cli(
      dir, "simulate --floating --start spin.csv --integrator euler --dt 0.2 --duration 20 --out spin_out.csv");
  EXPECT_EQ(spin.exit_code, 3) << spin.err;
  EXPECT_NE(spin.err.find("spin_out.csv holds the partial trajectory up to t = "), std::string::npos) << spin.err;
}

// simulate --floating says its trajectory's form on every row (form = floating): id (and fd, by the same
// reader) read it with --floating only, view and motion export not at all (a file that does not go with the
// options: a usage error); a form cell that says anything else is an input error. A start whose energy
// overflows a double is refused by name.
TEST_F(CliBase, AFloatingTrajectorySaysItsForm) {
  const AnyModel<double> model(floating_description(d));
  write_text(dir / "toss.csv", toss(joint_names(model.description())));
  ASSERT_EQ(humandyn_cli(dir, "simulate --floating --start toss.csv --duration 0.01 --out flight.csv").exit_code, 0);
  const CsvTable t = read_trajectory(dir / "flight.csv");
  ASSERT_EQ(t.header.back(), "form");
  const std::string text = read_text(dir / "flight.csv");
  std::size_t rows = 0;
  for (std::size_t a = text.find('\n') + 1; a < text.size(); a = text.find('\n', a) + 1, ++rows)
    EXPECT_EQ(text.substr(text.find('\n', a) - 9, 9), ",floating") << rows;
  EXPECT_EQ(rows, 11u);
  // a trajectory as the start: its first row is the state, and the rest and a time are said to go unread
  const CliRun again = humandyn_cli(dir, "simulate --floating --start flight.csv --duration 0.001 --out again.csv");
  ASSERT_EQ(again.exit_code, 0) << again.err;
  EXPECT_NE(again.err.find("humandyn simulate: warning: flight.csv: line 2: the flight starts from this row's state; "
                           "the 10 row(s) after it are checked, not used"),
            std::string::npos)
      << again.err;
  write_text(dir / "late.csv", "t,base_x,base_y,base_z\n1.5,0,0,1\n");
  const CliRun late = humandyn_cli(dir, "simulate --floating --start late.csv --duration 0.001 --out late_out.csv");
  ASSERT_EQ(late.exit_code, 0) << late.err;
  EXPECT_EQ(late.err,
            "humandyn simulate: warning: late.csv: line 2: t = 1.5 is not read: the flight starts at t = 0\n");
  const std::string refused = "flight.csv: line 2, column " + std::to_string(t.header.size()) +
                              " 'form': a state of the floating form (its base_ columns are the pelvis's, its "
                              "re-hung leg's angles its own), where the stance-rooted form's is read";
  for (const char* run : {"id --terms gravity --in flight.csv --out tau.csv", "view flight.csv --out page.html",
                          "motion export flight.csv --out clip.bvh"}) {
    const CliRun r = humandyn_cli(dir, run);
    EXPECT_EQ(r.exit_code, 2) << run;
    EXPECT_NE(r.err.find(refused), std::string::npos) << run << "\n" << r.err;
  }
  for (const char* file : {"tau.csv", "page.html", "clip.bvh"}) EXPECT_FALSE(std::filesystem::exists(dir / file));
  const CliRun id = humandyn_cli(dir, "id --floating --terms gravity --in flight.csv --out tau.csv");
  EXPECT_EQ(id.exit_code, 0) << id.err;
  // another word in the column
  std::string other_text = text;
  for (std::size_t at; (at = other_text.find(",floating\n")) != std::string::npos;)
    other_text.replace(at, 10, ",stance\n");
  write_text(dir / "other.csv", other_text);
  const CliRun other = humandyn_cli(dir, "id --floating --terms gravity --in other.csv --out tau2.csv");
  EXPECT_EQ(other.exit_code, 1);
  EXPECT_NE(other.err.find("'stance' is no form of the body (the column says 'floating' on every row)"),
            std::string::npos)
      << other.err;
  // a start beyond what a step allows (its first step would stop the run, naming no cell)
  std::string knee_header, knee_row;
  int knee_column = 0;
  for (const auto& name : joint_names(model.description())) {
    knee_header += (knee_header.empty() ? "q_" : ",q_") + name;
    knee_row += std::string(knee_row.empty() ? "" : ",") + (name == "r_knee_pitch" ? "1e300" : "0");
    if (name == "r_knee_pitch") knee_column = int(std::count(knee_header.begin(), knee_header.end(), ',')) + 1;
  }
  for (const auto& [start, message] :
       {std::pair<std::string, std::string>{"base_vx,base_vy,base_vz\n1e200,0,0\n",
                                            "fast.csv: line 2, column 1 'base_vx': a speed of 1e+200 m/s is beyond "
                                            "the 1000 m/s a step allows"},
        // the speed is the vector's length: the message names the largest of its three cells
        {"base_vx,base_vy,base_vz\n600,-500,-700\n",
         "fast.csv: line 2, column 3 'base_vz': a speed of 1048.81 m/s is beyond the 1000 m/s a step allows"},
        {"base_vx,base_vy,base_vz\n1e200,-2e200,0\n",
         "fast.csv: line 2, column 2 'base_vy': a speed of 2.23607e+200 m/s is beyond the 1000 m/s a step allows"},
        {"base_wx,base_wy,base_wz\n0,2e4,0\n",
         "fast.csv: line 2, column 2 'base_wy': an angular speed of 20000 rad/s is beyond the 10000 rad/s a step "
         "allows"},
        {knee_header + "\n" + knee_row + "\n", "fast.csv: line 2, column " + std::to_string(knee_column) +
                                                   " 'q_r_knee_pitch': 1e+300 rad is beyond the 10000 rad a step "
                                                   "allows"}}) {
    write_text(dir / "fast.csv", start);
    const CliRun r = humandyn_cli(dir, "simulate --floating --start fast.csv --duration 0.01 --out fast_out.csv");
    EXPECT_EQ(r.exit_code, 1);
    EXPECT_NE(r.err.find(message), std::string::npos) << r.err;
    EXPECT_FALSE(std::filesystem::exists(dir / "fast_out.csv"));
  }
}

TEST_F(CliBase, FloatingRefusesWhatHasNoMeaningThere) {
  std::string zeros;
  for (int k = 0; k < 48; ++k) zeros += ",0";
  std::string header = "stance";
  for (const auto& c : concat({q_cols, qd_cols, qdd_cols})) header += "," + c;
  write_text(dir / "s.csv", header + "\nright" + zeros + "\n");
  std::string start = "stance", right = "right";
  for (const auto& c : q_cols) start += "," + c, right += ",0";
  write_text(dir / "start.csv", start + "\n" + right + "\n");
  write_text(dir / "torque.csv",
             "base_x,base_y,base_z,tau_waist_yaw\n0,0,1,1000\n");  // a start is a state: no torque drives the flight
  write_text(dir / "accel.csv", "qdd_r_knee_pitch,base_x,base_y,base_z\n3,0,0,1\n");
  write_text(dir / "wrench.csv", "base_x,base_y,base_z,base_fx\n0,0,1,5\n");  // (what id --floating writes)
  const std::pair<std::string, std::string> cases[] = {
      {"id --floating --in s.csv",
       "humandyn id: the stance column of s.csv goes with the stance-rooted form, not --floating"},
      {"id --floating --ground-reaction --in s.csv", "humandyn id: --ground-reaction goes with the stance-rooted form"},
      {"id --floating --scene upper_body --in s.csv", "humandyn id: --scene does not go with --floating"},
      {"simulate --floating --integrator implicit", "humandyn simulate: --floating steps with euler or rk4"},
      {"simulate --start s.csv", "humandyn simulate: --start requires --floating"},
      {"simulate --floating --start start.csv",
       "start.csv: line 2, column 1 'stance': the floating body has no stance foot (its base_ columns are the "
       "pelvis's, "
       "docs/base.md): a stance-rooted state is not its starting state"},
      {"simulate --floating --start torque.csv",
       "torque.csv: line 2, column 4 'tau_waist_yaw': the floating body flies with no joint torque: a start has none"},
      {"simulate --floating --start accel.csv",
       "accel.csv: line 2, column 1 'qdd_r_knee_pitch': a starting state has no acceleration: forward dynamics gives "
       "it"},
      {"model --floating --model paper.json", "paper.json: cannot open"},
      {"id --floating --in wrench.csv",
       "wrench.csv: line 1, column 4 'base_fx': a column this command writes (its result), not one it reads"},
  };
  for (const auto& [arguments, message] : cases) {
    const CliRun run = humandyn_cli(dir, arguments);
    EXPECT_NE(run.exit_code, 0) << arguments;
    EXPECT_NE(run.err.find(message), std::string::npos) << arguments << "\n" << run.err;
  }
}

}  // namespace

}  // namespace test_cli_base
