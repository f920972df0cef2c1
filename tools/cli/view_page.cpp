#include "cli/view_page.hpp"

#include "cli/base_columns.hpp"
#include "cli/csv.hpp"
#include "cli/errors.hpp"
#include "cli/joint_table.hpp"
#include "cli/json.hpp"
#include "cli/stance_switching.hpp"
#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/data.hpp"
#include "humandyn/stance.hpp"
#include "text/shown.hpp"
#include "view_page_template.hpp"  // generated from tools/view_page.html: kViewPageTemplate

#include <fmt/format.h>
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

// x rounded to `per_unit` steps per unit, e.g. 1e4: to 0.1 mm (the page draws pixels; shorter numbers make
// a smaller page); dividing by the exact integer gives the nearest double to the decimal. A value with
// no digit below the step (2^52 steps and beyond) is kept as it is, not overflowed.
double rounded(double x, double per_unit) {
  const double steps = x * per_unit;
  return std::abs(steps) < 0x1p52 ? std::round(steps) / per_unit : x;
}

// How far from the origin a point of the drawn body may lie (m): the page's views span the body's path.
constexpr double max_view_reach = 1e6;

// The torques file into the clip, as `humandyn id` writes it: its tau_ columns by joint, and its ground
// reaction if it has one (grf_fx, grf_fy, grf_fz with cop_x, cop_y, cop_z, whose cells are empty on the
// rows where the foot would pull: no centre of pressure, no arrow); every other column passed over.
void read_torques(const std::string& path, const JointTable& states, ViewClip& clip) {
  const std::size_t nj = clip.joints.size();
  std::vector<ColumnGroup> groups;  // tau_<joint> one by one (id writes only some under a scene), then the force
  for (const auto& name : joint_columns(clip.joints, "tau_")) groups.push_back({{name}, ColumnGroup::Optional});
  groups.push_back({{"grf_fx", "grf_fy", "grf_fz"}, ColumnGroup::Optional});
  const std::vector<std::string> cop_columns{"cop_x", "cop_y", "cop_z"};
  const JointTable table(path, groups, {"tau_"}, cop_columns, StateForm::Any);
  const CsvTable& csv = table.csv();
  if (table.rows() != states.rows())
    throw InputError(csv.source + ": " + std::to_string(table.rows()) + " rows, the states (" + states.csv().source +
                     ") have " + std::to_string(states.rows()) + ": one row of torques per state");
  clip.has_torques = true;
  for (std::size_t i = 0; i < nj; ++i) clip.has_tau.push_back(table.has(i));
  // the ground reaction: the force with its centre of pressure (cop_z: 0, the ground, when left out)
  clip.has_ground_reaction = table.has(nj);
  if (std::none_of(clip.has_tau.begin(), clip.has_tau.end(), [](bool b) { return b; }) && !clip.has_ground_reaction)
    throw InputError(csv.source + ": line " + std::to_string(csv.header_line) +
                     ": no tau_<joint> column of the model's joints and no ground reaction (grf_fx, grf_fy, "
                     "grf_fz): no torque to show");
  if (clip.has_ground_reaction != (csv.column("cop_x") >= 0 && csv.column("cop_y") >= 0) ||
      (csv.column("cop_z") >= 0 && !clip.has_ground_reaction))
    throw InputError(csv.source + ": line " + std::to_string(csv.header_line) +
                     ": the ground reaction grf_fx, grf_fy, grf_fz goes with its centre of pressure cop_x, cop_y"
                     "[, cop_z]: all of them or none");
  Eigen::VectorXd value(1);
  for (std::size_t r = 0; r < table.rows(); ++r) {
    if (table.has_time() && states.has_time() && std::abs(table.time(r) - states.time(r)) > 1e-9)
      table.fail_at(r, "t",
                    "time " + format_number(table.time(r)) + " differs from the states' (" +
                        format_number(states.time(r)) + " on line " + std::to_string(states.csv().lines[r]) + " of " +
                        states.csv().source + ")");
    std::vector<double> values(nj, 0.0);
    for (std::size_t i = 0; i < nj; ++i)
      if (table.has(i)) {
        table.read(r, i, value);
        values[i] = rounded(value[0], 1e3);
      }
    clip.tau.push_back(std::move(values));
    if (!clip.has_ground_reaction) continue;
    Eigen::Vector3d force;
    table.read(r, nj, force);
    clip.grf.push_back(force);
    // the centre of pressure: every cell empty (the foot pulls) or every cell a number
    std::array<const std::string*, 3> cells{};
    for (std::size_t k = 0; k < 3; ++k) cells[k] = table.text(r, cop_columns[k]);
    const bool none = std::all_of(cells.begin(), cells.end(), [](const std::string* c) { return !c || c->empty(); });
    std::optional<Eigen::Vector3d> cop;
    if (!none) {
      cop = Eigen::Vector3d::Zero();
      for (std::size_t k = 0; k < 3; ++k) {
        std::string why;
        if (cells[k] && !parse_number(*cells[k], (*cop)[Eigen::Index(k)], why))
          table.fail_at(r, cop_columns[k], why + " (empty cells: all three, where the foot pulls)");
      }
    }
    clip.cop.push_back(cop);
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
      throw UsageError("--plot: model '" + text::shown(description.name) + "' has no joint '" + text::shown(name) +
                       "'");

  // the columns id reads: every q_<joint>, the base's, the stance foot; qd_, qdd_, phase and any other
  // column passed over (a misspelt q_, qd_, qdd_, tau_ or base_ column is an error)
  std::vector<ColumnGroup> groups{{joint_columns(clip.joints, "q_"), ColumnGroup::Required},
                                  {joint_columns(clip.joints, "qd_"), ColumnGroup::Ignored},
                                  {joint_columns(clip.joints, "qdd_"), ColumnGroup::Ignored}};
  const BaseColumns base_columns(groups);
  const JointTable states(in.states, groups, {"q_", "qd_", "qdd_", "tau_", "base_"}, {"stance", "phase"},
                          StateForm::StanceRooted);
  if (states.rows() == 0) throw InputError(states.csv().source + ": no rows: the clip needs at least one");
  if (!(in.rate > 0)) throw UsageError("--rate must be positive");
  if (in.rate_given && states.has_time())
    throw UsageError("--rate: " + states.csv().source + " has a column t, which gives every row's time");
  const bool has_phase = states.csv().column("phase") >= 0;

  // the stance foot's sole, in the base frame: straight below the base origin at home, at the ground
  const Pose<double>& home_base = model.base_pose();
  const Eigen::Vector3d sole = home_base.R.transpose() * Eigen::Vector3d(0, 0, -std::max(0.0, home_base.p.z()));

  StancePlacement where(model, base_columns, states);  // identity where the model stands
  Eigen::VectorXd q(nj);
  for (std::size_t r = 0; r < states.rows(); ++r) {
    // time
    const double t = states.has_time() ? states.time(r) : double(r) / in.rate;
    if (!std::isfinite(t))
      throw UsageError("--rate " + format_number(in.rate) + ": row " + std::to_string(r + 1) +
                       "'s time is not finite (a rate that small leaves no time a double can hold)");
    if (r > 0 && !(t > clip.t.back()))
      states.fail_at(
          r, "t",
          "time must increase from row to row (" + format_number(t) + " after " + format_number(clip.t.back()) + ")");
    clip.t.push_back(t);
    // the stance foot, read as id and fd read it
    const int stance = StanceSwitching::left_row(states, r) ? 1 : 0;
    clip.stance.push_back(stance);
    if (has_phase) {
      const std::string& phase = *states.text(r, "phase");
      if (const std::size_t at = text::first_non_utf8(phase); at != std::string::npos)
        states.fail_at(
            r, "phase",
            "the phase '" + text::shown(phase) + "' is not UTF-8 text (byte " + std::to_string(at + 1) + ")");
      clip.phase.push_back(phase);
    }

    // forward kinematics: the angles are the model's (the right-stance model's) on every row
    states.read(r, 0, q);
    forward_kinematics(model, data, q);
    // where the body stands: the file's base pose for the stance foot, or the stance foot held still
    const Pose<double> placement = where.at(r, stance == 1, data);

    std::vector<double> points;
    points.reserve(std::size_t(6 + 6 * nj));
    const auto add = [&](const Eigen::Vector3d& p) {
      if (!(p.cwiseAbs().maxCoeff<Eigen::PropagateNaN>() <= max_view_reach))  // (the default passes over a NaN)
        throw InputError(
            fmt::format("{}: line {}: the body reaches {:.3g} m from the origin on this row, beyond the "
                        "{:g} m the page draws (the row's base position, or the model's size)",
                        states.csv().source, states.csv().lines[r], p.stableNorm(), max_view_reach));
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
  clip.left_foot_joint = where.left_foot_link();

  if (!in.torques.empty()) read_torques(in.torques, states, clip);
  clip.plot = in.plot;
  if (clip.plot.empty()) {
    for (const char* knee : {"r_knee_pitch", "l_knee_pitch"})
      if (model.joint_index(knee) >= 0) clip.plot.push_back(knee);
    for (int i = 0; clip.plot.empty() && i < std::min(nj, 2); ++i) clip.plot.push_back(clip.joints[std::size_t(i)]);
  }
  // (the page is UTF-8: a file name that is not is shown with its bytes spelt out)
  if (const std::size_t at = text::first_non_utf8(in.title); at != std::string::npos)
    throw UsageError("--title '" + text::shown(in.title) + "' is not UTF-8 text (byte " + std::to_string(at + 1) + ")");
  // (the file's name shown as messages show it; the model's as it is, which an imported clip's already shows)
  clip.title = in.title.empty()
                   ? (in.states == "-" ? std::string("<stdin>") : text::shown(in.states)) + ", " + description.name
                   : in.title;
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
  j["phase"] = clip.phase.empty() ? Json() : Json(clip.phase);
  Json grf = Json::array(), cop = Json::array();
  for (std::size_t r = 0; r < clip.grf.size(); ++r) {
    grf.push_back({rounded(clip.grf[r].x(), 1e2), rounded(clip.grf[r].y(), 1e2), rounded(clip.grf[r].z(), 1e2)});
    const auto& c = clip.cop[r];  // null: the foot pulls, no arrow
    cop.push_back(c ? Json{rounded(c->x(), 1e4), rounded(c->y(), 1e4), rounded(c->z(), 1e4)} : Json());
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
