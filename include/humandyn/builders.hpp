// Builders of a human body from its table (body.hpp; the seed's 16 joints by default): the table's DH
// rows for a person's lengths, loaded with the person's segments.
//   human_description<table>(p)    the body as a description, for any lengths and segments
//   human_model(parameters)        the seed body, validated
//   de_leva_parameters(h, m, sex)  a person scaled from de Leva (1996)
//   default_parameters()           the embedded default: de Leva's reference male, 1.741 m, 73.0 kg
//   paper_parameters()             Table 1 with lengths of a 1.7 m adult, de Leva's male segments
#pragma once

#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/anthropometry.hpp"
#include "humandyn/data.hpp"
#include "humandyn/model.hpp"

#include <array>
#include <cmath>
#include <string>
#include <tuple>
#include <utility>

namespace humandyn {

/// A body segment, described at the home pose (standing, arms hanging) in segment axes: x forward,
/// z from the segment's proximal joint towards its distal one, y = z x x, the origin at the proximal
/// joint centre.
using Segment = RigidBodyInertia<double>;

/// Everything that makes a seed human: Table 1's lengths (m) and the segments on its links.
struct SeedParameters {
  std::string name = "human";  ///< the description's name
  /// Table 1's lengths (m).
  double a1 = 0, a2 = 0, d4 = 0, d6 = 0, d7 = 0, a8 = 0, a9 = 0, a16 = 0;
  Segment shank;           ///< links 1 and 15 (m1): knee to ankle
  Segment thigh;           ///< links 2 and 14 (m2): hip to knee
  Segment pelvis;          ///< link 4: the lower trunk, from the mid-hip point up (massless in Table 1)
  Segment upper_body;      ///< link 6 (m6): the rest of the trunk and the head, from the mid-hip point up
  Segment upper_arm;       ///< links 8 and 11 (m8): shoulder to elbow
  Segment forearm;         ///< links 9 and 12 (m9): forearm and hand, elbow to wrist
  Segment hand;            ///< a hand beyond the wrist, for bodies with a wrist joint (the seed's is in `forearm`)
  Segment foot;            ///< link 16 (m16), the free foot: ankle down to the sole, x along the foot
  Segment stance_foot;     ///< the base body (counts for the centre of mass only)
  Pose<double> base_pose;  ///< the right ankle frame in the world
};

/// Where a body of the lengths in `p` stands at q = 0, as the built-in bodies do: the pose of the right
/// ankle frame in the world (x_world = R x_base + p, m), x0 up the shank, z0 (the ankle's axis) to the
/// left and y0 forward, the ankle a16 above the ground (z = 0, z up) and the pelvis centred on y = 0 (the
/// body facing +x).
inline Pose<double> standing_base_pose(const SeedParameters& p) {
  Pose<double> X;
  X.R << 0, 1, 0,  //
      0, 0, 1,     //
      1, 0, 0;
  X.p = Eigen::Vector3d(0, -p.d4, p.a16);
  return X;
}

/// The joint names of the seed body, in the paper's order (body.hpp).
inline constexpr auto seed_joint_names = seed_body.joint_names();
/// The link names of the seed body, in the paper's order (the link each joint moves).
inline constexpr auto seed_link_names = seed_body.link_names();

namespace detail {

// Segment axes at the home pose (world frame): z from its proximal to its distal joint centre, x the
// body's `forward` (a unit vector) made square to it.
inline Eigen::Matrix3d segment_axes(const Eigen::Vector3d& proximal, const Eigen::Vector3d& distal,
                                    const Eigen::Vector3d& forward) {
  Eigen::Matrix3d A;
  const Eigen::Vector3d z = (distal - proximal).normalized();
  const Eigen::Vector3d x = (forward - z.dot(forward) * z).normalized();
  A.col(0) = x;
  A.col(1) = z.cross(x);
  A.col(2) = z;
  return A;
}

// A segment hung on a link whose frame is `frame` at the home pose, as the link's inertia.
inline RigidBodyInertia<double> place_segment(const Segment& seg, const Pose<double>& frame,
                                              const Eigen::Vector3d& proximal, const Eigen::Vector3d& distal,
                                              const Eigen::Vector3d& forward) {
  const Pose<double> segment{segment_axes(proximal, distal, forward), proximal};  // segment axes in the world
  return seg.expressed_in(frame.inverse() * segment);
}

// A segment from a de Leva row: scaled length L, mass, centre of mass along z, radii of gyration.
inline Segment de_leva_segment(const anthropometry::SegmentRow& r, double length, double body_mass) {
  Segment s;
  s.mass = r.mass_fraction * body_mass;
  s.com = Eigen::Vector3d(0, 0, r.com * length);
  s.inertia = (s.mass * Eigen::Vector3d(r.r_sag * length * r.r_sag * length, r.r_trans * length * r.r_trans * length,
                                        r.r_long * length * r.r_long * length))
                  .asDiagonal();  // principal axes along the segment axes
  return s;
}

// A segment's geometry rescaled to a new length along its axis (same mass, same fractions).
inline Segment rescale(Segment s, double factor) {
  s.com *= factor;
  s.inertia *= factor * factor;
  return s;
}

}  // namespace detail

/// A person of `height`, `mass` and sex, scaled from de Leva's reference subject of that sex;
/// the segments' masses sum to `mass`. Link 4 (the pelvis) carries the lower trunk, link 6 the upper and
/// middle trunk with the head, links 9 and 12 forearm and hand. A massless pelvis, as in Table 1, would
/// leave the hip pitches and the waist pitch (joints 4, 5, 13, one axis) a direction that moves no mass,
/// and the mass matrix singular.
/// In each foot the ankle stands a quarter of the foot's length ahead of the heel and the centre of
/// mass half-way down to the sole (anthropometry.hpp lists the lengths de Leva does not give).
/// \param height  stature (m)
/// \param mass    body mass (kg)
/// \param sex     whose reference subject and rows to scale
/// \return the lengths, segments and standing base pose (standing_base_pose) of that person
/// \throws ModelError unless height and mass are both positive and finite
inline SeedParameters de_leva_parameters(double height, double mass, anthropometry::Sex sex) {
  using namespace anthropometry;
  if (!std::isfinite(height) || height <= 0 || !std::isfinite(mass) || mass <= 0)
    throw ModelError("de Leva person: height " + exact_number(height) + " m and mass " + exact_number(mass) +
                     " kg must be positive and finite");
  const Reference ref = sex == Sex::Male ? reference_male : reference_female;
  const double k = height / ref.height;
  const auto L = [&](const SegmentRow& r) { return r.length * k; };
  const SegmentRow& shank = row("shank", "KJC-AJC", sex);
  const SegmentRow& thigh = row("thigh", "HJC-KJC", sex);
  const SegmentRow& trunk = row("trunk", "SUPR-MIDH", sex);
  const SegmentRow& upper_trunk = row("upper_trunk", "SUPR-XYPH", sex);
  const SegmentRow& mid_trunk = row("mid_trunk", "XYPH-OMPH", sex);
  const SegmentRow& lower_trunk = row("lower_trunk", "OMPH-MIDH", sex);
  const SegmentRow& trunk_c7 = row("trunk", "CERV-MIDH", sex);
  const SegmentRow& head = row("head_neck", "VERT-CERV", sex);
  const SegmentRow& upper_arm = row("upper_arm", "SJC-EJC", sex);
  const SegmentRow& forearm = row("forearm", "EJC-WJC", sex);
  const SegmentRow& hand = row("hand", "WJC-MET3", sex);
  const SegmentRow& foot = row("foot", "HEEL-TTIP", sex);

  SeedParameters p;
  p.name = std::string("de Leva ") + (sex == Sex::Male ? "male " : "female ") + exact_number(height) + " m " +
           exact_number(mass) + " kg";
  p.a1 = L(shank);
  p.a2 = L(thigh);
  p.d4 = hip_half_width * height;
  p.d6 = L(trunk);
  p.d7 = (sex == Sex::Male ? shoulder_half_width_male : shoulder_half_width_female) * height;
  p.a8 = L(upper_arm);
  p.a9 = L(forearm);
  p.a16 = ankle_height * height;

  // segment masses: de Leva's fractions of the body mass, normalised to sum to one
  const double basis = mass / whole_body_mass_fraction(sex);

  // shank and thigh: de Leva's centres of mass are measured from the proximal (upper) joint
  p.shank = detail::de_leva_segment(shank, L(shank), basis);
  p.thigh = detail::de_leva_segment(thigh, L(thigh), basis);
  p.upper_arm = detail::de_leva_segment(upper_arm, L(upper_arm), basis);

  // forearm and hand in line, the hand's centre of mass beyond the wrist
  Segment hand_seg = detail::de_leva_segment(hand, L(hand), basis);
  hand_seg.com.z() += L(forearm);
  p.forearm = detail::de_leva_segment(forearm, L(forearm), basis) + hand_seg;

  // the trunk from the mid-hip point up, in de Leva's three parts stacked along it (each centre of
  // mass measured down from the part's upper end): the lower trunk is the pelvis, the middle and upper
  // trunk join the head with neck (measured down from the vertex, which stands a C7-trunk and a
  // head-neck length above the mid-hip point) in the upper body
  const auto trunk_part = [&](const SegmentRow& r, double base_height) {
    Segment s = detail::de_leva_segment(r, L(r), basis);
    s.com.z() = base_height + (1 - r.com) * L(r);
    return s;
  };
  p.pelvis = trunk_part(lower_trunk, 0);
  const Segment mid = trunk_part(mid_trunk, L(lower_trunk));
  const Segment upper = trunk_part(upper_trunk, L(lower_trunk) + L(mid_trunk));
  Segment head_seg = detail::de_leva_segment(head, L(head), basis);
  head_seg.com.z() = L(trunk_c7) + (1 - head.com) * L(head);
  p.upper_body = mid + upper + head_seg;

  // the feet: ankle down to the sole (z down), x along the foot; the longitudinal radius is about x
  const auto foot_segment = [&] {
    Segment s;
    const SegmentRow& r = foot;
    const double Lf = L(foot);
    s.mass = r.mass_fraction * basis;
    s.com = Eigen::Vector3d((r.com - heel_to_ankle) * Lf, 0, 0.5 * p.a16);
    s.inertia =
        (s.mass * Eigen::Vector3d(std::pow(r.r_long * Lf, 2), std::pow(r.r_trans * Lf, 2), std::pow(r.r_sag * Lf, 2)))
            .asDiagonal();
    return s;
  };
  p.foot = foot_segment();
  p.stance_foot = foot_segment();

  p.base_pose = standing_base_pose(p);
  return p;
}

/// The embedded default model: de Leva's reference male, 1.741 m, 73.0 kg.
inline SeedParameters default_parameters() {
  auto p = de_leva_parameters(anthropometry::reference_male.height, anthropometry::reference_male.mass,
                              anthropometry::Sex::Male);
  p.name = "default (de Leva reference male, 1.741 m, 73.0 kg)";
  return p;
}

/// de Leva's reference female: 1.735 m, 61.9 kg.
inline SeedParameters female_parameters() {
  auto p = de_leva_parameters(anthropometry::reference_female.height, anthropometry::reference_female.mass,
                              anthropometry::Sex::Female);
  p.name = "female (de Leva reference female, 1.735 m, 61.9 kg)";
  return p;
}

/// The paper's model: Table 1 with a1 = a2 = 0.43, d4 = 0.09, d6 = 0.5, d7 = 0.19,
/// a8 = 0.28, a9 = 0.27 m (the paper prints no numbers); the segments are de Leva's reference male,
/// stretched to these lengths, the pelvis massless (the upper body carries the whole trunk and the head);
/// the right ankle at the world origin.
inline SeedParameters paper_parameters() {
  SeedParameters p = default_parameters();
  const SeedParameters ref = p;
  p.name = "paper (Table 1, a1 = a2 = 0.43 m, de Leva male segments)";
  p.a1 = 0.43;
  p.a2 = 0.43;
  p.d4 = 0.09;
  p.d6 = 0.5;
  p.d7 = 0.19;
  p.a8 = 0.28;
  p.a9 = 0.27;
  p.shank = detail::rescale(ref.shank, p.a1 / ref.a1);
  p.thigh = detail::rescale(ref.thigh, p.a2 / ref.a2);
  // Table 1's pelvis is massless: m6 holds the whole trunk and the head
  p.upper_body = detail::rescale(ref.pelvis + ref.upper_body, p.d6 / ref.d6);
  p.pelvis = Segment{};
  p.upper_arm = detail::rescale(ref.upper_arm, p.a8 / ref.a8);
  p.forearm = detail::rescale(ref.forearm, p.a9 / ref.a9);
  p.base_pose.p.setZero();
  return p;
}

namespace detail {

// The body's dimensions: which member of SeedParameters each is, and its name.
struct DimensionField {
  Dim dim;
  const char* name;
  double SeedParameters::*member;
};
inline constexpr std::array<DimensionField, 8> dimensions{{{Dim::a1, "a1", &SeedParameters::a1},
                                                           {Dim::a2, "a2", &SeedParameters::a2},
                                                           {Dim::d4, "d4", &SeedParameters::d4},
                                                           {Dim::d6, "d6", &SeedParameters::d6},
                                                           {Dim::d7, "d7", &SeedParameters::d7},
                                                           {Dim::a8, "a8", &SeedParameters::a8},
                                                           {Dim::a9, "a9", &SeedParameters::a9},
                                                           {Dim::a16, "a16", &SeedParameters::a16}}};
inline const DimensionField& dimension(Dim d) { return dimensions[std::size_t(d) - 1]; }  // (not Dim::None)

// The value of a table's length for the dimensions of `p` (m).
inline double length(const Length& l, const SeedParameters& p) {
  if (l.dim == Dim::None) return 0;
  const double v = p.*dimension(l.dim).member;
  return l.sign < 0 ? -v : v;
}

// A special angle of a table (radians).
inline double angle(Twist t) {
  constexpr double h = 1.57079632679489661923;  // 90 degrees
  switch (t) {
    case Twist::HalfPi:
      return h;
    case Twist::MinusHalfPi:
      return -h;
    case Twist::Pi:
      return 2 * h;
    default:
      return 0;
  }
}

// The segment of `p` that a table's part names.
inline const Segment& part(const SeedParameters& p, Part k) {
  static const Segment none{};
  switch (k) {
    case Part::Shank:
      return p.shank;
    case Part::Thigh:
      return p.thigh;
    case Part::Pelvis:
      return p.pelvis;
    case Part::UpperBody:
      return p.upper_body;
    case Part::UpperArm:
      return p.upper_arm;
    case Part::Forearm:
      return p.forearm;
    case Part::Hand:
      return p.hand;
    case Part::Foot:
      return p.foot;
    case Part::StanceFoot:
      return p.stance_foot;
    case Part::Massless:
      break;
  }
  return none;
}

}  // namespace detail

/// A body table's DH rows (a, alpha, d, theta) for the lengths of `p`, massless (the seed's: Table 1).
/// \param p  the lengths (m), name and base pose; its segments are not read
/// \return the description: names, parents and DH rows (m, rad), no mass
template <const auto& Body = seed_body>
ModelDescription<double> body_geometry(const SeedParameters& p) {
  ModelDescription<double> d;
  d.name = p.name;
  d.base_link_name = Body.base_link;
  d.base_pose = p.base_pose;
  for (int i = 0; i < Body.size; ++i) {
    const BodyJoint& row = Body.joints[std::size_t(i)];
    JointDescription<double> j;
    j.name = row.name;
    j.link_name = row.link;
    j.parent = Body.parent(i);
    j.dh = {detail::length(row.dh.a, p), detail::angle(row.dh.alpha), detail::length(row.dh.d, p),
            detail::angle(row.dh.theta)};
    d.joints.push_back(j);
  }
  return d;
}

/// The dimensions of a body of a table's shape, read back from its description (one human_description
/// or body_geometry made, or `humandyn model --json` wrote): `p` with a1 ... a16 taken from the DH rows
/// whose formula uses each (all of which must agree, to 1e-9 relative), with the description's name and
/// base pose; the segments stay p's. The inverse of body_geometry, for what needs the body's
/// kinematics alone (motion export places landmarks by them).
/// \throws ModelError naming the first joint whose name, parent, mount or DH row does not fit the table
template <const auto& Body = seed_body>
SeedParameters with_dimensions_of(const ModelDescription<double>& d, SeedParameters p) {
  if (int(d.joints.size()) != Body.size)
    throw ModelError(d.name + ": " + std::to_string(d.joints.size()) + " joints, where the body has " +
                     std::to_string(Body.size));
  std::array<int, detail::dimensions.size()> read_at{};  // the joint each dimension was read from (+1; 0: none yet)
  for (int i = 0; i < Body.size; ++i) {
    const BodyJoint& row = Body.joints[std::size_t(i)];
    const JointDescription<double>& j = d.joints[std::size_t(i)];
    const auto fail = [&](const std::string& why) {
      throw ModelError(d.name + ": joint " + std::to_string(i + 1) + " '" + j.name + "': " + why);
    };
    if (j.name != row.name) fail(std::string("the body's joint ") + std::to_string(i + 1) + " is '" + row.name + "'");
    if (j.parent != Body.parent(i)) fail("its parent is not the body's");
    if (j.mounted) fail("it is mounted, which the body's joints are not");
    if (!(std::abs(j.dh.alpha - detail::angle(row.dh.alpha)) <= 1e-9) ||
        !(std::abs(j.dh.theta - detail::angle(row.dh.theta)) <= 1e-9))
      fail("its DH twist or offset is not the body's");
    for (const auto& [formula, value, what] : {std::tuple{row.dh.a, j.dh.a, "a"}, std::tuple{row.dh.d, j.dh.d, "d"}}) {
      if (formula.dim == Dim::None) {
        if (!(std::abs(value) <= 1e-9)) fail(std::string("its DH ") + what + " is not 0 as the body's");
        continue;
      }
      const detail::DimensionField& f = detail::dimension(formula.dim);
      const double v = formula.sign < 0 ? -value : value;
      int& at = read_at[std::size_t(formula.dim) - 1];
      if (at == 0) {
        p.*f.member = v;
        at = i + 1;
      } else if (!(std::abs(v - p.*f.member) <= 1e-9 * std::abs(p.*f.member))) {
        fail(std::string("its DH ") + what + " gives " + f.name + " = " + exact_number(v) + " m, joint " +
             std::to_string(at) + " gave " + exact_number(p.*f.member) + " m");
      }
    }
  }
  p.name = d.name;
  p.base_pose = d.base_pose;
  return p;
}

/// A body table with the dimensions and segments of `p`: its geometry, with each part placed on its link
/// where the table's span says (a part of no mass leaves its link empty). The placement reads the body's
/// own up and forward from its base frame (x0 and y0 of p.base_pose), so a turned base pose turns the whole
/// body, inertias included.
/// \param p  the lengths (m), segments, name and base pose
/// \return the description (body_geometry with bodies)
/// \throws ModelError naming a length of `p` that is not positive and finite, or from validating the geometry
template <const auto& Body = seed_body>
ModelDescription<double> human_description(const SeedParameters& p) {
  for (const auto& f : detail::dimensions)
    if (const double v = p.*f.member; !std::isfinite(v) || v <= 0)
      throw ModelError(p.name + ": length " + f.name + " must be positive and finite");

  ModelDescription<double> d = body_geometry<Body>(p);
  // the home-pose frames, from the massless geometry (index -1: the base frame)
  const Model<double, BodyShape<Body>> geometry(d);
  Data<Model<double, BodyShape<Body>>> data(geometry);
  forward_kinematics(geometry, data, Eigen::Matrix<double, Body.size, 1>::Zero());
  const auto frame = [&](int l) -> const Pose<double>& { return l < 0 ? p.base_pose : data.oMi[std::size_t(l)]; };
  const auto o = [&](int l) -> Eigen::Vector3d { return frame(l).p; };
  // the body's up and forward at q = 0, whatever the base pose: x of the base frame (up the stance
  // shank) and y
  const Eigen::Vector3d up = p.base_pose.R.col(0), forward = p.base_pose.R.col(1);
  const auto place = [&](Part k, int l, Span span) {
    const Segment& s = detail::part(p, k);
    const int parent = l < 0 ? -1 : Body.parent(l);
    Eigen::Vector3d proximal = o(parent), distal = o(l);
    switch (span) {
      case Span::ParentToOwn:
        break;
      case Span::OwnToParent:
        std::swap(proximal, distal);
        break;
      case Span::ParentOnward:
        distal = 2 * o(parent) - o(Body.parent(parent));
        break;
      case Span::ParentDown:
        distal = o(parent) - up;
        break;
      case Span::OwnDown:
        proximal = o(l), distal = o(l) - up;
        break;
      case Span::OwnUp:
        proximal = o(l), distal = o(l) + up;
        break;
    }
    return detail::place_segment(s, frame(l), proximal, distal, forward);
  };
  for (int i = 0; i < Body.size; ++i) {
    const BodyJoint& row = Body.joints[std::size_t(i)];
    // (a negative or non-finite mass is placed too, for validation to name its link)
    if (row.part != Part::Massless && detail::part(p, row.part).mass != 0)
      d.joints[std::size_t(i)].body = place(row.part, i, row.span);
  }
  d.base_body = place(Body.base_part, -1, Span::OwnDown);
  return d;
}

/// The seed human, validated, in the scalar type S.
/// \throws ModelError as human_description does, or if the model fails validation
template <class S = double>
HumanModel<S> human_model(const SeedParameters& p) {
  return HumanModel<S>(human_description(p).template cast<S>());
}

/// The embedded default model (de Leva's reference male), in the scalar type S.
template <class S = double>
HumanModel<S> default_model() {
  return human_model<S>(default_parameters());
}

}  // namespace humandyn
