// `humandyn view` (tools/cli/view_page.hpp): the positions the page draws are the engine's forward
// kinematics; a foot the body stands on stays still; a base pose moves it; torques and the ground
// reaction reach the page; bad input names the file, line and column; the page is one file with no
// external resource (runs the binary). The page's drawing is tested in a browser (view_browser.py).
#include "cli/csv.hpp"
#include "cli/errors.hpp"
#include "cli/model_json.hpp"
#include "cli/view_page.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/builders.hpp"
#include "humandyn/stance.hpp"
#include "support/cli_run.hpp"

#include <gtest/gtest.h>
#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

namespace test_view {

namespace {

namespace hd = humandyn;
namespace ht = humandyn::testing;
using hd::cli::format_number;
using ht::Scratch;
using ht::write_text;
using M = hd::HumanModel<double>;
using Q = M::JointVector;

const hd::ModelDescription<double> body = hd::human_description(hd::default_parameters());

// A states CSV: the header, then one row per (extra cells, q).
std::string states_csv(const std::string& extra_header, const std::vector<std::pair<std::string, Q>>& rows,
                       const std::vector<std::string>& names) {
  std::string text = extra_header;
  for (const auto& n : names) text.append(text.empty() ? "q_" : ",q_").append(n);
  text += '\n';
  for (const auto& [extra, q] : rows) {
    std::string line = extra;
    for (int i = 0; i < q.size(); ++i) line.append(line.empty() ? "" : ",").append(format_number(q[i]));
    text += line + '\n';
  }
  return text;
}

Q some_pose(double phase) {
  Q q;
  for (int i = 0; i < 16; ++i) q[i] = 0.4 * std::sin(1.3 * i + phase);
  return q;
}

// Point k of frame f of a clip (0: base origin, 1: sole, 2 + 2i: joint i's centre, 3 + 2i: its link's end).
Eigen::Vector3d point(const hd::cli::ViewClip& clip, std::size_t f, int k) {
  const auto& p = clip.points[f];
  return {p[std::size_t(3 * k)], p[std::size_t(3 * k + 1)], p[std::size_t(3 * k + 2)]};
}

hd::cli::ViewClip load(const Scratch& s, const std::string& states, const std::string& torques = "") {
  write_text(s / "states.csv", states);
  hd::cli::ViewInputs in;
  in.states = (s / "states.csv").string();
  if (!torques.empty()) {
    write_text(s / "tau.csv", torques);
    in.torques = (s / "tau.csv").string();
  }
  return hd::cli::load_view_clip(in, body);
}

std::string load_error(const Scratch& s, const std::string& states, const std::string& torques = "") {
  try {
    load(s, states, torques);
  } catch (const hd::cli::InputError& e) {
    return e.what();
  }
  return "no error";
}

TEST(View, PointsAreTheForwardKinematicsOfEveryRow) {
  Scratch s;
  const M model(body);
  hd::Data<M> data(model);
  const auto names = ht::joint_names(body);
  const auto clip = load(s, states_csv("t", {{"0", some_pose(0)}, {"0.01", some_pose(1)}}, names));
  ASSERT_EQ(clip.points.size(), 2u);
  EXPECT_EQ(clip.t, (std::vector<double>{0, 0.01}));
  for (std::size_t f = 0; f < 2; ++f) {
    hd::forward_kinematics(model, data, some_pose(double(f)));
    EXPECT_LE((point(clip, f, 0) - model.base_pose().p).norm(), 1e-4);
    for (int i = 0; i < 16; ++i) {
      const int parent = model.joint(i).parent;
      const Eigen::Vector3d joint = parent < 0 ? model.base_pose().p : data.oMi[std::size_t(parent)].p;
      EXPECT_LE((point(clip, f, 2 + 2 * i) - joint).norm(), 1e-4) << names[std::size_t(i)];
      EXPECT_LE((point(clip, f, 3 + 2 * i) - data.oMi[std::size_t(i)].p).norm(), 1e-4) << names[std::size_t(i)];
      EXPECT_NEAR(clip.q[f][std::size_t(i)], some_pose(double(f))[i], 1e-6);
    }
    EXPECT_NEAR(point(clip, f, 1).z(), 0, 1e-4) << "the stance sole on the ground";
  }
  EXPECT_EQ(clip.plot, (std::vector<std::string>{"r_knee_pitch", "l_knee_pitch"}));
}

// Rows that stand on the left foot (the angles stay the model's, rooted at the right foot): the left foot
// comes down where it is and stays there while the body moves around it, as the left-stance model
// (stance.hpp) rooted at that foot places every link; a base pose on a left row places the left ankle.
TEST(View, TheLeftFootHeldStillCarriesTheBody) {
  Scratch s;
  const M right(body), left(hd::left_stance_description(body));
  const auto names = ht::joint_names(body);
  const Q qa = some_pose(0), qb = some_pose(1.5);
  const auto clip = load(s, states_csv("stance", {{"right", qa}, {"left", qa}, {"l", qb}}, names));
  EXPECT_EQ(clip.stance, (std::vector<int>{0, 1, 1}));
  const int foot = right.joint_index("l_ankle_pitch");
  EXPECT_EQ(clip.left_foot_joint, foot);
  // the foot comes down where it is: nothing moves at the switch
  for (int k = 0; k < 34; ++k) EXPECT_EQ(point(clip, 1, k), point(clip, 0, k)) << k;
  // then it stays: the left ankle and sole where they were
  EXPECT_LE((point(clip, 2, 2 + 2 * foot) - point(clip, 1, 2 + 2 * foot)).norm(), 2e-4);
  EXPECT_LE((point(clip, 2, 3 + 2 * foot) - point(clip, 1, 3 + 2 * foot)).norm(), 2e-4);
  // and every link is where the left-stance model rooted at that foot puts it: the exact state map gives
  // the left model's base at the foot in the row of the switch, and its angles in the next row
  const hd::StanceSwitch<M, M> to_left(right, left);
  hd::StanceState<M> at_switch, next;
  to_left(right, left, qa, Q::Zero(), at_switch);
  to_left(right, left, qb, Q::Zero(), next);
  const M standing = hd::rebase(left, at_switch.base_pose);
  hd::Data<M> d(standing);
  hd::forward_kinematics(standing, d, next.q);
  const auto nearest = [&](const Eigen::Vector3d& p) {
    double e = 1e9;
    for (int k = 0; k < 34; ++k) e = std::min(e, (point(clip, 2, k) - p).norm());
    return e;
  };
  EXPECT_LE(nearest(standing.base_pose().p), 2e-4) << "the left ankle";
  for (int i = 0; i < 16; ++i) EXPECT_LE(nearest(d.oMi[std::size_t(i)].p), 2e-4) << left.joint_name(i);

  // a base pose on a left row is the left ankle's frame: the left model's home base pose stands at home
  const auto home = load(s, states_csv("", {{"", Q::Zero()}}, names));
  const auto& B = left.base_pose();
  const Eigen::Quaterniond u(B.R);
  std::string cells;
  for (const double v : {B.p.x(), B.p.y(), B.p.z(), u.w(), u.x(), u.y(), u.z()})
    cells.append(",").append(format_number(v));
  const auto placed = load(s, states_csv("stance,base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz",
                                         {{"left" + cells, Q::Zero()}}, names));
  for (int k = 0; k < 34; ++k) EXPECT_LE((point(placed, 0, k) - point(home, 0, k)).norm(), 2e-4) << k;
}

TEST(View, BasePoseColumnsPlaceTheStanceFoot) {
  Scratch s;
  const auto names = ht::joint_names(body);
  const Q q = some_pose(2);
  const auto still = load(s, states_csv("", {{"", q}}, names));
  // the base where it stands, then moved 1 m forward and turned half a turn about the vertical
  const auto& p = body.base_pose.p;
  const auto pose_cells = [](const Eigen::Vector3d& x, const Eigen::Matrix3d& R) {
    const Eigen::Quaterniond u(R);
    std::string cells;
    for (const double v : {x.x(), x.y(), x.z(), u.w(), u.x(), u.y(), u.z()})
      cells.append(cells.empty() ? "" : ",").append(format_number(v));
    return cells;
  };
  const Eigen::Matrix3d half_turn =
      Eigen::AngleAxisd(3.14159265358979323846, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto moved = load(s, states_csv("base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz",
                                        {{pose_cells(p, body.base_pose.R), q},
                                         {pose_cells(p + Eigen::Vector3d(1, 0, 0), half_turn * body.base_pose.R), q}},
                                        names));
  for (int k = 0; k < 34; ++k) {
    EXPECT_LE((point(moved, 0, k) - point(still, 0, k)).norm(), 2e-4) << k;
    const Eigen::Vector3d d = point(still, 0, k) - p;
    const Eigen::Vector3d turned(p.x() + 1 - d.x(), p.y() - d.y(), p.z() + d.z());
    EXPECT_LE((point(moved, 1, k) - turned).norm(), 2e-4) << k;
  }
}

TEST(View, TorquesAndTheGroundReactionReachTheClip) {
  Scratch s;
  const auto names = ht::joint_names(body);
  // the states as motion import writes them (phase, qd_, anatomical angles passed over), the torques as
  // id --ground-reaction writes them: the centre of pressure's cells empty where the foot pulls
  const std::string states = states_csv("t,phase,stance,r_knee_flexion,qd_r_knee_pitch",
                                        {{"0,right,r,0.3,1.5", some_pose(0)},
                                         {"0.5,flight,right,0.2,1", some_pose(1)},
                                         {"1,double,right,0.1,0.5", some_pose(2)}},
                                        names);
  const auto clip = load(s, states,
                         "t,phase,tau_r_knee_pitch,grf_fx,grf_fy,grf_fz,grf_mx,cop_x,cop_y,cop_z,foot_pulls\n"
                         "0,right,12.5,1,2,700,3,0.05,-0.09,0,0\n0.5,flight,-3.25,0,0,-10,3,,,,1\n"
                         "1,double,1,0,0,710,3,0.06,-0.08,0,0\n");
  EXPECT_EQ(clip.phase, (std::vector<std::string>{"right", "flight", "double"}));
  ASSERT_TRUE(clip.has_torques && clip.has_ground_reaction);
  const int knee = 1;
  EXPECT_TRUE(clip.has_tau[knee]);
  EXPECT_FALSE(clip.has_tau[0]);
  EXPECT_EQ(clip.tau[1][knee], -3.25);
  EXPECT_EQ(clip.grf[0], Eigen::Vector3d(1, 2, 700));
  EXPECT_EQ(clip.cop[0], Eigen::Vector3d(0.05, -0.09, 0));
  EXPECT_FALSE(clip.cop[1]) << "no centre of pressure where the foot pulls";
  EXPECT_EQ(clip.cop[2], Eigen::Vector3d(0.06, -0.08, 0));
  // the page's JSON carries them
  const auto j = nlohmann::json::parse(hd::cli::view_clip_json(clip));
  EXPECT_EQ(j["tau"][1][knee].get<double>(), -3.25);
  EXPECT_EQ(j["grf"][0][2].get<double>(), 700);
  EXPECT_TRUE(j["cop"][1].is_null());
  EXPECT_EQ(j["cop"][2][0].get<double>(), 0.06);
  EXPECT_EQ(j["phase"][1], "flight");
  EXPECT_EQ(j["joints"].size(), 16u);
}

TEST(View, BadInputNamesFileLineAndColumn) {
  Scratch s;
  const auto names = ht::joint_names(body);
  const std::string good = states_csv("t", {{"0", some_pose(0)}, {"0.1", some_pose(1)}}, names);
  const auto expect_error = [&](const std::string& states, const std::string& torques, const std::string& want) {
    const std::string e = load_error(s, states, torques);
    EXPECT_NE(e.find(want), std::string::npos) << "got: " << e << "\nwant: " << want;
  };
  std::string typo = good;
  typo.replace(typo.find("q_r_knee_pitch"), 14, "q_r_kne_pitch");
  expect_error(typo, "", "states.csv: line 1, column 3 'q_r_kne_pitch': unknown column");
  std::string base_typo = states_csv("base_x,base_y,base_z,base_yaw", {{"0,0,0,0", some_pose(0)}}, names);
  expect_error(base_typo, "", "states.csv: line 1, column 4 'base_yaw': unknown column");
  // the stance foot in id's words: right, left, r, l (not the numbers of old)
  expect_error(states_csv("stance", {{"1", some_pose(0)}}, names), "",
               "states.csv: line 2, column 1 'stance': '1' is not a stance foot (right, left, r or l)");
  expect_error(states_csv("t", {{"0", some_pose(0)}, {"0", some_pose(1)}}, names), "",
               "states.csv: line 3, column 1 't': time must increase");
  expect_error(
      states_csv("base_x,base_y,base_z,base_qw,base_qx,base_qy,base_qz", {{"0,0,0,2,0,0,0", some_pose(0)}}, names), "",
      "states.csv: line 2, column 4 'base_qw': the orientation quaternion (base_qw, base_qx, base_qy, base_qz) has "
      "norm 2, not 1");
  expect_error(states_csv("base_qw,base_qx,base_qy,base_qz", {{"1.00001,0,0,0", some_pose(0)}}, names), "",
               "states.csv: line 2, column 1 'base_qw': the orientation quaternion");  // 1e-6, as id
  expect_error(states_csv("base_x,base_y", {{"0,0", some_pose(0)}}, names), "",
               "states.csv: line 1: missing column 'base_z'");
  expect_error(good, "tau_r_knee_pitch\n1\n", "tau.csv: 1 rows, the states (");
  expect_error(good, "t,tau_r_knee_pitch\n0,1\n0.2,1\n",
               "tau.csv: line 3, column 1 't': time 0.2 differs from the states'");
  expect_error(good, "tau_r_knee\n1\n2\n", "tau.csv: line 1, column 1 'tau_r_knee': unknown column");
  expect_error(good, "grf_fx,grf_fy,grf_fz\n1,2,3\n4,5,6\n",
               "tau.csv: line 1: the ground reaction grf_fx, grf_fy, grf_fz goes with its centre of pressure");
  expect_error(good, "grf_fx,grf_fy,grf_fz,cop_x,cop_y\n1,2,3,0,0\n4,5,6,x,0\n",
               "tau.csv: line 3, column 4 'cop_x': 'x' is not a number");
  expect_error("t\n", "", "states.csv: line 1: missing column 'q_r_ankle_pitch'");
  // a torques file with nothing to show, and columns the command reads hidden by an invisible character
  expect_error(good, "t\n0\n0.1\n",
               "tau.csv: line 1: no tau_<joint> column of the model's joints and no ground reaction");
  expect_error(states_csv("t\u00A0", {{"0", some_pose(0)}}, names), "",
               "states.csv: line 1, column 1 't<U+00A0>': unknown column: the command reads 't'");
  expect_error(states_csv("stance\u200B", {{"left", some_pose(0)}}, names), "",
               "states.csv: line 1, column 1 'stance<U+200B>': unknown column: the command reads 'stance'");
  expect_error(good, "\u200Btau_r_knee_pitch\n1\n2\n",
               "tau.csv: line 1, column 1 '<U+200B>tau_r_knee_pitch': unknown column");
  // the page is UTF-8 text: a phase that is not is named, not passed to the page
  expect_error(states_csv("phase", {{"righ\xE9", some_pose(0)}}, names), "",
               "states.csv: line 2, column 1 'phase': the phase 'righ<0xE9>' is not UTF-8 text (byte 5)");
  // the page draws a body within 1e6 m of the origin: one beyond is named, not drawn at a null point
  expect_error(states_csv("base_x,base_y,base_z", {{"0,0,0", some_pose(0)}, {"1e305,0,0", some_pose(1)}}, names), "",
               "states.csv: line 3: the body reaches 1e+305 m from the origin on this row, beyond the 1e+06 m the "
               "page draws");
}

// Numbers beyond the page's rounding are kept, never turned into null; a file name that is not UTF-8 is
// shown in the title with its bytes spelt out.
TEST(View, LargeNumbersAndNamesThatAreNotUtf8ReachThePage) {
  Scratch s;
  const auto names = ht::joint_names(body);
  Q far = some_pose(0);
  far[3] = 1e303;  // rad: a pose like any other, whatever the turns
  const std::string tau = "tau_r_knee_pitch,grf_fx,grf_fy,grf_fz,cop_x,cop_y\n1e306,1e307,0,1,0,0\n";
  const hd::cli::ViewClip clip = load(s, states_csv("", {{"", far}}, names), tau);
  const nlohmann::json page = nlohmann::json::parse(hd::cli::view_clip_json(clip));
  EXPECT_EQ(page["q"][0][3].get<double>(), 1e303);
  EXPECT_EQ(page["tau"][0][1].get<double>(), 1e306);
  EXPECT_EQ(page["grf"][0][0].get<double>(), 1e307);
  for (const auto& x : page["points"][0]) EXPECT_TRUE(x.is_number()) << x;
  // the default title shows the file's name; a --title that is not UTF-8 is a usage error
  hd::cli::ViewInputs in;
  in.states = (s / "caf\xE9.csv").string();
  write_text(in.states, states_csv("", {{"", some_pose(0)}}, names));
  const hd::cli::ViewClip latin1 = hd::cli::load_view_clip(in, body);
  EXPECT_NE(latin1.title.find("caf<0xE9>.csv"), std::string::npos) << latin1.title;
  EXPECT_NO_THROW((void)hd::cli::view_clip_json(latin1));
  // the model's name as it is: one an imported clip gave it already shows its file's name (once shown twice,
  // its backslashes doubled)
  hd::ModelDescription<double> named = body;
  named.name = "new\\nline.bvh (scaled to the clip)";
  const hd::cli::ViewClip imported = hd::cli::load_view_clip(in, named);
  EXPECT_EQ(imported.title,
            in.states.substr(0, in.states.size() - 8) + "caf<0xE9>.csv, new\\nline.bvh (scaled to the clip)");
  in.title = "bad \xE9 title";
  EXPECT_THROW((void)hd::cli::load_view_clip(in, body), hd::cli::UsageError);
}

// A URDF or JSON body of another shape cannot stand on its left foot: said at the row that asks.
TEST(View, TheLeftFootNeedsTheSeedShape) {
  Scratch s;
  hd::ModelDescription<double> chain = body;
  chain.joints.resize(3);
  std::vector<std::string> names{chain.joints[0].name, chain.joints[1].name, chain.joints[2].name};
  write_text(s / "states.csv",
             "stance,q_" + names[0] + ",q_" + names[1] + ",q_" + names[2] + "\nright,0,0,0\nleft,0,0,0\n");
  hd::cli::ViewInputs in;
  in.states = (s / "states.csv").string();
  try {
    hd::cli::load_view_clip(in, chain);
    ADD_FAILURE() << "no error";
  } catch (const hd::cli::UsageError& e) {  // (a usage error, exit code 2, as in id)
    EXPECT_NE(std::string(e.what()).find(
                  "line 3, column 1 'stance': the left foot needs a body of the seed's shape with mirror-image sides"),
              std::string::npos)
        << e.what();
  }
}

// A body whose legs differ in length has no left-stance model that is the same body (the left-stance model
// is its mirror image): a left row is refused at that row, not drawn with the left foot misplaced.
TEST(View, TheLeftFootNeedsMirrorImageSides) {
  Scratch s;
  hd::ModelDescription<double> uneven = body;
  const hd::HumanModel<double> model(body);
  uneven.joints[std::size_t(model.joint_index("l_knee_pitch"))].dh.a += 0.05;  // a longer left shank
  std::string header = "stance", right = "right", left = "left";
  for (const auto& j : uneven.joints) {
    header += ",q_" + j.name;
    right += ",0";
    left += ",0";
  }
  write_text(s / "states.csv", header + "\n" + right + "\n" + left + "\n");
  hd::cli::ViewInputs in;
  in.states = (s / "states.csv").string();
  try {
    hd::cli::load_view_clip(in, uneven);
    ADD_FAILURE() << "no error";
  } catch (const hd::cli::UsageError& e) {
    EXPECT_NE(std::string(e.what()).find("line 3, column 1 'stance': the left foot needs a body of the seed's shape "
                                         "with mirror-image sides: stance switch: models"),
              std::string::npos)
        << e.what();
    EXPECT_NE(std::string(e.what()).find("do not describe the same body"), std::string::npos) << e.what();
  }
}

// The chain the viewer is for, on a real walk (CMU 07_08): `motion import` writes the states (t, phase, a
// text stance, base_ columns, q_/qd_/qdd_, anatomical angles) and the scaled body, `id --ground-reaction`
// the torques and the ground reaction, and `view` reads both as they are. The page's positions are the
// forward kinematics of that body on every row: on a right row the right-stance model standing on the
// base columns, on a left row the left-stance model (the exact state map) standing on them.
TEST(View, MotionImportThenIdThenView) {
  const std::filesystem::path clip = std::filesystem::path(HUMANDYN_SHARED_DATA) / "mocap" / "07_08.bvh";
  if (!std::filesystem::exists(clip)) GTEST_SKIP() << clip << " is absent (HUMANDYN_SHARED_DATA): not tested";
  Scratch s;
  for (const std::string& step : {"motion import '" + clip.string() + "' --cmu --out states.csv --model-out body.json",
                                  std::string("id --ground-reaction --model body.json --in states.csv --out tau.csv"),
                                  std::string("view states.csv --torques tau.csv --model body.json --out clip.html")}) {
    const auto run = ht::humandyn_cli(s, step);
    ASSERT_EQ(run.exit_code, 0) << step << "\n" << run.err;
  }
  const std::string page = ht::read_text(s / "clip.html");
  const std::string open = "<script id=\"clip\" type=\"application/json\">";
  const std::size_t from = page.find(open) + open.size(), to = page.find("</script>", from);
  const auto j = nlohmann::json::parse(page.substr(from, to - from));

  const auto description = hd::cli::parse_model_json(ht::read_text(s / "body.json"), "body.json");
  const M right(description), left(hd::left_stance_description(description));
  const hd::cli::CsvTable states = hd::cli::read_csv((s / "states.csv").string(), [](hd::cli::CsvTable& t) {
    t.keep_as_text(t.require_column("stance"));
    t.keep_as_text(t.require_column("phase"));
  });
  const std::size_t n = states.rows.size();
  ASSERT_GT(n, 100u);
  ASSERT_EQ(j["t"].size(), n);
  ASSERT_EQ(j["phase"].size(), n);
  ASSERT_FALSE(j["tau"].is_null());
  ASSERT_EQ(j["grf"].size(), n);
  const auto names = ht::joint_names(description);
  const auto cell = [&](std::size_t r, const std::string& name) {
    return states.rows[r][std::size_t(states.column(name))];
  };
  const auto point_of = [&](std::size_t f, int k) {
    const auto& p = j["points"][f];
    return Eigen::Vector3d(p[std::size_t(3 * k)], p[std::size_t(3 * k + 1)], p[std::size_t(3 * k + 2)]);
  };
  std::size_t rights = 0, lefts = 0;
  const hd::StanceSwitch<M, M> to_left(right, left);
  for (std::size_t f = 0; f < n; ++f) {
    Q q;
    for (int i = 0; i < 16; ++i) q[i] = cell(f, "q_" + names[std::size_t(i)]);
    const Eigen::Vector3d p(cell(f, "base_x"), cell(f, "base_y"), cell(f, "base_z"));
    const Eigen::Quaterniond u(cell(f, "base_qw"), cell(f, "base_qx"), cell(f, "base_qy"), cell(f, "base_qz"));
    const hd::Pose<double> B{u.normalized().toRotationMatrix(), p};
    const std::string& stance = states.text(f, states.column("stance"));
    EXPECT_EQ(j["phase"][f], states.text(f, states.column("phase")));
    EXPECT_EQ(j["stance"][f].get<int>(), stance == "left" ? 1 : 0);
    // every link frame's origin of the stance foot's model standing on the base columns, among the page's points
    std::vector<Eigen::Vector3d> links;
    if (stance == "left") {
      ++lefts;
      hd::StanceState<M> state;
      to_left(right, left, q, Q::Zero(), state);
      const M standing = hd::rebase(left, B);
      hd::Data<M> d(standing);
      hd::forward_kinematics(standing, d, state.q);
      links.push_back(B.p);
      for (int i = 0; i < 16; ++i) links.push_back(d.oMi[std::size_t(i)].p);
    } else {
      ++rights;
      const M standing = hd::rebase(right, B);
      hd::Data<M> d(standing);
      hd::forward_kinematics(standing, d, q);
      EXPECT_LE((point_of(f, 0) - B.p).norm(), 2e-4) << "frame " << f;
      for (int i = 0; i < 16; ++i)
        EXPECT_LE((point_of(f, 3 + 2 * i) - d.oMi[std::size_t(i)].p).norm(), 2e-4)
            << "frame " << f << " " << names[std::size_t(i)];
    }
    for (const auto& x : links) {
      double e = 1e9;
      for (int k = 0; k < 34; ++k) e = std::min(e, (point_of(f, k) - x).norm());
      EXPECT_LE(e, 2e-4) << "frame " << f;
    }
  }
  EXPECT_GT(rights, 0u);
  EXPECT_GT(lefts, 0u);
}

TEST(View, WritesOneSelfContainedPage) {
  Scratch s;
  write_text(s / "states.csv", states_csv("t", {{"0", some_pose(0)}, {"0.1", some_pose(1)}}, ht::joint_names(body)));
  const auto run = ht::humandyn_cli(s, "view states.csv --plot r_hip_pitch --out clip.html");
  ASSERT_EQ(run.exit_code, 0) << run.err;
  const std::string page = ht::read_text(s / "clip.html");
  EXPECT_TRUE(page.starts_with("<!DOCTYPE html>"));
  for (const char* external : {"http:", "https:", "src=", "href=", "@import", "url("})
    EXPECT_EQ(page.find(external), std::string::npos) << external;
  // the clip's JSON in its element, whole
  const std::string open = "<script id=\"clip\" type=\"application/json\">";
  const std::size_t from = page.find(open) + open.size(), to = page.find("</script>", from);
  const auto j = nlohmann::json::parse(page.substr(from, to - from));
  EXPECT_EQ(j["plot"], nlohmann::json::array({"r_hip_pitch"}));
  EXPECT_EQ(j["t"].size(), 2u);
  EXPECT_TRUE(j["tau"].is_null());

  // usage errors: an unknown --plot joint, no --out, --out over the input
  const auto unknown = ht::humandyn_cli(s, "view states.csv --plot r_knee --out clip.html");
  EXPECT_EQ(unknown.exit_code, 2);
  EXPECT_NE(unknown.err.find("--plot: model"), std::string::npos) << unknown.err;
  EXPECT_EQ(ht::humandyn_cli(s, "view states.csv").exit_code, 2);
  EXPECT_EQ(ht::humandyn_cli(s, "view states.csv --out states.csv").exit_code, 2);
  // without a t column, a rate so small that the times overflow
  write_text(s / "untimed.csv",
             states_csv("stance", {{"right", some_pose(0)}, {"right", some_pose(1)}, {"right", some_pose(2)}},
                        ht::joint_names(body)));
  const auto tiny = ht::humandyn_cli(s, "view untimed.csv --rate 1e-308 --out u.html");
  EXPECT_EQ(tiny.exit_code, 2);
  EXPECT_NE(tiny.err.find("--rate 1e-308: row 3's time is not finite"), std::string::npos) << tiny.err;
  EXPECT_FALSE(std::filesystem::exists(s / "u.html"));
  // a rate where the file gives every row's time, and an empty title: refused, not passed over
  for (const auto& [arguments, message] :
       {std::pair<std::string, std::string>{"view states.csv --rate 50 --out r.html",
                                            "humandyn view: --rate: states.csv has a column t, which gives every "
                                            "row's time"},
        {"view states.csv --title '' --out r.html", "humandyn view: --title is given an empty value"}}) {
    const auto r = ht::humandyn_cli(s, arguments);
    EXPECT_EQ(r.exit_code, 2) << arguments;
    EXPECT_NE(r.err.find(message), std::string::npos) << arguments << "\n" << r.err;
    EXPECT_FALSE(std::filesystem::exists(s / "r.html"));
  }
  EXPECT_EQ(ht::humandyn_cli(s, "view untimed.csv --rate 50 --out r.html").exit_code, 0);
  // a title with markup stays text: no "</" can close the script element
  const auto titled = ht::humandyn_cli(s, "view states.csv --title '</script><b>x' --out t.html");
  ASSERT_EQ(titled.exit_code, 0) << titled.err;
  EXPECT_EQ(ht::read_text(s / "t.html").find("</script><b>"), std::string::npos);
}

}  // namespace

}  // namespace test_view
