// One named scene's inverse dynamics, alone in a translation unit, so that the object file's machine
// code is exactly what that scene compiles to (with every helper it pulls in). Built once per scene by
// bench/scene_code_size.py, which sums the .text sections and compares each scene with `full`:
//   python3 bench/scene_code_size.py            (the table in docs/scenes.md)
#include "humandyn/scene.hpp"

#ifndef HUMANDYN_SCENE
#error "define HUMANDYN_SCENE as a scene of humandyn::scenes, e.g. -DHUMANDYN_SCENE=UpperBody"
#endif

namespace humandyn::scene_code_size {

using SceneT = scenes::HUMANDYN_SCENE;
using SceneModel = SceneT::model_type<double>;
using Vector = SceneT::vector<double>;

const SceneModel::JointVector& inverse_dynamics(const SceneModel& model, Data<SceneModel>& data, const Vector& q,
                                                const Vector& qd, const Vector& qdd) noexcept {
  return scene_rnea<SceneT>(model, data, q, qd, qdd);
}

}  // namespace humandyn::scene_code_size
