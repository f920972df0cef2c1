// Every named scene (humandyn/scene.hpp) as an inverse-dynamics variant of the error-against-run-time
// table (variants.hpp), on the same states as the full model:
//   - time: scene_rnea on the scene's joints, its locked joints held at the first state's angles (the
//     time of a call does not depend on the angles);
//   - error: each state evaluated in a scene whose locked joints are held at that state's own angles, so
//     the figure is what the scene drops (the locked joints' rates and accelerations, the omitted terms),
//     not a different pose. Joints a scene does not output (locked, or pruned) are filled with the full
//     model's double-precision torques, so the error is that of the scene's outputs.
// Empty for a model that is not of the seed's shape.
#pragma once

#include "bench/timing.hpp"
#include "bench/variants.hpp"
#include "humandyn/scene.hpp"

#include <memory>
#include <string>
#include <vector>

namespace humandyn::bench {

inline std::vector<Variant> scene_variants(const ModelDescription<double>& d) {
  std::vector<Variant> out;
  std::shared_ptr<const HumanModel<double>> full;
  try {
    full = std::make_shared<const HumanModel<double>>(d);
  } catch (const ModelError&) {
    return out;  // scenes are reductions of the seed's shape
  }
  for_each_named_scene([&](auto scene) {
    using SceneT = decltype(scene);
    using SceneModel = typename SceneT::template model_type<double>;
    using V = typename SceneT::template vector<double>;
    Variant v;
    v.name = "ID scene " + std::string(SceneT::name) + " double";
    v.problem = Problem::InverseDynamics;
    v.scalar = "double";
    v.engine = "humandyn";
    v.evaluate = [d, full](const Eigen::VectorXd& q, const Eigen::VectorXd& qd, const Eigen::VectorXd& qdd,
                           Eigen::VectorXd& result) {
      const SceneModel model = SceneT::template model<double>(d, q);
      Data<SceneModel> data(model);
      Data<HumanModel<double>> full_data(*full);
      const Eigen::VectorXd tau =
          SceneT::expand(scene_rnea<SceneT>(model, data, SceneT::reduce(q), SceneT::reduce(qd), SceneT::reduce(qdd)));
      result = rnea(*full, full_data, q, qd, qdd);
      for (int i = 0; i < int(result.size()); ++i)
        if (SceneT::outputs(i)) result[i] = tau[i];
    };
    v.time = [d](const Workload& w, double seconds) {
      const SceneModel model =
          SceneT::template model<double>(d, w.q.empty() ? Eigen::VectorXd::Zero(SceneT::full_nj) : w.q[0]);
      Data<SceneModel> data(model);
      std::vector<V> q, qd, qdd;
      for (int s = 0; s < w.size(); ++s) {
        q.push_back(SceneT::reduce(w.q[std::size_t(s)]));
        qd.push_back(SceneT::reduce(w.qd[std::size_t(s)]));
        qdd.push_back(SceneT::reduce(w.x[std::size_t(s)]));
      }
      return ns_per_call(w.size(), seconds, [&](int i) {
        const auto& r = scene_rnea<SceneT>(model, data, q[std::size_t(i)], qd[std::size_t(i)], qdd[std::size_t(i)]);
        do_not_optimize(r);
      });
    };
    out.push_back(std::move(v));
  });
  return out;
}

}  // namespace humandyn::bench
