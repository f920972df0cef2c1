// Gravity torques of the embedded default model, from an installed humandyn: the left arm held
// straight forward loads the shoulder with de Leva's 10.55 N m and the waist pitch with the same.
#include <humandyn/humandyn.hpp>

#include <cmath>
#include <cstdio>

int main() {
  const auto model = humandyn::default_model<double>();
  humandyn::Data<humandyn::HumanModel<double>> data(model);
  Eigen::Matrix<double, 16, 1> q = Eigen::Matrix<double, 16, 1>::Zero();
  q[6] = -1.5707963267948966;  // joint 7, left shoulder pitch: the arm forward
  const auto& tau = humandyn::gravity_torques(model, data, q);
  std::printf("shoulder %.4f N m, waist %.4f N m, total mass %.3f kg\n", tau[6], tau[4], model.total_mass());

  const bool ok = std::abs(std::abs(tau[6]) - 10.55) <= 0.01 * 10.55 && std::abs(tau[4] - tau[6]) <= 1e-9 &&
                  std::abs(model.total_mass() - 73.0) <= 1e-9;
  // the float model builds and agrees
  const auto model_f = humandyn::default_model<float>();
  humandyn::Data<humandyn::HumanModel<float>> data_f(model_f);
  const float shoulder_f = humandyn::gravity_torques(model_f, data_f, q.cast<float>())[6];
  const bool ok_f = std::abs(shoulder_f - float(tau[6])) <= 1e-4f;
  if (!ok || !ok_f) {
    std::printf("unexpected torques (float shoulder %.5f)\n", double(shoulder_f));
    return 1;
  }
  return 0;
}
