// The workspace of the algorithms: every buffer a per-call function writes, sized once from a model.
// One Data per character (or per thread); the Model it was made from stays const and shared.
#pragma once

#include "humandyn/model.hpp"

namespace humandyn {

// An external wrench on a link: force and moment about the link frame's origin, in the link frame,
// applied by the environment to the link (e.g. the weight of a load held in the hand).
template <class S>
struct Wrench {
  Vec3<S> force = Vec3<S>::Zero();
  Vec3<S> moment = Vec3<S>::Zero();
};

template <class Model>
struct Data {
  using S = typename Model::scalar_type;
  static constexpr int nj = Model::nj;
  template <class T> using Links = PerJoint<T, nj>;

  explicit Data(const Model& model) {
    if constexpr (nj == Eigen::Dynamic) {
      const auto n = std::size_t(model.size());
      for (auto* v : {&w, &wd, &vd, &f, &n_o, &com_world}) v->assign(n, Vec3<S>::Zero());
      oMi.assign(n, Pose<S>{});
      cos_q.assign(n, S(1));
      sin_q.assign(n, S(0));
      tau.setZero(model.size());
    } else {
      (void)model;
      tau.setZero();
    }
  }

  // inverse dynamics (rnea.hpp), each in the link's own frame
  Links<Vec3<S>> w{};    // angular velocity of link i
  Links<Vec3<S>> wd{};   // angular acceleration of link i
  Links<Vec3<S>> vd{};   // linear acceleration of link i's origin, gravity included as -g
  Links<Vec3<S>> f{};    // force link i receives from its parent
  Links<Vec3<S>> n_o{};  // moment link i receives from its parent, about link i's origin
  Links<S> cos_q{}, sin_q{};  // cos and sin of theta_i + q_i, from the forward pass for the backward one
  typename Model::JointVector tau;  // joint torques (N m)

  // forward kinematics (kinematics.hpp), in the world
  Links<Pose<S>> oMi{};       // pose of link i's frame
  Links<Vec3<S>> com_world{}; // centre of mass of link i
  Vec3<S> com = Vec3<S>::Zero();  // whole-body centre of mass (moving links and base body)
};

template <class Model>
using LinkWrenches = PerJoint<Wrench<typename Model::scalar_type>, Model::nj>;

}  // namespace humandyn
