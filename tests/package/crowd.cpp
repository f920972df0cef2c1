// The crowd component from an installed humandyn: a crowd stepped by the widest kernel the CPU runs,
// each character as the scalar step gives it.
#include <humandyn/crowd_kernels.hpp>
#include <humandyn/humandyn.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <vector>

int main() {
  using namespace humandyn;
  const auto model = default_model<double>();
  const CrowdKernel<double> kernel(model);
  auto ws = kernel.workspace();
  const std::size_t characters = 5, nj = 16;
  std::vector<double> q(characters * nj), qd(characters * nj, 0.0), tau(characters * nj, 0.0);
  for (std::size_t k = 0; k < q.size(); ++k) q[k] = 0.01 * double(k % 7);  // a lean each
  std::vector<StepStatus> status(characters);
  const std::vector<double> q0 = q;
  const CrowdView<double> crowd{characters, q.data(), qd.data(), tau.data(), nullptr, status.data()};
  kernel.step(Integrator::RungeKutta4, ws, crowd, 0, characters, 1e-3);

  StepWorkspace<HumanModel<double>> sws(model);
  State<HumanModel<double>> x(model);
  double worst = 0;
  for (std::size_t c = 0; c < characters; ++c) {
    for (std::size_t i = 0; i < nj; ++i) x.q[int(i)] = q0[c * nj + i], x.qd[int(i)] = 0;
    if (!status[c].ok() ||
        !step<Integrator::RungeKutta4>(model, sws, x, HumanModel<double>::JointVector::Zero(), 1e-3).ok())
      return 1;
    for (std::size_t i = 0; i < nj; ++i) worst = std::max(worst, std::abs(x.q[int(i)] - q[c * nj + i]));
  }
  std::printf("crowd of %zu stepped with %s lanes (%d wide): %.1e rad from the scalar step\n", characters,
              isa_name(kernel.isa()), kernel.width(), worst);
  return worst <= 1e-12 ? 0 : 1;
}
