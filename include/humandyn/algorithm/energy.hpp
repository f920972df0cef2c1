// Mechanical energy of the body. Kinetic energy from the link velocities (a velocity pass outwards, in
// link frames, as in the articulated-body algorithm), so that it checks 1/2 qd^T M qd independently;
// potential energy from the links' centres of mass in the world.
#pragma once

#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/data.hpp"
#include "humandyn/detail/dh.hpp"
#include "humandyn/detail/joint_loop.hpp"
#include "humandyn/detail/spatial.hpp"

#include <Eigen/Core>

namespace humandyn {

/// Kinetic energy of the moving links, the sum of 1/2 m |v_com|^2 + 1/2 w . I_com w (Featherstone 2008,
/// §2.15), from an outward velocity pass in link frames.
/// \param q   joint angles (rad), nj
/// \param qd  joint velocities (rad/s), nj
/// \return the kinetic energy (J); leaves the link spatial velocities in data.v
template <class Model, class Q, class QD>
inline typename Model::scalar_type kinetic_energy(const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q,
                                                  const Eigen::MatrixBase<QD>& qd) noexcept {
  using S = typename Model::scalar_type;
  eigen_assert(q.size() == model.size() && qd.size() == model.size());
  S energy = 0;
  detail::for_each_joint(model, [&](auto i, auto T, auto mounted, auto massless) {
    constexpr Twist twist = decltype(T)::value;
    const auto k = std::size_t(i);
    const auto& j = model.joint(int(i));
    // the parent's velocity carried over the joint, plus the joint's own
    SpatialVector<S> v = detail::motion_subspace<twist>(j) * S(qd[int(i)]);
    if (j.parent >= 0) {
      S c, s;
      detail::cos_sin(S(j.theta + S(q[int(i)])), c, s);
      v += detail::motion_to_child<twist>(j, mounted, c, s, data.v[std::size_t(j.parent)]);
    }
    data.v[k] = v;
    if (!massless) {
      const Vec3<S> w = v.template head<3>();
      const Vec3<S> v_com = v.template tail<3>() + w.cross(j.com);
      energy += S(0.5) * (j.mass * v_com.squaredNorm() + w.dot(j.inertia * w));
    }
  });
  return energy;
}

/// Potential energy of the moving links in gravity, -sum m g . com, zero with every centre of mass at
/// the world origin's height (the fixed base body adds only a constant and is left out).
/// \param q  joint angles (rad), nj
/// \return the potential energy (J); leaves forward kinematics in data
template <class Model, class Q>
inline typename Model::scalar_type potential_energy(const Model& model, Data<Model>& data,
                                                    const Eigen::MatrixBase<Q>& q) noexcept {
  using S = typename Model::scalar_type;
  forward_kinematics(model, data, q);
  S energy = 0;
  for (int i = 0; i < model.size(); ++i)
    energy -= model.joint(i).mass * model.gravity().dot(data.com_world[std::size_t(i)]);
  return energy;
}

/// Kinetic plus potential energy.
/// \param q   joint angles (rad), nj
/// \param qd  joint velocities (rad/s), nj
/// \return the total mechanical energy (J)
template <class Model, class Q, class QD>
inline typename Model::scalar_type total_energy(const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q,
                                                const Eigen::MatrixBase<QD>& qd) noexcept {
  return kinetic_energy(model, data, q, qd) + potential_energy(model, data, q);
}

}  // namespace humandyn
