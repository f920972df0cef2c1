// The default human through the installed URDF component: exported, imported back, same torques.
#include <humandyn/algorithm/rnea.hpp>
#include <humandyn/builders.hpp>
#include <humandyn/urdf.hpp>

#include <cstdio>

int main() {
  const auto description = humandyn::human_description(humandyn::default_parameters());
  humandyn::urdf::ImportOptions options;
  options.gravity = description.base_pose.R.transpose() * description.gravity;
  const auto imported = humandyn::urdf::import_urdf(humandyn::urdf::to_urdf(description), options, "default.urdf");
  const auto human = humandyn::urdf::try_human_model(imported.model);
  if (!human) return 1;
  const auto original = humandyn::HumanModel<double>(description);
  humandyn::Data<humandyn::HumanModel<double>> a(original), b(*human);
  Eigen::Matrix<double, 16, 1> q = Eigen::Matrix<double, 16, 1>::LinSpaced(-0.8, 0.8);
  humandyn::gravity_torques(original, a, q);
  humandyn::gravity_torques(*human, b, q);
  const double diff = (a.tau - b.tau).cwiseAbs().maxCoeff();
  std::printf("humandyn::urdf round trip: %zu joints, static torques %.1e N m apart\n", imported.model.joints.size(),
              diff);
  return diff < 1e-9 ? 0 : 1;
}
