// Mechanical energy of the body. mechanical_energy takes both kinds in one outward pass in link frames:
// the link velocities (as in the articulated-body algorithm), so that the kinetic energy checks
// 1/2 qd^T M qd independently, and gravity carried with them for the centres of mass's heights.
// potential_energy takes the heights from forward kinematics instead: its independent check.
#pragma once

#include "humandyn/algorithm/kinematics.hpp"
#include "humandyn/data.hpp"
#include "humandyn/detail/dh.hpp"
#include "humandyn/detail/joint_loop.hpp"
#include "humandyn/detail/spatial.hpp"

#include <Eigen/Core>

namespace humandyn {

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

namespace detail {

// mechanical_energy's pass (below) at the angles whose cosines and sines data.cos_q and data.sin_q
// already hold, left there by an algorithm just run at them (the backward-Euler step's crba and rnea):
// no sweep of its own.
template <class Model, class QD>
inline void mechanical_energy_pass(const Model& model, Data<Model>& data, const Eigen::MatrixBase<QD>& qd,
                                   typename Model::scalar_type& kinetic,
                                   typename Model::scalar_type& potential) noexcept {
  using S = typename Model::scalar_type;
  eigen_assert(qd.size() == model.size());
  const auto& base = model.base_pose();
  const Vec3<S> g_base = base.R.transpose() * model.gravity();
  const S g_base_origin = model.gravity().dot(base.p);
  kinetic = 0;
  potential = 0;
  for_each_joint(model, [&](auto i, auto T, auto mounted, auto massless) {
    constexpr Twist twist = decltype(T)::value;
    const auto k = std::size_t(i);
    const auto& j = model.joint(int(i));
    const S c = data.cos_q[k], s = data.sin_q[k];
    // the parent's velocity and gravity carried over the joint (through the mount, then E_i^T), plus
    // the joint's own velocity; the origin's height moves by the mount's and the DH offset p*_i
    SpatialVector<S> v = motion_subspace<twist>(j) * S(qd[int(i)]);
    Vec3<S> g = g_base;
    S g_origin = g_base_origin;
    if (j.parent >= 0) {
      const auto pk = std::size_t(j.parent);
      v += motion_to_child<twist>(j, mounted, c, s, data.v[pk]);
      g = data.g_link[pk];
      g_origin = data.g_origin[pk];
    }
    if (mounted) {
      g_origin += g.dot(j.mount_p);
      g = j.mount_R.transpose() * g;
    }
    g = rot_x_t<twist>(rot_z_t(g, c, s), j.ca, j.sa);
    g_origin += g.dot(j.pstar);
    data.v[k] = v;
    data.g_link[k] = g;
    data.g_origin[k] = g_origin;
    if (!massless) {
      const Vec3<S> w = v.template head<3>();
      const Vec3<S> v_com = v.template tail<3>() + w.cross(j.com);
      kinetic += S(0.5) * (j.mass * v_com.squaredNorm() + w.dot(j.inertia * w));
      potential -= j.mass * (g_origin + g.dot(j.com));
    }
  });
}

}  // namespace detail

/// Kinetic and potential energy in one outward pass in link frames: the link velocities, and gravity
/// carried with them, so that a link's centre of mass has the height
/// g . com = g . o_i + (R_i^T g) . c_i without forward kinematics (o_i, R_i: link i's origin and
/// orientation in the world, c_i its centre of mass in its frame). The kinetic energy is the sum of
/// 1/2 m |v_com|^2 + 1/2 w . I_com w (Featherstone 2008, §2.15); the potential agrees with
/// potential_energy's to rounding, at about half the cost of its forward kinematics.
/// \param q          joint angles (rad), nj
/// \param qd         joint velocities (rad/s), nj
/// \param kinetic    receives the kinetic energy (J)
/// \param potential  receives the potential energy (J), zero at the world origin's height as for potential_energy
/// leaves data.v (link velocities), data.g_link (gravity in link frames, m/s^2), data.g_origin (g . o_i, m^2/s^2)
/// and the joints' data.cos_q, data.sin_q
template <class Model, class Q, class QD>
inline void mechanical_energy(const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q,
                              const Eigen::MatrixBase<QD>& qd, typename Model::scalar_type& kinetic,
                              typename Model::scalar_type& potential) noexcept {
  eigen_assert(q.size() == model.size());
  detail::joint_cos_sin(model, q, data.cos_q, data.sin_q);
  detail::mechanical_energy_pass(model, data, qd, kinetic, potential);
}

/// Kinetic energy of the moving links, the sum of 1/2 m |v_com|^2 + 1/2 w . I_com w (Featherstone 2008,
/// §2.15), from an outward velocity pass in link frames (mechanical_energy's).
/// \param q   joint angles (rad), nj
/// \param qd  joint velocities (rad/s), nj
/// \return the kinetic energy (J); leaves the link spatial velocities in data.v
template <class Model, class Q, class QD>
inline typename Model::scalar_type kinetic_energy(const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q,
                                                  const Eigen::MatrixBase<QD>& qd) noexcept {
  typename Model::scalar_type kinetic, potential;
  mechanical_energy(model, data, q, qd, kinetic, potential);
  return kinetic;
}

/// Kinetic plus potential energy, by mechanical_energy's one pass.
/// \param q   joint angles (rad), nj
/// \param qd  joint velocities (rad/s), nj
/// \return the total mechanical energy (J)
template <class Model, class Q, class QD>
inline typename Model::scalar_type total_energy(const Model& model, Data<Model>& data, const Eigen::MatrixBase<Q>& q,
                                                const Eigen::MatrixBase<QD>& qd) noexcept {
  typename Model::scalar_type kinetic, potential;
  mechanical_energy(model, data, q, qd, kinetic, potential);
  return kinetic + potential;
}

}  // namespace humandyn
