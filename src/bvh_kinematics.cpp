// Forward kinematics of a BVH skeleton, and the map from the file's axes and units to humandyn's world.
#include "bvh_text.hpp"

#include <Eigen/Geometry>

namespace humandyn::motion {

Eigen::Vector3d to_world(const Eigen::Vector3d& p, const WorldOptions& world) {
  const double s = world.metres_per_unit;
  return world.up == UpAxis::y ? Eigen::Vector3d(s * p.z(), s * p.x(), s * p.y()) : Eigen::Vector3d(s * p);
}

namespace {

// The elementary rotation about axis 0, 1 or 2 by `degrees`.
Eigen::Matrix3d axis_rotation(int axis, double degrees) {
  const double a = degrees * (M_PI / 180.0), c = std::cos(a), s = std::sin(a);
  const int i = (axis + 1) % 3, k = (axis + 2) % 3;
  Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
  r(i, i) = c, r(i, k) = -s, r(k, i) = s, r(k, k) = c;
  return r;
}

// The unit is usable and every joint's parent comes before it (the order forward kinematics walks).
void check_clip(const BvhClip& clip, const WorldOptions& world) {
  for (std::size_t i = 0; i < clip.joints.size(); ++i)
    if (clip.joints[i].parent < -1 || clip.joints[i].parent >= static_cast<int>(i))
      throw BvhError(clip.source + ": joint " + std::to_string(i) + " ('" + detail::shown(clip.joints[i].name) +
                     "') comes before its parent " + std::to_string(clip.joints[i].parent));
  if (!(world.metres_per_unit > 0) || !std::isfinite(world.metres_per_unit))
    throw BvhError(clip.source + ": the unit must be a positive number of metres per file unit, not " +
                   humandyn::exact_number(world.metres_per_unit));
}

// Every joint's position at one frame, in the world: parents come before their children in clip.joints.
void frame_positions(const BvhClip& clip, const double* values, const WorldOptions& world,
                     std::vector<Eigen::Matrix3d>& rotation, std::vector<Eigen::Vector3d>& position) {
  const std::size_t n = clip.joints.size();
  rotation.resize(n);
  position.resize(n);
  std::vector<Eigen::Vector3d> file_position(n);
  for (std::size_t i = 0; i < n; ++i) {
    const BvhJoint& j = clip.joints[i];
    Eigen::Vector3d t = j.offset;
    Eigen::Matrix3d r = Eigen::Matrix3d::Identity();
    for (const Channel c : j.channels) {
      const double v = *values++;
      const int axis = static_cast<int>(c) % 3;
      if (c <= Channel::Zposition)
        t[axis] += v;
      else
        r = r * axis_rotation(axis, v);  // R_1 R_2 ... R_k in the order listed
    }
    if (j.parent < 0) {
      rotation[i] = r;
      file_position[i] = t;
    } else {
      const auto p = static_cast<std::size_t>(j.parent);
      rotation[i] = rotation[p] * r;
      file_position[i] = file_position[p] + rotation[p] * t;
    }
    position[i] = to_world(file_position[i], world);
  }
}

}  // namespace

std::vector<Eigen::Vector3d> joint_positions(const BvhClip& clip, int frame, const WorldOptions& world) {
  check_clip(clip, world);
  if (frame < 0 || frame >= clip.frame_count())
    throw BvhError(clip.source + ": frame " + std::to_string(frame) + " is not in the clip's 0.." +
                   std::to_string(clip.frame_count() - 1));
  std::vector<Eigen::Matrix3d> rotation;
  std::vector<Eigen::Vector3d> position;
  frame_positions(clip, clip.values.data() + std::size_t(frame) * std::size_t(clip.channel_count()), world, rotation,
                  position);
  return position;
}

std::vector<std::vector<Eigen::Vector3d>> all_joint_positions(const BvhClip& clip, const WorldOptions& world) {
  check_clip(clip, world);
  const int frames = clip.frame_count();
  const auto channels = static_cast<std::size_t>(clip.channel_count());
  std::vector<std::vector<Eigen::Vector3d>> out(static_cast<std::size_t>(frames));
  std::vector<Eigen::Matrix3d> rotation;
  for (std::size_t f = 0; f < out.size(); ++f)
    frame_positions(clip, clip.values.data() + f * channels, world, rotation, out[f]);
  return out;
}

}  // namespace humandyn::motion
