// The human body, described once: one constexpr table per body, one row per joint. Everything the
// engine knows about a body's structure is derived from its table: the static shape the algorithms
// unroll over (BodyShape), the joint and link names, the joint sets of the named scenes (groups), the
// mirror map of stance switching, and the DH rows and segments the builders fill in with a person's
// dimensions (builders.hpp). Changing one chain of a body, or making a variant of it, is an edit of
// its table: joints refer to each other by name, so rows can be added or removed without renumbering.
#pragma once

#include "humandyn/shape.hpp"

#include <array>
#include <cstdint>
#include <string_view>

namespace humandyn {

/// A dimension of the seed body (SeedParameters, builders.hpp; Table 1's lengths, in metres).
/// None: no dimension (a zero length).
enum class Dim : std::uint8_t { None, a1, a2, d4, d6, d7, a8, a9, a16 };

/// A length of a DH row: zero (Dim::None), or plus or minus one of the body's dimensions.
struct Length {
  Dim dim = Dim::None;   ///< the dimension; Dim::None: zero
  std::int8_t sign = 1;  ///< +1 or -1
  /// Zero.
  constexpr Length() = default;
  /// Implicit: a dimension is a length.
  constexpr Length(Dim d, int s = 1) : dim(d), sign(std::int8_t(s)) {}
};
/// Minus a dimension: `-d7` is the length -d7.
constexpr Length operator-(Dim d) { return {d, -1}; }

/// A DH row as a formula of the body's dimensions: a and d are lengths, the twist alpha and the offset
/// theta are special angles (0, ±90°, 180°). alpha is the link's twist class, which the algorithms
/// specialise on.
struct DHFormula {
  Length a;                   ///< DH a (m)
  Twist alpha = Twist::Zero;  ///< DH twist alpha
  Length d;                   ///< DH d (m)
  Twist theta = Twist::Zero;  ///< DH offset theta, added to the joint angle
};

/// The chains of a human body. A joint belongs to one; unions name the limbs.
namespace group {
/// One bit per chain (BodyJoint::group).
inline constexpr unsigned right_leg = 1u << 0, waist = 1u << 1, left_arm = 1u << 2, right_arm = 1u << 3,
                          left_leg = 1u << 4;
/// The limbs: both legs, both arms.
inline constexpr unsigned legs = right_leg | left_leg, arms = left_arm | right_arm;
}  // namespace group

/// The body segment a link carries (a member of SeedParameters), or none: Massless.
/// StanceFoot: the base body (SeedParameters::stance_foot).
enum class Part : std::uint8_t { Massless, Shank, Thigh, Pelvis, UpperBody, UpperArm, Forearm, Hand, Foot, StanceFoot };

/// Where a segment lies at the home pose, from its proximal joint centre (first) towards its distal one.
/// "Own" is the origin of the link's frame (its distal DH frame), "parent" that of the parent link's
/// frame (the base frame for a root joint).
enum class Span : std::uint8_t {
  ParentToOwn,   ///< along the link, from the parent's frame to the link's own (a limb hanging outwards)
  OwnToParent,   ///< along the link, from its own frame back to the parent's (a limb climbed from its end)
  ParentOnward,  ///< from the parent's frame, on along the line from the grandparent's frame to it
  ParentDown,    ///< from the parent's frame straight down (a foot: ankle to sole)
  OwnDown,       ///< from the link's own frame straight down (the stance foot on the base frame)
  OwnUp,         ///< from the link's own frame straight up (the trunk from the mid-hip point)
};

/// One joint and the link it moves.
struct BodyJoint {
  const char* name;               ///< the joint (names CSV columns: q_<name>, tau_<name>, ...)
  const char* link;               ///< the link it moves
  const char* parent;             ///< the joint whose link it hangs from; nullptr: the base
  DHFormula dh;                   ///< its DH row
  const char* mirror;             ///< the joint in the mirror image across the body's mid-plane (itself if on it)
  unsigned group = 0;             ///< the chain it belongs to (group::...)
  Part part = Part::Massless;     ///< the segment its link carries
  Span span = Span::ParentToOwn;  ///< where that segment lies
};

namespace detail {
constexpr bool same_name(const char* a, const char* b) { return a && b && std::string_view(a) == std::string_view(b); }
}  // namespace detail

/// A body: its base link and one row per joint, parents before children.
template <int N>
struct BodyTable {
  static constexpr int size = N;    ///< number of joints
  const char* base_link;            ///< the link fixed to the base frame
  Part base_part;                   ///< the segment on it (hanging OwnDown from the base frame)
  std::array<BodyJoint, N> joints;  ///< one row per joint, parents before children

  /// Index of the joint called `name`, -1 if none.
  constexpr int index(std::string_view name) const {
    for (int i = 0; i < N; ++i)
      if (joints[std::size_t(i)].name && name == joints[std::size_t(i)].name) return i;
    return -1;
  }
  /// Index of the joint whose link is called `link`, -1 if none (the base link has no joint).
  constexpr int link_index(std::string_view link) const {
    for (int i = 0; i < N; ++i)
      if (joints[std::size_t(i)].link && link == joints[std::size_t(i)].link) return i;
    return -1;
  }
  /// Index of joint i's parent, -1 if it hangs from the base.
  constexpr int parent(int i) const {
    const char* p = joints[std::size_t(i)].parent;
    return p ? index(p) : -1;
  }
  /// Index of joint i's mirror partner (BodyJoint::mirror), -1 if none.
  constexpr int mirror(int i) const {
    const char* m = joints[std::size_t(i)].mirror;
    return m ? index(m) : -1;
  }
  /// Whether joint i's link carries no segment (Part::Massless).
  constexpr bool massless(int i) const { return joints[std::size_t(i)].part == Part::Massless; }

  /// The joints in any of `groups` (group::...), as a joint set over the body's joints.
  constexpr JointSet<N> joint_set(unsigned groups) const {
    JointSet<N> s;
    for (int i = 0; i < N; ++i) s.set(i, (joints[std::size_t(i)].group & groups) != 0);
    return s;
  }

  /// Every joint's parent, by index (parent(i)).
  constexpr std::array<int, N> parents() const {
    std::array<int, N> out{};
    for (int i = 0; i < N; ++i) out[std::size_t(i)] = parent(i);
    return out;
  }
  /// Every joint's mirror partner, by index (mirror(i)).
  constexpr std::array<int, N> mirrors() const {
    std::array<int, N> out{};
    for (int i = 0; i < N; ++i) out[std::size_t(i)] = mirror(i);
    return out;
  }

  /// The link in the mirror image of link `l` (-1: the base link), as the joint moving it (-1: the base;
  /// -2: none): the link that touches the mirrors of the joints link l touches (its own joint and its
  /// children's).
  constexpr int mirror_link(int l) const { return mirror_link(l, parents(), mirrors()); }
  /// As above, from given parent and mirror indices (parents(), mirrors()).
  static constexpr int mirror_link(int l, const std::array<int, N>& parent, const std::array<int, N>& mirror) {
    const auto touching = [&](int k) {
      std::uint64_t s = k >= 0 ? std::uint64_t(1) << k : 0;
      for (int i = 0; i < N; ++i)
        if (parent[std::size_t(i)] == k) s |= std::uint64_t(1) << i;
      return s;
    };
    std::uint64_t want = 0;
    const std::uint64_t own = touching(l);
    for (int i = 0; i < N; ++i)
      if (own >> i & 1u) want |= std::uint64_t(1) << mirror[std::size_t(i)];
    for (int k = -1; k < N; ++k)
      if (touching(k) == want) return k;
    return -2;
  }
  /// The name of link `l`, the link of joint l (-1: the base link).
  constexpr const char* link_name(int l) const { return l < 0 ? base_link : joints[std::size_t(l)].link; }

  /// Joint names in joint order.
  constexpr std::array<const char*, N> joint_names() const {
    std::array<const char*, N> out{};
    for (int i = 0; i < N; ++i) out[std::size_t(i)] = joints[std::size_t(i)].name;
    return out;
  }
  /// Link names in joint order (the link each joint moves).
  constexpr std::array<const char*, N> link_names() const {
    std::array<const char*, N> out{};
    for (int i = 0; i < N; ++i) out[std::size_t(i)] = joints[std::size_t(i)].link;
    return out;
  }

  /// The static shape: parents, twist classes (the DH alphas), no mounts, massless links.
  constexpr ShapeSpec<N> shape_spec() const {
    ShapeSpec<N> s{};
    s.parent = parents();
    for (int i = 0; i < N; ++i) {
      s.twist[std::size_t(i)] = joints[std::size_t(i)].dh.alpha;
      s.massless[std::size_t(i)] = massless(i);
    }
    return s;
  }

  /// Whether the table is well formed: names unique and known, the first joint the only root (the
  /// stance ankle), parents before children, the mirror an involution that maps every link onto a
  /// link, DH angles special, at most 64 joints.
  constexpr bool valid() const {
    if (N > 64) return false;
    const auto parent = parents();
    const auto mirror = mirrors();
    for (int i = 0; i < N; ++i) {
      const BodyJoint& j = joints[std::size_t(i)];
      if (!j.name || !j.link || index(j.name) != i || link_index(j.link) != i || detail::same_name(j.link, base_link))
        return false;
      const int p = parent[std::size_t(i)], m = mirror[std::size_t(i)];
      if (j.parent ? !(p >= 0 && p < i) : i != 0) return false;
      if (m < 0 || mirror[std::size_t(m)] != i) return false;
      if (j.dh.alpha == Twist::General || j.dh.theta == Twist::General) return false;
      if (mirror_link(i, parent, mirror) == -2) return false;
    }
    return mirror_link(-1, parent, mirror) != -2;
  }
};

/// A variant of `body` with the joint `row` added right after the joint it hangs from (parents stay
/// before children; rows refer to each other by name, so nothing is renumbered). The new joint's
/// mirror must be added too, and the table still be valid (BodyShape checks it).
/// \param body  the table to extend
/// \param row   the new joint; row.parent names the joint of `body` it hangs from
/// \return the table with N + 1 joints
template <int N>
constexpr BodyTable<N + 1> with_joint(const BodyTable<N>& body, const BodyJoint& row) {
  BodyTable<N + 1> out{body.base_link, body.base_part, {}};
  const int at = row.parent ? body.index(row.parent) + 1 : 0;
  for (int i = 0, k = 0; i <= N; ++i) out.joints[std::size_t(i)] = i == at ? row : body.joints[std::size_t(k++)];
  return out;
}

// clang-format off
/// The seed's 16-joint human (Table 1 of the paper), rooted at the right (stance) ankle, in five chains:
/// right leg 1-4, waist 5-6, left arm 7-9, right arm 10-12, left leg 13-16 (1-based as in the paper).
/// Branch points: the pelvis (waist and left leg) and the upper body (both arms). Table 1's "hip yaw"
/// joints turn about the forward axis and are named roll here, its "waist roll" turns about the
/// vertical and is named yaw, and its "shoulder yaw" is an ab-adduction, named roll. Table 1's zero
/// masses are the links carrying no part: hip roll, waist pitch, shoulder pitch and the left hip pitch;
/// its massless pelvis may carry the lower trunk.
inline constexpr BodyTable<16> seed_body = [] {
  using enum Dim;
  using enum Twist;
  using enum Part;
  using enum Span;
  using namespace group;
  return BodyTable<16>{"r_foot", StanceFoot, {{
      // name                link               parent              DH row {a, alpha, d, theta}            mirror              group      part, span
      {"r_ankle_pitch",    "r_shank",         nullptr,            {a1, Zero, None, Zero},                "l_ankle_pitch",    right_leg, Shank, OwnToParent},
      {"r_knee_pitch",     "r_thigh",         "r_ankle_pitch",    {a2, HalfPi, None, Zero},              "l_knee_pitch",     right_leg, Thigh, OwnToParent},
      {"r_hip_roll",       "r_hip_link",      "r_knee_pitch",     {None, MinusHalfPi, None, Zero},       "l_hip_roll",       right_leg, Massless},
      {"r_hip_pitch",      "pelvis",          "r_hip_roll",       {None, Zero, d4, MinusHalfPi},         "l_hip_pitch",      right_leg, Pelvis, OwnUp},
      {"waist_pitch",      "waist_link",      "r_hip_pitch",      {None, MinusHalfPi, None, Zero},       "waist_pitch",      waist,     Massless},
      {"waist_yaw",        "upper_body",      "waist_pitch",      {None, HalfPi, d6, Zero},              "waist_yaw",        waist,     UpperBody, ParentToOwn},
      {"l_shoulder_pitch", "l_shoulder_link", "waist_yaw",        {None, MinusHalfPi, d7, MinusHalfPi},  "r_shoulder_pitch", left_arm,  Massless},
      {"l_shoulder_roll",  "l_upper_arm",     "l_shoulder_pitch", {a8, HalfPi, None, Zero},              "r_shoulder_roll",  left_arm,  UpperArm, ParentToOwn},
      {"l_elbow_pitch",    "l_forearm",       "l_shoulder_roll",  {a9, Zero, None, Zero},                "r_elbow_pitch",    left_arm,  Forearm, ParentToOwn},
      {"r_shoulder_pitch", "r_shoulder_link", "waist_yaw",        {None, MinusHalfPi, -d7, MinusHalfPi}, "l_shoulder_pitch", right_arm, Massless},
      {"r_shoulder_roll",  "r_upper_arm",     "r_shoulder_pitch", {a8, HalfPi, None, Zero},              "l_shoulder_roll",  right_arm, UpperArm, ParentToOwn},
      {"r_elbow_pitch",    "r_forearm",       "r_shoulder_roll",  {a9, Zero, None, Zero},                "l_elbow_pitch",    right_arm, Forearm, ParentToOwn},
      {"l_hip_pitch",      "l_hip_link",      "r_hip_pitch",      {None, MinusHalfPi, d4, MinusHalfPi},  "r_hip_pitch",      left_leg,  Massless},
      {"l_hip_roll",       "l_thigh",         "l_hip_pitch",      {a2, HalfPi, None, Zero},              "r_hip_roll",       left_leg,  Thigh, ParentToOwn},
      {"l_knee_pitch",     "l_shank",         "l_hip_roll",       {a1, Zero, None, Zero},                "r_knee_pitch",     left_leg,  Shank, ParentToOwn},
      {"l_ankle_pitch",    "l_foot",          "l_knee_pitch",     {a16, Zero, None, Zero},               "r_ankle_pitch",    left_leg,  Foot, ParentDown},
  }}};
}();
// clang-format on

/// The static shape of a body table: what the algorithms unroll over. Does not compile unless the
/// table is valid().
template <const auto& Body>
struct BodyShape {
  static_assert(Body.valid(), "the body table is not well formed (names, parents, mirrors, angles)");
  static constexpr const auto& body = Body;                         ///< the table
  static constexpr int nj = Body.size;                              ///< number of joints
  static constexpr bool is_static = true;                           ///< known when compiling: loops unroll
  static constexpr ShapeSpec<nj> spec = Body.shape_spec();          ///< per-joint facts (BodyTable::shape_spec)
  static constexpr int num_chains = count_chains(spec.parent, nj);  ///< number of serial chains
  /// The serial chains (split_chains), in joint order.
  static constexpr std::array<ChainSpec, num_chains> chains = [] {
    std::array<ChainSpec, num_chains> out{};
    split_chains(spec.parent, nj, out);
    return out;
  }();
};

/// The seed body's shape.
using SeedShape = BodyShape<seed_body>;
static_assert(SeedShape::num_chains == 5, "the seed body has five chains");

}  // namespace humandyn
