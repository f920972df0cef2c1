// External wrenches on the command line: `--wrench LINK:FX,FY,FZ[@PX,PY,PZ]`, repeatable, on `id`, `fd`
// and `simulate`. The force (N) is given in the world frame and keeps its world direction (a weight
// stays vertical). It acts at the point P (m, world coordinates in the first state: the first row of
// --in, or the starting pose of `simulate`), which is fixed on the link from then on; without @P, at
// the link frame's origin. Each becomes rnea's and forward_dynamics' fext: the wrench in the link's
// frame about its origin.
#pragma once

#include "humandyn/data.hpp"
#include "humandyn/model.hpp"

#include <CLI/CLI.hpp>

#include <optional>
#include <string>
#include <vector>

namespace humandyn::cli {

class ExternalWrenches {
 public:
  using M = AnyModel<double>;

  // Parses every spec; UsageError naming the bad part, or listing the link names for an unknown link.
  ExternalWrenches(const std::vector<std::string>& specs, const M& model);

  bool empty() const { return specs_.empty(); }
  // Whether any wrench has a force other than 0 (a zero force does no work).
  bool any_force() const {
    for (const Spec& w : specs_)
      if (w.force != Vec3<double>::Zero()) return true;
    return false;
  }

  // Fixes each point on its link at the first state's angles q.
  void attach(const M& model, Data<M>& data, const Eigen::VectorXd& q);

  // rnea's fext at the angles q (each link's wrenches summed, in its frame about its origin).
  const LinkWrenches<M>& at(const M& model, Data<M>& data, const Eigen::VectorXd& q);

  // The joint torques J^T w the wrenches apply at the angles q (what `simulate` adds to the joint torques).
  const Eigen::VectorXd& joint_torques(const M& model, Data<M>& data, const Eigen::VectorXd& q);

 private:
  struct Spec {
    int link = 0;
    Vec3<double> force;
    std::optional<Vec3<double>> point_world;  // as given, before attach()
    Vec3<double> point_link = Vec3<double>::Zero();
  };
  std::vector<Spec> specs_;
  LinkWrenches<M> fext_;
  Eigen::VectorXd tau_;
};

// Registers the repeatable --wrench on `command`; `effect` ends its help (what the wrenches change there).
CLI::Option* add_wrench_option(CLI::App& command, std::vector<std::string>& specs, const std::string& effect);

}  // namespace humandyn::cli
