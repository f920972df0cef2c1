// Named poses of the seed body: the joint angles a document, a help text or a benchmark calls by a
// name ("seated", "the left arm raised forward"), written once here. Every pitch axis of the seed body
// points left at the home pose (world: x forward, y left, z up), so a positive pitch swings a hanging
// limb backward and a negative one forward; on the stance leg, climbed from the foot, a negative knee
// pitch brings the hip back behind the knee. tests/test_poses.cpp proves by forward kinematics that
// each pose is the pose its name says.
#pragma once

#include "humandyn/model.hpp"

#include <array>
#include <cstdio>
#include <string>
#include <string_view>

namespace humandyn::poses {

inline constexpr double quarter_turn = 1.57079632679489661923;  // 90 degrees (rad)

/// One joint's angle in a named pose (rad); every joint a pose does not name is at 0.
struct JointAngle {
  std::string_view joint;
  double angle;
};

/// A pose by name: what it is, and the joints away from the home pose (q = 0: standing upright,
/// arms hanging).
template <std::size_t N>
struct NamedPose {
  std::string_view name;
  std::string_view what;
  std::array<JointAngle, N> angles;
};

/// Sitting on a chair: both thighs horizontal, pointing forward from the hips; both shanks vertical;
/// the trunk upright; both soles on the ground where they stand at home. The stance (right) leg is
/// climbed from the foot: the knee pitch brings the hip back, the hip pitch sets the trunk upright
/// again; the swing (left) leg hangs from the pelvis: the hip pitch swings the thigh forward, the
/// knee pitch folds the shank back down. Lock the legs of the `upper_body` scene here for a seated
/// crowd.
inline constexpr NamedPose<4> seated{"seated",
                                     "hips and knees bent by 90 degrees, thighs forward, shanks vertical",
                                     {{{"r_knee_pitch", -quarter_turn},
                                       {"r_hip_pitch", quarter_turn},
                                       {"l_hip_pitch", -quarter_turn},
                                       {"l_knee_pitch", quarter_turn}}}};

/// The seed paper's Table 2: the left arm raised forward by 90 degrees, horizontal, elbow straight.
inline constexpr NamedPose<1> left_arm_forward{
    "left_arm_forward", "the left arm raised forward to horizontal", {{{"l_shoulder_pitch", -quarter_turn}}}};

/// The pose's joint angles for `model`, every other joint at 0.
/// \return nj angles (rad), in the model's joint order
/// \throws ModelError naming the joint if the model has none of that name
template <class Model, std::size_t N>
typename Model::JointVector angles(const Model& model, const NamedPose<N>& pose) {
  typename Model::JointVector q = Model::JointVector::Zero(model.size());
  for (const auto& [joint, angle] : pose.angles) {
    const int i = model.joint_index(std::string(joint));
    if (i < 0)
      throw ModelError("pose '" + std::string(pose.name) + "': model '" + model.description().name +
                       "' has no joint '" + std::string(joint) + "'");
    q[i] = angle;
  }
  return q;
}

/// The pose as the command line's `--lock` takes it: "JOINT=ANGLE,..." with the angles in radians to
/// two decimals (e.g. "r_knee_pitch=-1.57,...").
template <std::size_t N>
std::string lock_text(const NamedPose<N>& pose) {
  std::string out;
  for (const auto& [joint, angle] : pose.angles) {
    char number[32];
    std::snprintf(number, sizeof number, "%.2f", angle);
    if (!out.empty()) out += ',';
    out.append(joint).append("=").append(number);
  }
  return out;
}

}  // namespace humandyn::poses
