#include "cli/view_page.hpp"

#include "cli/csv.hpp"
#include "cli/errors.hpp"
#include "cli/json.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/data.hpp"
#include "humandyn/stance.hpp"
#include "view_page_template.hpp"  // generated from tools/view_page.html: kViewPageTemplate

#include <Eigen/Geometry>

#include <algorithm>
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

namespace humandyn::cli {

namespace {

using M = AnyModel<double>;

const std::array<std::string, 7> base_columns{"base_x", "base_y", "base_z", "base_qw", "base_qx", "base_qy", "base_qz"};
const std::array<std::string, 3> grf_columns{"grf_fx", "grf_fy", "grf_fz"};

// An error in the header of `table`, at column c (0-based), as the CSV reader words its own.
[[noreturn]] void fail_in_header(const CsvTable& table, int c, const std::string& message) {
  throw InputError(table.source + ": line " + std::to_string(table.header_line) + ", column " + std::to_string(c + 1) +
                   " " + shown(table.header[std::size_t(c)]) + ": " + message);
}

// x rounded to `per_unit` steps per unit, e.g. 1e4: to 0.1 mm (the page draws pixels; shorter numbers make
// a smaller page); dividing by the exact integer gives the nearest double to the decimal
double rounded(double x, double per_unit) { return std::round(x * per_unit) / per_unit; }

// The columns of the states file that the viewer reads.
struct StateColumns {
  std::vector<int> q;
  int t = -1, stance = -1;
  std::vector<int> base;  // empty, or the seven base pose columns
};

// The base pose in row r: position and unit quaternion (InputError naming the quaternion's first column
// if it is not a rotation).
Pose<double> base_pose_of(const CsvTable& table, std::size_t r, const std::vector<int>& base) {
  const auto& row = table.rows[r];
  const auto cell = [&](int k) { return row[std::size_t(base[std::size_t(k)])]; };
  Eigen::Quaterniond quaternion(cell(3), cell(4), cell(5), cell(6));
  const double norm = quaternion.norm();
  if (!(std::abs(norm - 1) <= 1e-3))
    table.fail_at(r, base[3],
                  "the base orientation (base_qw, base_qx, base_qy, base_qz) is not a unit quaternion (norm " +
                      format_number(norm) + ")");
  quaternion.normalize();
  return {quaternion.toRotationMatrix(), Eigen::Vector3d(cell(0), cell(1), cell(2))};
}

// The torques file into the clip: its tau_ columns by joint, its ground reaction if it has one.
void read_torques(const std::string& path, const CsvTable& states, int states_t, ViewClip& clip) {
  const std::size_t nj = clip.joints.size();
  std::vector<int> tau(nj, -1), grf, cop;
  int t = -1;
  const CsvTable table = read_csv(path, [&](const CsvTable& tab) {
    for (std::size_t c = 0; c < tab.header.size(); ++c) {
      const std::string& name = tab.header[c];
      if (!name.starts_with("tau_")) continue;
      const auto j = std::find(clip.joints.begin(), clip.joints.end(), name.substr(4));
      if (j == clip.joints.end())
        fail_in_header(tab, int(c), "unknown column: the model has no joint '" + name.substr(4) + "'");
      tau[std::size_t(j - clip.joints.begin())] = int(c);
    }
    t = tab.column("t");
    // the ground reaction: all three force columns or none; the centre of pressure with them
    const bool any = std::any_of(grf_columns.begin(), grf_columns.end(), [&](auto& n) { return tab.column(n) >= 0; }) ||
                     tab.column("cop_x") >= 0 || tab.column("cop_y") >= 0 || tab.column("cop_z") >= 0;
    if (any) {
      for (const auto& n : grf_columns) grf.push_back(tab.require_column(n));
      cop = {tab.require_column("cop_x"), tab.require_column("cop_y"), tab.column("cop_z")};
    }
  });
  if (table.rows.size() != states.rows.size())
    throw InputError(path + ": " + std::to_string(table.rows.size()) + " rows, the states (" + states.source +
                     ") have " + std::to_string(states.rows.size()) + ": one row of torques per state");
  clip.has_torques = true;
  for (std::size_t i = 0; i < nj; ++i) clip.has_tau.push_back(tau[i] >= 0);
  clip.has_ground_reaction = !grf.empty();
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const auto& row = table.rows[r];
    if (t >= 0 && states_t >= 0 && std::abs(row[std::size_t(t)] - states.rows[r][std::size_t(states_t)]) > 1e-9)
      table.fail_at(r, t,
                    "time " + format_number(row[std::size_t(t)]) + " differs from the states' (" +
                        format_number(states.rows[r][std::size_t(states_t)]) + " on line " +
                        std::to_string(states.lines[r]) + " of " + states.source + ")");
    std::vector<double> values(nj, 0.0);
    for (std::size_t i = 0; i < nj; ++i)
      if (tau[i] >= 0) values[i] = rounded(row[std::size_t(tau[i])], 1e3);
    clip.tau.push_back(std::move(values));
    if (clip.has_ground_reaction) {
      clip.grf.emplace_back(row[std::size_t(grf[0])], row[std::size_t(grf[1])], row[std::size_t(grf[2])]);
      clip.cop.emplace_back(row[std::size_t(cop[0])], row[std::size_t(cop[1])],
                            cop[2] >= 0 ? row[std::size_t(cop[2])] : 0.0);
    }
  }
}

}  // namespace

ViewClip load_view_clip(const ViewInputs& in, const ModelDescription<double>& description) {
  ViewClip clip;
  const M model(description);
  Data<M> data(model);
  const int nj = model.size();
  for (int i = 0; i < nj; ++i) {
    clip.joints.push_back(model.joint_name(i));
    clip.parent.push_back(model.joint(i).parent);
  }
  for (const auto& name : in.plot)
    if (std::find(clip.joints.begin(), clip.joints.end(), name) == clip.joints.end())
      throw UsageError("--plot: model '" + description.name + "' has no joint '" + name + "'");

  // the header: every q_<joint>; q_ of no joint is a typo; the base pose complete or absent
  StateColumns col;
  const CsvTable states = read_csv(in.states, [&](const CsvTable& tab) {
    for (std::size_t c = 0; c < tab.header.size(); ++c)
      if (tab.header[c].starts_with("q_") &&
          std::find(clip.joints.begin(), clip.joints.end(), tab.header[c].substr(2)) == clip.joints.end())
        fail_in_header(tab, int(c), "unknown column: the model has no joint '" + tab.header[c].substr(2) + "'");
    col.q = require_columns(tab, joint_columns(clip.joints, "q_"));
    col.t = tab.column("t");
    col.stance = tab.column("stance");
    if (std::any_of(base_columns.begin(), base_columns.end(), [&](auto& n) { return tab.column(n) >= 0; }))
      for (const auto& n : base_columns) col.base.push_back(tab.require_column(n));
  });
  if (states.rows.empty()) throw InputError(states.source + ": no rows: the clip needs at least one");
  if (!(in.rate > 0)) throw UsageError("--rate must be positive");

  // the left foot, when a row stands on it: the link of the model that is the left-stance model's base,
  // and that model's base frame seen from the link's frame (both standing at home)
  std::optional<std::pair<int, Pose<double>>> left_foot;
  const auto left = [&](std::size_t r) -> const std::pair<int, Pose<double>>& {
    if (!left_foot) {
      try {
        const ModelDescription<double> mirror = left_stance_description(description);
        int link = -1;
        for (int i = 0; i < nj; ++i)
          if (description.joints[std::size_t(i)].link_name == mirror.base_link_name) link = i;
        if (link < 0) throw ModelError("no link '" + mirror.base_link_name + "'");
        Data<M> home(model);
        forward_kinematics(model, home, Eigen::VectorXd::Zero(nj));
        left_foot.emplace(link, home.oMi[std::size_t(link)].inverse() * mirror.base_pose);
      } catch (const ModelError& e) {
        states.fail_at(r, col.stance,
                       std::string("the left foot (stance 1) needs a body of the seed's shape: ") + e.what());
      }
    }
    return *left_foot;
  };

  // the stance foot's sole, in the base frame: straight below the base origin at home, at the ground
  const Pose<double>& home_base = model.base_pose();
  const Eigen::Vector3d sole = home_base.R.transpose() * Eigen::Vector3d(0, 0, -std::max(0.0, home_base.p.z()));

  Pose<double> placement;  // world = placement * the model's world: identity where the model stands
  Pose<double> held;       // the left foot's link frame in the world while the body stands on it
  int previous = 0;        // the stance of the previous row
  Eigen::VectorXd q(nj);
  for (std::size_t r = 0; r < states.rows.size(); ++r) {
    const auto& row = states.rows[r];
    // time
    const double t = col.t >= 0 ? row[std::size_t(col.t)] : double(r) / in.rate;
    if (r > 0 && !(t > clip.t.back()))
      states.fail_at(
          r, col.t,
          "time must increase from row to row (" + format_number(t) + " after " + format_number(clip.t.back()) + ")");
    clip.t.push_back(t);
    // stance
    int stance = 0;
    if (col.stance >= 0) {
      const double s = row[std::size_t(col.stance)];
      if (s != 0 && s != 1) states.fail_at(r, col.stance, "stance must be 0 (the right foot) or 1 (the left foot)");
      stance = int(s);
    }
    clip.stance.push_back(stance);

    // forward kinematics: the angles are the model's (the right-stance model's) on every row
    for (int i = 0; i < nj; ++i) q[i] = row[std::size_t(col.q[std::size_t(i)])];
    forward_kinematics(model, data, q);
    // where the body stands: the file's base pose for the stance foot, or the stance foot held still
    if (stance == 1) {
      const auto& [link, offset] = left(r);
      if (!col.base.empty())
        held = base_pose_of(states, r, col.base) * offset.inverse();
      else if (r == 0 || previous == 0)  // the left foot comes down where it is
        held = placement * data.oMi[std::size_t(link)];
      placement = held * data.oMi[std::size_t(link)].inverse();
    } else if (!col.base.empty()) {
      placement = base_pose_of(states, r, col.base) * home_base.inverse();
    }  // else the right foot stays where it was
    previous = stance;

    std::vector<double> points;
    points.reserve(std::size_t(6 + 6 * nj));
    const auto add = [&](const Eigen::Vector3d& p) {
      for (int k = 0; k < 3; ++k) points.push_back(rounded(p[k], 1e4));
    };
    const Pose<double> base = placement * home_base;
    add(base.p);
    add(base * sole);
    std::vector<double> angles(std::size_t(nj), 0.0);
    for (int i = 0; i < nj; ++i) {
      const auto& j = model.joint(i);
      Pose<double> parent = j.parent < 0 ? home_base : data.oMi[std::size_t(j.parent)];
      if (j.mounted) parent = parent * Pose<double>{j.mount_R, j.mount_p};
      add(placement * parent.p);
      add(placement * data.oMi[std::size_t(i)].p);
      angles[std::size_t(i)] = rounded(q[i], 1e6);
    }
    clip.points.push_back(std::move(points));
    clip.q.push_back(std::move(angles));
  }
  clip.left_foot_joint = left_foot ? left_foot->first : -1;

  if (!in.torques.empty()) read_torques(in.torques, states, col.t, clip);
  clip.plot = in.plot;
  if (clip.plot.empty()) {
    for (const char* knee : {"r_knee_pitch", "l_knee_pitch"})
      if (model.joint_index(knee) >= 0) clip.plot.push_back(knee);
    for (int i = 0; clip.plot.empty() && i < std::min(nj, 2); ++i) clip.plot.push_back(clip.joints[std::size_t(i)]);
  }
  clip.title =
      in.title.empty() ? (in.states == "-" ? std::string("<stdin>") : in.states) + ", " + description.name : in.title;
  return clip;
}

std::string view_clip_json(const ViewClip& clip) {
  using json::Json;
  Json j;
  j["title"] = clip.title;
  j["joints"] = clip.joints;
  j["parent"] = clip.parent;
  j["left_foot_joint"] = clip.left_foot_joint;
  j["t"] = clip.t;
  j["stance"] = clip.stance;
  j["points"] = clip.points;
  j["q"] = clip.q;
  j["tau"] = clip.has_torques ? Json(clip.tau) : Json();
  j["has_tau"] = clip.has_torques ? Json(clip.has_tau) : Json();
  Json grf = Json::array(), cop = Json::array();
  for (std::size_t r = 0; r < clip.grf.size(); ++r) {
    grf.push_back({rounded(clip.grf[r].x(), 1e2), rounded(clip.grf[r].y(), 1e2), rounded(clip.grf[r].z(), 1e2)});
    cop.push_back({rounded(clip.cop[r].x(), 1e4), rounded(clip.cop[r].y(), 1e4), rounded(clip.cop[r].z(), 1e4)});
  }
  j["grf"] = clip.has_ground_reaction ? grf : Json();
  j["cop"] = clip.has_ground_reaction ? cop : Json();
  j["plot"] = clip.plot;
  std::string text = j.dump();
  // inside the page's <script> element no "</" may appear: '<' only occurs in strings, where \u003c is '<'
  std::string out;
  out.reserve(text.size());
  for (const char c : text) out += c == '<' ? std::string("\\u003c") : std::string(1, c);
  return out;
}

std::string view_page(const ViewClip& clip) {
  std::string page(kViewPageTemplate);
  const std::string marker = "/*CLIP_JSON*/null";
  const std::size_t at = page.find(marker);
  if (at == std::string::npos) throw std::logic_error("the page template has no " + marker);
  return page.replace(at, marker.size(), view_clip_json(clip));
}

}  // namespace humandyn::cli
