// Contact phases of a clip and the stance-rooted form per frame. Each foot is on the ground in a frame
// when its toe or its ankle landmark is low and slow; the two feet give the phase (right, left, double
// support, flight), the stance foot, and how the ground reaction is shared in double support. A filtered
// floating-form motion (motion/filter.hpp) is carried to the model rooted at the stance foot by the
// exact state maps (stance.hpp), with the foot's own motion as the moving base.
//
//   const Phases phases = contact_phases(clip);                // per frame: phase, stance foot, right share
//   const StanceForms forms(body.parameters);
//   StanceFrame s;
//   forms.stance_state(phases.stance[k], motion.frames[k], s);  // s.base (BaseMotion), s.q, s.qd, s.qdd
#pragma once

#include "humandyn/algorithm/ground_reaction.hpp"
#include "humandyn/floating.hpp"
#include "humandyn/motion/filter.hpp"
#include "humandyn/motion/fit.hpp"
#include "humandyn/stance.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

namespace humandyn::motion {

enum class Foot : std::uint8_t { right, left };
enum class Phase : std::uint8_t { flight, right, left, double_support };

/// A phase's name for CSV files: "flight", "right", "left", "double".
inline const char* phase_name(Phase p) {
  constexpr const char* names[] = {"flight", "right", "left", "double"};
  return names[int(p)];
}

/// When a foot is on the ground: its toe landmark at most `toe_height` above the floor, or its ankle at
/// most `ankle_height`, that landmark moving slower than `max_speed`. The floor under frame k is `floor`
/// when given (a number), otherwise the lowest toe or ankle landmark of either foot within `floor_window`
/// seconds of frame k (a floor that is not level across the capture volume, or not at zero, is followed).
/// A foot's contact then ignores blips: a gap shorter than `min_frames` between two contacts is filled,
/// and a contact shorter than that between two gaps is dropped.
struct ContactOptions {
  double floor = std::numeric_limits<double>::quiet_NaN();  ///< floor height (m); NaN: from the clip
  double floor_window = 1.0;                                ///< s either side of a frame
  double toe_height = 0.05;                                 ///< m above the floor
  double ankle_height = 0.10;                               ///< m above the floor
  double max_speed = 1.0;                                   ///< m/s (central differences of the landmark)
  int min_frames = 3;                                       ///< shortest contact or gap kept (frames)
};

/// A clip's contact phases, frame by frame.
struct Phases {
  std::vector<double> floor;                 ///< the floor height under each frame (m)
  std::vector<std::array<bool, 2>> contact;  ///< right, left foot on the ground
  std::vector<Phase> phase;
  std::vector<Foot> stance;         ///< the foot the stance-rooted form stands on
  std::vector<double> right_share;  ///< the right foot's share of the ground reaction (0 to 1)
};

namespace detail {

// Sets runs of `value` shorter than `min` that lie between two runs of the other value to the other value.
inline void drop_short_runs(std::vector<std::array<bool, 2>>& c, int foot, bool value, int min) {
  const int n = int(c.size());
  for (int a = 0; a < n;) {
    int b = a;
    while (b + 1 < n && c[std::size_t(b + 1)][std::size_t(foot)] == c[std::size_t(a)][std::size_t(foot)]) ++b;
    if (c[std::size_t(a)][std::size_t(foot)] == value && a > 0 && b + 1 < n && b - a + 1 < min)
      for (int k = a; k <= b; ++k) c[std::size_t(k)][std::size_t(foot)] = !value;
    a = b + 1;
  }
}

}  // namespace detail

/// The contact phases of a clip. Each foot's contact by ContactOptions; the phase from the two. The
/// share of the ground reaction: 1 on the foot in single support; across a double support, from the
/// trailing foot (the one in single support before it) to the leading one by a cosine transfer,
/// trailing share = (1 + cos(pi tau)) / 2 with tau = (k - first + 1) / (frames + 1) for the phase's k-th
/// frame (smooth, no jump at either end); a double support that has no single support before it takes
/// as trailing foot the one that is not in single support after it; the whole clip in double support
/// shares half and half. In flight, the share is that of the last frame on the ground (no reaction is
/// needed there). The stance foot is the one with the larger share (right on a tie).
/// \throws MotionError for a clip check_clip refuses or of fewer than 3 frames.
inline Phases contact_phases(const LandmarkClip& clip, const ContactOptions& options = {}) {
  using enum Landmark;
  check_clip(clip);
  const int n = int(clip.frames.size());
  if (n < 3)
    throw MotionError(clip.source + ": contact phases need 3 frames or more, the clip has " + std::to_string(n));
  const auto z = [&](int k, Landmark l) { return clip.frames[std::size_t(k)][std::size_t(l)].z(); };
  Phases out;
  out.floor.assign(std::size_t(n), options.floor);
  if (std::isnan(options.floor)) {
    std::vector<double> low(out.floor.size());
    for (int k = 0; k < n; ++k)
      low[std::size_t(k)] = std::min({z(k, r_toe), z(k, r_ankle), z(k, l_toe), z(k, l_ankle)});
    // (a window longer than the clip is the whole clip: no integer overflow for a tiny frame time)
    const double frames = std::round(options.floor_window / clip.frame_time);
    const int w = frames < n ? int(frames) : n;
    for (int k = 0; k < n; ++k)
      out.floor[std::size_t(k)] =
          *std::min_element(low.begin() + std::max(k - w, 0), low.begin() + std::min(k + w, n - 1) + 1);
  }
  const auto speed = [&](int k, Landmark l) {
    const int a = std::max(k - 1, 0), b = std::min(k + 1, n - 1);
    const auto& f = clip.frames;
    return (f[std::size_t(b)][std::size_t(l)] - f[std::size_t(a)][std::size_t(l)]).norm() / ((b - a) * clip.frame_time);
  };
  const auto down = [&](int k, Landmark toe, Landmark ankle) {
    const double floor = out.floor[std::size_t(k)];
    return (z(k, toe) - floor <= options.toe_height && speed(k, toe) <= options.max_speed) ||
           (z(k, ankle) - floor <= options.ankle_height && speed(k, ankle) <= options.max_speed);
  };
  out.contact.resize(std::size_t(n));
  out.phase.resize(std::size_t(n));
  for (int k = 0; k < n; ++k) out.contact[std::size_t(k)] = {down(k, r_toe, r_ankle), down(k, l_toe, l_ankle)};
  for (int foot = 0; foot < 2; ++foot) {
    detail::drop_short_runs(out.contact, foot, false, options.min_frames);
    detail::drop_short_runs(out.contact, foot, true, options.min_frames);
  }
  for (int k = 0; k < n; ++k) {
    const auto [r, l] = out.contact[std::size_t(k)];
    out.phase[std::size_t(k)] = r && l ? Phase::double_support : r ? Phase::right : l ? Phase::left : Phase::flight;
  }

  // the shares: single support, then each double support's transfer, then flight
  constexpr double pi = 3.14159265358979323846;
  out.right_share.assign(std::size_t(n), std::numeric_limits<double>::quiet_NaN());
  for (int k = 0; k < n; ++k) {
    const Phase p = out.phase[std::size_t(k)];
    if (p == Phase::right || p == Phase::left) out.right_share[std::size_t(k)] = p == Phase::right ? 1.0 : 0.0;
  }
  for (int a = 0; a < n;) {
    if (out.phase[std::size_t(a)] != Phase::double_support) {
      ++a;
      continue;
    }
    int b = a;
    while (b + 1 < n && out.phase[std::size_t(b + 1)] == Phase::double_support) ++b;
    const Phase before = a > 0 ? out.phase[std::size_t(a - 1)] : Phase::flight;
    const Phase after = b + 1 < n ? out.phase[std::size_t(b + 1)] : Phase::flight;
    double trailing_right = 0.5;  // the right foot's share at the start, 1 or 0 when a trailing foot is known
    if (before == Phase::right || before == Phase::left)
      trailing_right = before == Phase::right ? 1.0 : 0.0;
    else if (after == Phase::right || after == Phase::left)
      trailing_right = after == Phase::right ? 0.0 : 1.0;
    const int frames = b - a + 1;
    for (int k = a; k <= b; ++k) {
      const double tau = double(k - a + 1) / (frames + 1), s = 0.5 * (1 + std::cos(pi * tau));
      out.right_share[std::size_t(k)] =
          trailing_right == 0.5 ? 0.5 : trailing_right * s + (1 - trailing_right) * (1 - s);
    }
    a = b + 1;
  }
  // flight: the last share on the ground (or the first, before any contact; half and half with none)
  double last = std::numeric_limits<double>::quiet_NaN();
  for (int k = 0; k < n; ++k) {
    if (!std::isnan(out.right_share[std::size_t(k)]))
      last = out.right_share[std::size_t(k)];
    else
      out.right_share[std::size_t(k)] = last;
  }
  for (int k = n - 1; k >= 0; --k)
    if (!std::isnan(out.right_share[std::size_t(k)]))
      last = out.right_share[std::size_t(k)];
    else
      out.right_share[std::size_t(k)] = std::isnan(last) ? 0.5 : last;
  out.stance.resize(std::size_t(n));
  for (int k = 0; k < n; ++k)
    out.stance[std::size_t(k)] = out.right_share[std::size_t(k)] >= 0.5 ? Foot::right : Foot::left;
  return out;
}

/// One foot's part of a ground reaction: a force and a moment about `point` (world axes, N and N m).
struct FootWrench {
  Eigen::Vector3d force = Eigen::Vector3d::Zero(), moment = Eigen::Vector3d::Zero(), point = Eigen::Vector3d::Zero();
};

/// The ground reaction `total` split between the feet: the right foot takes `right_share` s of the force,
/// the left 1 - s, each at its own point (e.g. the ankle's ground projection); the moment those forces
/// do not make about the total's origin is shared in the same proportion. The two wrenches add up to the
/// total exactly; with s = 1 the right foot takes the whole reaction (its moment: the total's about its
/// point).
inline std::array<FootWrench, 2> split_reaction(const GroundReaction<double>& total, double right_share,
                                                const Eigen::Vector3d& right_point,
                                                const Eigen::Vector3d& left_point) noexcept {
  const double s = right_share;
  std::array<FootWrench, 2> w;
  w[0].point = right_point, w[1].point = left_point;
  w[0].force = s * total.force;
  w[1].force = (1 - s) * total.force;
  const Eigen::Vector3d rest =
      total.moment - (right_point - total.origin).cross(w[0].force) - (left_point - total.origin).cross(w[1].force);
  w[0].moment = s * rest;
  w[1].moment = (1 - s) * rest;
  return w;
}

/// A frame of the stance-rooted form: the stance foot, its motion as the moving base (its ankle frame's
/// pose, angular velocity and acceleration, its origin's acceleration; world), and the joint angles,
/// rates and accelerations of the model rooted on it (right: human_model; left: left_stance_model).
struct StanceFrame {
  Foot foot = Foot::right;
  BaseMotion<double> base;
  HumanModel<double>::JointVector q, qd, qdd;
};

/// The three forms of one body (rooted at the right foot, at the left foot, floating) and the exact maps
/// from the floating form to the other two. Built once (allocates, validates); stance_state is noexcept
/// and allocates nothing.
class StanceForms {
 public:
  explicit StanceForms(const SeedParameters& p)
      : models_{human_model(p), left_stance_model(p)}, floating_(floating_model(p)), fd_(floating_) {
    for (int f = 0; f < 2; ++f) {
      const HumanModel<double>& stance = models_[std::size_t(f)];
      const StanceSwitch<FloatingModel, HumanModel<double>> to(floating_, stance);
      // each stance joint's floating source, sign and offset: q_stance[k] = sign q[source] + offset
      StanceState<HumanModel<double>> m;
      const JointAngles zero = JointAngles::Zero();
      to(floating_, stance, zero, zero, m);
      auto& map = maps_[std::size_t(f)];
      map.offset = m.q;
      for (int j = 0; j < FloatingModel::nj; ++j) {
        to(floating_, stance, zero, JointAngles::Unit(j), m);
        for (int k = 0; k < FloatingModel::nj; ++k)
          if (std::abs(std::abs(m.qd[k]) - 1) < 1e-9)
            map.source[std::size_t(k)] = j, map.sign[k] = m.qd[k] > 0 ? 1 : -1;
      }
      // the foot: its link in the floating form, and the stance base frame on it
      const std::string& foot = stance.description().base_link_name;
      for (int k = 0; k < FloatingModel::nj; ++k)
        if (floating_.description().joints[std::size_t(k)].link_name == foot) map.foot_link = k;
      if (map.foot_link < 0) throw ModelError("stance forms: the floating form has no link '" + foot + "'");
      Data<FloatingModel> d(floating_);
      forward_kinematics(floating_, d, zero);
      map.foot_to_base = d.oMi[std::size_t(map.foot_link)].inverse() * stance.base_pose();
      // the map is exact: a pose away from home maps through it as through the state switch
      JointAngles q;
      for (int k = 0; k < FloatingModel::nj; ++k) q[k] = 0.6 * std::sin(1.3 * k + 0.4);
      to(floating_, stance, q, zero, m);
      for (int k = 0; k < FloatingModel::nj; ++k) {
        const double mine = map.sign[k] * q[map.source[std::size_t(k)]] + map.offset[k];
        if (!(std::abs(std::remainder(mine - m.q[k], 6.283185307179586)) < 1e-9))
          throw ModelError("stance forms: joint '" + stance.description().joints[std::size_t(k)].name +
                           "' is not a signed copy of a floating joint");
      }
    }
  }

  const HumanModel<double>& model(Foot foot) const noexcept { return models_[std::size_t(foot)]; }
  const FloatingModel& floating() const noexcept { return floating_; }

  /// The stance-rooted state of floating frame `f` on `foot`: q = sign x q_floating[source] + offset per
  /// joint (q̇ and q̈ by the same signs), the foot's ankle frame and its motion from the floating form's
  /// link velocities and accelerations (a Newton–Euler forward pass).
  void stance_state(Foot foot, const FloatingFrame& f, StanceFrame& out) const noexcept {
    const Map& map = maps_[std::size_t(foot)];
    out.foot = foot;
    for (int k = 0; k < FloatingModel::nj; ++k) {
      const int j = map.source[std::size_t(k)];
      out.q[k] = map.sign[k] * f.q[j] + map.offset[k];
      out.qd[k] = map.sign[k] * f.qd[j];
      out.qdd[k] = map.sign[k] * f.qdd[j];
    }
    // the foot link's motion: rnea's forward pass (link frames) and forward kinematics (moved to X)
    floating_rnea(floating_, fd_, f.base, f.v_b, f.a_b, f.q, f.qd, f.qdd);
    forward_kinematics(floating_, fd_.data, f.q);
    const auto l = std::size_t(map.foot_link);
    const Pose<double> link = f.base * floating_.base_pose().inverse() * fd_.data.oMi[l];
    const Eigen::Vector3d w = link.R * fd_.data.w[l], wd = link.R * fd_.data.wd[l];
    const Eigen::Vector3d a = link.R * fd_.data.acc_origin[l] + floating_.gravity();
    out.base.pose = link * map.foot_to_base;
    const Eigen::Vector3d r = out.base.pose.p - link.p;
    out.base.w = w;
    out.base.wd = wd;
    out.base.a = a + wd.cross(r) + w.cross(w.cross(r));
  }

 private:
  struct Map {
    std::array<int, FloatingModel::nj> source{};
    HumanModel<double>::JointVector sign, offset;
    int foot_link = -1;
    Pose<double> foot_to_base;  // the stance form's base frame on the floating form's foot link
  };
  std::array<HumanModel<double>, 2> models_;
  FloatingModel floating_;
  mutable FloatingData<FloatingModel> fd_;  // the maps' workspace (a StanceForms serves one thread)
  std::array<Map, 2> maps_;
};

}  // namespace humandyn::motion
