// Anatomical joint angles. The DH angle q of a joint turns the joint's child link about the parent's z
// axis, and which link is the child depends on where the body is rooted: the stance leg is climbed from
// the foot up, so its knee's DH angle grows as the knee straightens while the swing knee's grows as it
// bends. Anatomical angles have one meaning whatever the root: each joint gets a name and a sign after
// the ISB's joint coordinate systems (Wu et al. 2002, J. Biomech. 35:543-548, hip, ankle and spine;
// Wu et al. 2005, J. Biomech. 38:981-992, shoulder and elbow): flexion, abduction and dorsiflexion
// positive, the trunk's axial rotation positive to the left. The map is exact: anatomical = sign x q
// (no offset: every form stands upright, arms hanging, at q = 0, which is the anatomical neutral pose),
// with one sign per joint and per form (docs/motion.md has the table; tests/test_anatomy.cpp proves each
// by forward kinematics).
#pragma once

#include "humandyn/body.hpp"

#include <array>
#include <cstdint>
#include <string_view>

namespace humandyn {

/// The three forms of the seed body: rooted at the right foot (human_model), at the left foot
/// (left_stance_model), or floating from the pelvis (floating_model).
enum class BodyForm : std::uint8_t { RightStance, LeftStance, Floating };

/// An anatomical joint: the DH joint it is (by its name in the right-stance seed table) and the
/// anatomical name of its angle, positive in the direction `positive` says.
struct AnatomicalJoint {
  const char* dh;
  const char* name;
  const char* positive;
};

/// The seed body's joints, anatomically, in the right-stance table's order (body.hpp).
inline constexpr std::array<AnatomicalJoint, 16> anatomical_joints{{
    {"r_ankle_pitch", "r_ankle_dorsiflexion", "toes up, towards the shin"},
    {"r_knee_pitch", "r_knee_flexion", "the shank backward, behind the thigh"},
    {"r_hip_roll", "r_hip_abduction", "the thigh out to the right, away from the mid-plane"},
    {"r_hip_pitch", "r_hip_flexion", "the thigh forward and up"},
    {"waist_pitch", "trunk_flexion", "the trunk forward over the pelvis"},
    {"waist_yaw", "trunk_rotation", "the shoulders turned to the left over the pelvis"},
    {"l_shoulder_pitch", "l_shoulder_flexion", "the arm forward and up"},
    {"l_shoulder_roll", "l_shoulder_abduction", "the arm out to the left, away from the trunk"},
    {"l_elbow_pitch", "l_elbow_flexion", "the forearm forward and up, towards the upper arm"},
    {"r_shoulder_pitch", "r_shoulder_flexion", "the arm forward and up"},
    {"r_shoulder_roll", "r_shoulder_abduction", "the arm out to the right, away from the trunk"},
    {"r_elbow_pitch", "r_elbow_flexion", "the forearm forward and up, towards the upper arm"},
    {"l_hip_pitch", "l_hip_flexion", "the thigh forward and up"},
    {"l_hip_roll", "l_hip_abduction", "the thigh out to the left, away from the mid-plane"},
    {"l_knee_pitch", "l_knee_flexion", "the shank backward, behind the thigh"},
    {"l_ankle_pitch", "l_ankle_dorsiflexion", "toes up, towards the shin"},
}};

/// The DH joint names of a form, by joint index: the right-stance table's; its mirror image for the left
/// stance (joint k is the mirror of the right-stance joint k); for the floating form, the right leg
/// re-hung from the pelvis (joints 0-3: hip pitch, hip roll, knee, ankle) and the others as in the table.
constexpr std::array<const char*, 16> form_joint_names(BodyForm form) {
  std::array<const char*, 16> out{};
  for (int k = 0; k < 16; ++k) {
    const auto i = std::size_t(k);
    switch (form) {
      case BodyForm::RightStance:
        out[i] = seed_body.joints[i].name;
        break;
      case BodyForm::LeftStance:
        out[i] = seed_body.joints[std::size_t(seed_body.mirror(k))].name;
        break;
      case BodyForm::Floating:
        out[i] = k < 4 ? seed_body.joints[std::size_t(seed_body.mirror(12 + k))].name : seed_body.joints[i].name;
        break;
    }
  }
  return out;
}

/// Where each anatomical joint is in a form and its sign: anatomical angle i = sign[i] x q[index[i]].
struct AnatomicalMap {
  std::array<int, 16> index{};
  std::array<int, 16> sign{};
};

/// The map of a form. The signs were found by forward kinematics and are proven by it
/// (tests/test_anatomy.cpp); docs/motion.md tabulates them. A joint of the leg a form stands on turns
/// the other way from the same joint hanging from the pelvis (the foot is its parent, the pelvis its
/// child); the left-stance form is the right-stance one's mirror image, so its signs are those of the
/// mirror joints, but for the trunk's axial rotation, which a mirror turns the other way.
constexpr AnatomicalMap anatomical_map(BodyForm form) {
  // signs in anatomical_joints' order: r_ankle r_knee r_hip_abd r_hip_flex trunk_flex trunk_rot
  // l_sh_flex l_sh_abd l_elbow r_sh_flex r_sh_abd r_elbow l_hip_flex l_hip_abd l_knee l_ankle
  // clang-format off
  constexpr std::array<int, 16> right_stance{1, -1, -1,  1, 1,  1, -1, -1, -1, -1,  1, -1, -1, -1,  1, -1};
  constexpr std::array<int, 16> left_stance{-1,  1, -1, -1, 1, -1, -1,  1, -1, -1, -1, -1,  1, -1, -1,  1};
  constexpr std::array<int, 16> floating{  -1,  1, -1, -1, 1,  1, -1, -1, -1, -1,  1, -1, -1, -1,  1, -1};
  // clang-format on
  AnatomicalMap m{};
  const auto names = form_joint_names(form);
  for (int i = 0; i < 16; ++i) {
    const std::string_view dh = anatomical_joints[std::size_t(i)].dh;
    for (int k = 0; k < 16; ++k)
      if (dh == names[std::size_t(k)]) m.index[std::size_t(i)] = k;
  }
  m.sign = form == BodyForm::RightStance ? right_stance : form == BodyForm::LeftStance ? left_stance : floating;
  return m;
}

namespace detail {
inline constexpr std::array<AnatomicalMap, 3> anatomical_maps{
    anatomical_map(BodyForm::RightStance), anatomical_map(BodyForm::LeftStance), anatomical_map(BodyForm::Floating)};
}  // namespace detail

/// The anatomical angles (rad, anatomical_joints' order) of the joint angles q (rad, the form's order).
/// The same map turns rates, accelerations and torques (sign x tau: the power is unchanged).
template <class Q, class Out>
constexpr void anatomical_angles(BodyForm form, const Q& q, Out& out) noexcept {
  const AnatomicalMap& m = detail::anatomical_maps[std::size_t(form)];
  for (int i = 0; i < 16; ++i) out[i] = m.sign[std::size_t(i)] * q[m.index[std::size_t(i)]];
}

/// The joint angles q (rad, the form's order) of anatomical angles (rad, anatomical_joints' order).
template <class A, class Out>
constexpr void dh_angles(BodyForm form, const A& anatomical, Out& q) noexcept {
  const AnatomicalMap& m = detail::anatomical_maps[std::size_t(form)];
  for (int i = 0; i < 16; ++i) q[m.index[std::size_t(i)]] = m.sign[std::size_t(i)] * anatomical[i];
}

}  // namespace humandyn
