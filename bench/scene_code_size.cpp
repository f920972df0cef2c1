// The machine code each named scene's inverse dynamics compiles to: one out-of-line function per scene,
// whose size the symbol table gives (docs/scenes.md):
//   g++ -std=c++20 -O3 -DNDEBUG -Iinclude -I/usr/include/eigen3 -c bench/scene_code_size.cpp -o scene_code_size.o
//   nm -C -S --size-sort scene_code_size.o | grep scene_code_size
#include "humandyn/scene.hpp"

namespace humandyn::scene_code_size {

template <class SceneT>
using Vector = typename SceneT::template vector<double>;

#define HUMANDYN_SCENE_FUNCTION(Name, SceneT)                                                                   \
  __attribute__((noinline)) const SceneT::model_type<double>::JointVector& Name(                                \
      const SceneT::model_type<double>& model, Data<SceneT::model_type<double>>& data, const Vector<SceneT>& q, \
      const Vector<SceneT>& qd, const Vector<SceneT>& qdd) noexcept {                                           \
    return scene_rnea<SceneT>(model, data, q, qd, qdd);                                                         \
  }

HUMANDYN_SCENE_FUNCTION(full, scenes::Full)
HUMANDYN_SCENE_FUNCTION(no_coriolis, scenes::NoCoriolis)
HUMANDYN_SCENE_FUNCTION(static_pose, scenes::StaticPose)
HUMANDYN_SCENE_FUNCTION(upper_body, scenes::UpperBody)
HUMANDYN_SCENE_FUNCTION(arms_only, scenes::ArmsOnly)
HUMANDYN_SCENE_FUNCTION(arm_torques, scenes::ArmTorques)

}  // namespace humandyn::scene_code_size
