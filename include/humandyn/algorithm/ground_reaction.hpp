// The ground's share. After inverse dynamics, the wrench that the base link (the stance foot) must
// receive from outside: what the backward pass delivers to the base through the root joints, plus
// the base link's own inertial and gravity wrench. For a foot on flat ground it gives the centre of
// pressure and the friction the motion needs, and flags each state that one foot on the ground cannot
// produce: a foot that would have to pull, a centre of pressure outside the sole, friction beyond mu.
// Winter, "Biomechanics and Motor Control of Human Movement" (4th ed., 2009), ch. 5 (ground reaction
// and centre of pressure); Featherstone, "Rigid Body Dynamics Algorithms" (2008), sec. 5.3 (the
// base's wrench as the end of the inward pass).
#pragma once

#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/anthropometry.hpp"
#include "humandyn/detail/joint_loop.hpp"

#include <cstdint>

namespace humandyn {

/// The wrench applied to the base link from outside (by the ground, under a stance foot), in world axes.
template <class S>
struct GroundReaction {
  Vec3<S> force = Vec3<S>::Zero();   ///< force on the base link (N)
  Vec3<S> moment = Vec3<S>::Zero();  ///< moment about the base frame's origin (N m)
  Vec3<S> origin = Vec3<S>::Zero();  ///< the base frame's origin in the world (m)

  /// The same wrench's moment about `point` (world, m): M_P = M_O + (O - P) x F.
  Vec3<S> moment_about(const Vec3<S>& point) const noexcept { return moment + (origin - point).cross(force); }
};

/// Ground reaction after inverse dynamics: call it with the `data` of the rnea call (same `terms`, same
/// base motion) that computed the torques, no other algorithm run on that `data` since (each overwrites
/// the joints' cosines and sines, data.cos_q and data.sin_q, which this reads). Whole models only (a
/// scene that prunes outputs leaves the root links' wrenches unfinished). External wrenches given to rnea
/// are accounted for: the reaction is what the ground must add to them.
/// \param base the base's motion given to rnea (BaseMotion::at_rest(model) for the fixed-base rnea).
/// \return the reaction on the base link, world axes (N, N m about the base origin).
template <Terms terms = Terms::Full, class Model>
inline GroundReaction<typename Model::scalar_type> ground_reaction(
    const Model& model, const Data<Model>& data, const BaseMotion<typename Model::scalar_type>& base) noexcept {
  using S = typename Model::scalar_type;
  const auto b = detail::base_acceleration<terms>(model, base);

  // the base link's own Newton and Euler equations, in the base frame about its origin
  const auto& body = model.description().base_body;
  Vec3<S> w = Vec3<S>::Zero(), wd = Vec3<S>::Zero();
  if constexpr (terms != Terms::GravityOnly) wd = b.wd;
  if constexpr (terms == Terms::Full) w = b.w;
  const Vec3<S> ac = b.vd + wd.cross(body.com) + w.cross(w.cross(body.com));
  Vec3<S> f = body.mass * ac;
  Vec3<S> n = body.com.cross(f) + body.inertia * wd + w.cross(body.inertia * w);

  // plus what the root links receive from the base (their wrenches as rnea's backward pass leaves them)
  detail::for_each_joint(model, [&](auto i, auto T, auto mounted, auto) {
    if (model.joint(int(i)).parent >= 0) return;
    Vec3<S> fi, ni;
    detail::wrench_through_joint<decltype(T)::value>(model, data, int(i), fi, ni);
    detail::through_mount(model.joint(int(i)), mounted, fi, ni);
    f += fi;
    n += ni;
  });

  GroundReaction<S> r;
  r.force = base.pose.R * f;
  r.moment = base.pose.R * n;
  r.origin = base.pose.p;
  return r;
}

/// Fixed-base overload: the base at rest in the model's base pose.
template <Terms terms = Terms::Full, class Model>
inline GroundReaction<typename Model::scalar_type> ground_reaction(const Model& model,
                                                                   const Data<Model>& data) noexcept {
  return ground_reaction<terms>(model, data, BaseMotion<typename Model::scalar_type>::at_rest(model));
}

/// The sole of the stance foot, a rectangle fixed to the base frame (the ankle), given at the home pose
/// in world directions: x forward, y left, z up.
struct SoleDimensions {
  double length = 0;         ///< heel to toe tip (m)
  double width = 0;          ///< side to side (m)
  double heel_to_ankle = 0;  ///< how far the ankle stands ahead of the heel (m)
  double ankle_height = 0;   ///< the ankle's height above the sole (m)
};

/// A person's sole, scaled from de Leva (1996): the foot's length (HEEL-TTIP) scaled by stature; its
/// width and the ankle's height are Drillis and Contini's fractions of stature (0.055 and 0.039), the
/// ankle a quarter of the foot's length ahead of the heel, as the builders place it.
/// \param height stature (m), positive and finite; \param sex de Leva's reference subject to scale.
/// \throws ModelError for a height that is not positive and finite
inline SoleDimensions de_leva_sole(double height, anthropometry::Sex sex) {
  using namespace anthropometry;
  if (!(std::isfinite(height) && height > 0))
    throw ModelError("de Leva sole: height " + exact_number(height) + " m must be positive and finite");
  const Reference ref = sex == Sex::Male ? reference_male : reference_female;
  SoleDimensions s;
  s.length = row("foot", "HEEL-TTIP", sex).length * height / ref.height;
  s.width = foot_width * height;
  s.heel_to_ankle = heel_to_ankle * s.length;
  s.ankle_height = anthropometry::ankle_height * height;
  return s;
}

/// The sole's four corners in the base frame (m, 3 x 4: heel right, heel left, toe left, toe right).
/// The home pose's base rotation turns the world directions of SoleDimensions into the base frame.
template <class Model>
inline Eigen::Matrix<typename Model::scalar_type, 3, 4> sole_corners(const Model& model, const SoleDimensions& sole) {
  using S = typename Model::scalar_type;
  const double back = -sole.heel_to_ankle, front = sole.length - sole.heel_to_ankle, half = 0.5 * sole.width;
  const double x[4] = {back, back, front, front}, y[4] = {-half, half, half, -half};
  Eigen::Matrix<S, 3, 4> corners;
  for (int k = 0; k < 4; ++k)
    corners.col(k) = model.base_pose().R.transpose() * Vec3<S>(S(x[k]), S(y[k]), S(-sole.ankle_height));
  return corners;
}

/// What a state asks of one foot on flat ground (the plane z = ground_height, world).
enum ContactFlag : std::uint8_t {
  ContactOk = 0,       ///< no flag: the foot pushes (or carries nothing), centre of pressure inside, friction <= mu
  FootPulls = 1,       ///< normal force <= 0 under a load: the foot would have to pull on the ground
  CopOutsideSole = 2,  ///< the centre of pressure lies outside the sole's outline on the ground
  FootSlips = 4,       ///< tangential force beyond mu times the normal force (by more than 64 roundings)
};

/// What a ground reaction asks of one foot on flat ground (foot_contact's result), world axes.
template <class S>
struct FootContact {
  S normal = 0;                    ///< normal (vertical) force (N); positive pushes the foot up
  Vec3<S> cop = Vec3<S>::Zero();   ///< centre of pressure on the ground plane (world, m); NaN where normal <= 0
  S friction_ratio = 0;            ///< |tangential force| / normal force; where normal <= 0: +inf, 0 with no
                                   ///< tangential force
  S free_moment = 0;               ///< moment about the vertical through the centre of pressure (N m)
  std::uint8_t flags = ContactOk;  ///< ContactFlag bits
};

/// The centre of pressure of `reaction` on the ground plane and the flags of one foot standing there.
/// The sole's outline is its four corners (base frame, sole_corners) carried by `base_pose` and
/// projected down onto the ground: for a foot flat on the ground, its footprint; for a rolled foot, a
/// lenient outline (the part touching the ground lies inside it). A foot that carries nothing (no force, no
/// moment: a body in free fall, or in flight) has no flag.
/// \param corners the sole's four corners in the base frame (m, 3 x 4, in order around the sole; sole_corners)
/// \param mu friction coefficient (0.8 by default, dry shoe on a floor).
/// \param ground_height the ground plane's height z (m, world; 0 by default)
template <class S>
inline FootContact<S> foot_contact(const GroundReaction<S>& reaction, const Pose<S>& base_pose,
                                   const Eigen::Matrix<S, 3, 4>& corners, S mu = S(0.8),
                                   S ground_height = S(0)) noexcept {
  FootContact<S> c;
  const Vec3<S>& F = reaction.force;
  c.normal = F.z();
  // moment about a point on the ground plane under the base origin; the centre of pressure is where
  // the horizontal moment vanishes: M = (p - O') x F + free moment about z
  const Vec3<S> O(reaction.origin.x(), reaction.origin.y(), ground_height);
  const Vec3<S> M = reaction.moment_about(O);
  const S tangential = std::hypot(F.x(), F.y());
  if (c.normal > 0) {
    const S dx = -M.y() / c.normal, dy = M.x() / c.normal;
    c.cop = Vec3<S>(O.x() + dx, O.y() + dy, ground_height);
    c.free_moment = M.z() - (dx * F.y() - dy * F.x());
    c.friction_ratio = tangential / c.normal;
  } else {
    c.cop.setConstant(std::numeric_limits<S>::quiet_NaN());
    c.friction_ratio = tangential > 0 ? std::numeric_limits<S>::infinity() : S(0);
    if (!(F.isZero(0) && reaction.moment.isZero(0))) c.flags |= FootPulls;  // (no load: nothing to pull)
  }
  // beyond mu by more than rounding: a body standing still leans on a tangential force of round-off (1e-16 of
  // its weight), which a frictionless floor (mu = 0) would otherwise flag
  if (c.friction_ratio > mu + S(64) * std::numeric_limits<S>::epsilon()) c.flags |= FootSlips;
  if (c.normal > 0) {
    // inside the convex outline: the same side of every edge (corners in order around the sole)
    bool inside = true;
    S sign = 0;
    Eigen::Matrix<S, 2, 1> low = Eigen::Matrix<S, 2, 1>::Constant(std::numeric_limits<S>::infinity()), high = -low;
    for (int k = 0; k < 4; ++k) {
      const Vec3<S> a = base_pose.R * corners.col(k) + base_pose.p;
      const Vec3<S> b = base_pose.R * corners.col((k + 1) % 4) + base_pose.p;
      low = low.cwiseMin(a.template head<2>());
      high = high.cwiseMax(a.template head<2>());
      const S cross = (b.x() - a.x()) * (c.cop.y() - a.y()) - (b.y() - a.y()) * (c.cop.x() - a.x());
      if (cross == 0) continue;
      if (sign == 0) sign = cross;
      if ((cross > 0) != (sign > 0)) inside = false;
    }
    // on the line of every edge: an outline seen edge-on (no area), inside only between its ends
    if (sign == 0)
      inside = c.cop.x() >= low.x() && c.cop.x() <= high.x() && c.cop.y() >= low.y() && c.cop.y() <= high.y();
    if (!inside) c.flags |= CopOutsideSole;
  }
  return c;
}

}  // namespace humandyn
