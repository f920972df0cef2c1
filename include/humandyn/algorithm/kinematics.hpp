// Forward kinematics: every link frame, every link's centre of mass and the whole body's, in the world.
#pragma once

#include "humandyn/data.hpp"
#include "humandyn/detail/inline.hpp"
#include "humandyn/detail/joint_loop.hpp"

#include <Eigen/Core>

namespace humandyn {

/// The rotation and translation of one standard DH link, Rz(theta) Tz(d) Tx(a) Rx(alpha) (Craig 2005,
/// Denavit and Hartenberg 1955).
/// \param j  the joint's constants (a, d in m; cos and sin of alpha)
/// \param c  cos(theta + q)
/// \param s  sin(theta + q)
/// \return the link frame in its DH base frame (x_base = R x_link + p; p in m)
template <class S>
inline Pose<S> dh_pose(const JointConstants<S>& j, S c, S s) noexcept {
  Pose<S> T;
  T.R << c, -s * j.ca, s * j.sa,  //
      s, c * j.ca, -c * j.sa,     //
      S(0), j.sa, j.ca;
  T.p = Vec3<S>(j.a * c, j.a * s, j.d);
  return T;
}

/// Forward kinematics: every link frame, every link's centre of mass and the whole body's, in the world.
/// \param q  joint angles (rad), nj
/// \post data.oMi[i]: pose of link i's frame in the world (m); data.com_world[i]: link i's centre of
///       mass in the world (m); data.com: the whole body's (moving links and base body, m); data.cos_q,
///       data.sin_q: the joints' cosines and sines. No allocation.
template <class Model, class Q>
HUMANDYN_FLATTEN void forward_kinematics(const Model& model, Data<Model>& data,
                                         const Eigen::MatrixBase<Q>& q) noexcept {
  using S = typename Model::scalar_type;
  eigen_assert(q.size() == model.size());
  const auto& base = model.base_pose();
  const auto& base_body = model.description().base_body;
  Vec3<S> mc = base_body.mass * (base * base_body.com);
  S mass = base_body.mass;

  detail::joint_cos_sin(model, q, data.cos_q, data.sin_q);
  detail::for_each_joint(model, [&](auto i, auto, auto mounted, auto) {
    const auto& j = model.joint(int(i));
    // parent frame, then the fixed mount, then the DH link
    Pose<S> P = j.parent < 0 ? base : data.oMi[std::size_t(j.parent)];
    if (mounted) P = P * Pose<S>{j.mount_R, j.mount_p};
    const Pose<S> oMi = P * dh_pose(j, data.cos_q[std::size_t(i)], data.sin_q[std::size_t(i)]);
    data.oMi[std::size_t(i)] = oMi;
    data.com_world[std::size_t(i)] = oMi * j.com;
    mc += j.mass * data.com_world[std::size_t(i)];
    mass += j.mass;
  });
  // (the base's origin for a massless body; lane by lane for a batch)
  for (int k = 0; k < 3; ++k) data.com[k] = detail::lanes<S>::select(mass > 0, S(mc[k] / mass), base.p[k]);
}

}  // namespace humandyn
