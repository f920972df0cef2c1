// `humandyn view`'s clip and page: a states CSV (the rows `simulate` writes, `id` reads, `motion import`
// writes) turned into every joint's and link frame's position per frame by forward kinematics, with the
// torques and the ground reaction of an `id` output beside them, written as one self-contained HTML page
// that only draws (tools/view_page.html, embedded in the binary).
//
// The states file: the columns `humandyn id` reads, with the same words and checks (tools/cli/joint_table.hpp,
// base_columns.hpp): q_<joint> (rad) for every joint of the model, the angles of the model as given
// (rooted at the right foot) on every row; optional
//   t                   time (s), increasing; without it, rows are 1/rate s apart
//   stance              the foot the body stands on, held still while the body moves around it: right (or
//                       r, the model's base) or left (or l; a body of the seed's shape)
//   base_x, base_y, base_z, base_qw, base_qx, base_qy, base_qz (and base_ velocities, passed over)
//                       the stance foot's ankle frame in the world (m; unit quaternion within 1e-6, scalar
//                       first): the base of the right- or the left-stance model (stance.hpp); without them
//                       the body stands where the model puts it, and a foot coming down stays where it is
//   phase               a label shown with its frame (e.g. the gait phase `motion import` writes)
// Every other column (qd_, qdd_, anatomical angles, ...) is passed over; a misspelt q_, qd_, qdd_, tau_ or
// base_ column is an error, as in id.
// The torques file, as `humandyn id [--ground-reaction]` writes it: tau_<joint> (N m) for any of the
// joints, one row per state (t, if both files have it, equal); optional ground reaction grf_fx, grf_fy,
// grf_fz (N, world) with its centre of pressure cop_x, cop_y (m, world) and cop_z (default 0, the ground),
// whose cells are empty on the rows where the foot would pull (no arrow there); other columns passed over.
#pragma once

#include "humandyn/model.hpp"

#include <Eigen/Core>

#include <optional>
#include <string>
#include <vector>

namespace humandyn::cli {

struct ViewInputs {
  std::string states;             // path ("-": standard input)
  std::string torques;            // path, "" for none
  std::vector<std::string> plot;  // joints plotted at first (empty: the knees, or the first two)
  double rate = 100;              // rows per second when the states have no t
  bool rate_given = false;        // the rate was asked for: refused where the states have t
  std::string title;              // the page's heading ("" : the file and the model)
};

struct ViewClip {
  std::string title;
  std::vector<std::string> joints;  // joint names, model order
  std::vector<int> parent;          // each joint's parent (-1: the base)
  int left_foot_joint = -1;         // the joint moving the left foot's link (-1: no row stands on it)
  std::vector<double> t;            // s, per frame
  std::vector<int> stance;          // 0 right, 1 left, per frame
  std::vector<std::string> phase;   // per frame, or empty: the file has no phase
  // per frame: the base frame's origin, then for each joint its centre (the parent frame's origin, after
  // the mount) and its link frame's origin, world (m): 3 (1 + 2 nj) numbers
  std::vector<std::vector<double>> points;
  std::vector<std::vector<double>> q;  // rad, per frame, model order
  bool has_torques = false;
  std::vector<std::vector<double>> tau;  // N m, per frame, model order (0 where the file has none)
  std::vector<bool> has_tau;             // per joint: a column in the torques file
  bool has_ground_reaction = false;
  std::vector<Eigen::Vector3d> grf;                 // N, world, per frame
  std::vector<std::optional<Eigen::Vector3d>> cop;  // m, world, per frame (none: the foot pulls)
  std::vector<std::string> plot;                    // the joints plotted at first
};

// Reads the states (and the torques) and places every link by forward kinematics; InputError naming the
// file, line and column of a bad cell, UsageError for a --plot joint the model lacks.
ViewClip load_view_clip(const ViewInputs& inputs, const ModelDescription<double>& description);

// The page: the template with the clip as JSON (UTF-8 text, no external resource).
std::string view_page(const ViewClip& clip);

// The clip's JSON as the page embeds it (for tests).
std::string view_clip_json(const ViewClip& clip);

}  // namespace humandyn::cli
