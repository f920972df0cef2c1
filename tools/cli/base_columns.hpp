// The base's columns of the CSV files of id, fd and simulate: its pose, velocity and acceleration, all
// in the world frame (z up, x forward, y left), each group all or none:
//
//   base_x, base_y, base_z               position of the base frame's origin (m)
//   base_qw, base_qx, base_qy, base_qz   orientation: unit quaternion, world from base (norm 1 within 1e-6)
//   base_wx, base_wy, base_wz            angular velocity (rad/s)
//   base_vx, base_vy, base_vz            velocity of the base origin (m/s)
//   base_wdx, base_wdy, base_wdz         angular acceleration (rad/s^2)
//   base_ax, base_ay, base_az            acceleration of the base origin (m/s^2), gravity not included
//
// A group left out is the base at rest in the model's base pose. The base is the stance foot (its ankle
// frame) in the stance-rooted form and the pelvis in the floating form (docs/base.md).
#pragma once

#include "cli/joint_table.hpp"
#include "humandyn/algorithm/rnea.hpp"

#include <initializer_list>
#include <string>
#include <string_view>
#include <vector>

namespace humandyn::cli {

enum class BaseGroup { Position, Orientation, AngularVelocity, Velocity, AngularAcceleration, Acceleration };

// The column names of one group, e.g. base_x, base_y, base_z.
std::vector<std::string> base_columns(BaseGroup group);

// The columns of a state: each base group's, then each prefix's joint columns, e.g. base_x, ..., q_<joint>,
// ..., qd_<joint>, ...
std::vector<std::string> state_columns(std::initializer_list<BaseGroup> base, const std::vector<std::string>& joints,
                                       std::initializer_list<std::string_view> prefixes);

// A stance-rooted motion's state as numbers, in the columns state_columns({Position, Orientation,
// AngularVelocity, AngularAcceleration, Acceleration}, joints, {"q_", "qd_", "qdd_"}): the base's position,
// orientation (w, x, y, z), angular velocity, angular acceleration and acceleration (world), then q, qd, qdd.
std::vector<double> stance_state_values(const BaseMotion<double>& base, const Eigen::Ref<const Eigen::VectorXd>& q,
                                        const Eigen::Ref<const Eigen::VectorXd>& qd,
                                        const Eigen::Ref<const Eigen::VectorXd>& qdd);

// The base's state and motion in the world.
struct BaseState {
  Pose<double> pose;
  Vec3<double> w = Vec3<double>::Zero(), v = Vec3<double>::Zero();   // rad/s; m/s
  Vec3<double> wd = Vec3<double>::Zero(), a = Vec3<double>::Zero();  // rad/s^2; m/s^2

  // The stance-rooted form's base motion (its origin's velocity enters no force).
  BaseMotion<double> motion() const {
    BaseMotion<double> m;
    m.pose = pose;
    m.w = w;
    m.wd = wd;
    m.a = a;
    return m;
  }
  // The floating form's base velocity v_b = (angular; linear of the origin), base-frame coordinates.
  SpatialVector<double> twist() const {
    SpatialVector<double> v_b;
    v_b << pose.R.transpose() * w, pose.R.transpose() * v;
    return v_b;
  }
  // Its time derivative a_b: R^T wd, and R^T a - w_b x v_b for the linear part (the velocity product
  // dropped with `coriolis` false, as floating_rnea adds it back only with the full terms).
  SpatialVector<double> twist_rate(bool coriolis) const {
    const SpatialVector<double> v_b = twist();
    SpatialVector<double> a_b;
    a_b << pose.R.transpose() * wd, pose.R.transpose() * a;
    if (coriolis) a_b.tail<3>() -= v_b.head<3>().cross(v_b.tail<3>());
    return a_b;
  }
};

// The base groups of a states file, every one optional, to append to a JointTable's groups.
class BaseColumns {
 public:
  // Appends the six groups to `groups`.
  explicit BaseColumns(std::vector<ColumnGroup>& groups);

  // Whether the file has any base column.
  bool any(const JointTable& table) const;
  // The base of row `row`; groups left out: at rest in `home`. InputError naming the cell for a
  // quaternion that is not of norm 1.
  BaseState read(const JointTable& table, std::size_t row, const Pose<double>& home) const;

 private:
  std::size_t first_ = 0;  // the index of the position group
};

}  // namespace humandyn::cli
