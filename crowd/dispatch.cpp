// The choice among the crowd kernels compiled for each instruction set (kernel.cpp): what the build
// holds (HUMANDYN_CROWD_HAS_*) and what the CPU and the OS run (__builtin_cpu_supports, which checks
// the OS saves the wider registers too).
#include "humandyn/crowd_kernels.hpp"

#include "kernel_table.hpp"

#include <stdexcept>

HUMANDYN_COMPONENT_ABI_DEFINE(crowd)  // this build's Eigen alignment (humandyn/detail/component_abi.hpp)

namespace humandyn {

namespace {

const crowd_kernels::Kernels* kernels(Isa isa) noexcept {
  switch (isa) {
    case Isa::Sse2:
      return &crowd_kernels::kernels_sse2();
#ifdef HUMANDYN_CROWD_HAS_AVX2
    case Isa::Avx2:
      return &crowd_kernels::kernels_avx2();
#endif
#ifdef HUMANDYN_CROWD_HAS_AVX512
    case Isa::Avx512:
      return &crowd_kernels::kernels_avx512();
#endif
    default:
      return nullptr;
  }
}

template <class T>
const crowd_kernels::Table<T>& table(Isa isa) {
  if (!isa_available(isa))
    throw std::invalid_argument(std::string("crowd kernels: ") + isa_name(isa) + " not available");
  if constexpr (std::is_same_v<T, double>)
    return kernels(isa)->d;
  else
    return kernels(isa)->f;
}

}  // namespace

const char* isa_name(Isa isa) noexcept {
  switch (isa) {
    case Isa::Sse2:
      return "sse2";
    case Isa::Avx2:
      return "avx2";
    case Isa::Avx512:
      return "avx512";
  }
  return "?";
}

bool isa_available(Isa isa) noexcept {
  if (!kernels(isa)) return false;
  __builtin_cpu_init();
  const bool avx2 = __builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma");
  switch (isa) {
    case Isa::Sse2:
      return true;
    case Isa::Avx2:
      return avx2;
    case Isa::Avx512:
      return avx2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512dq") &&
             __builtin_cpu_supports("avx512vl") && __builtin_cpu_supports("avx512bw");
  }
  return false;
}

std::vector<Isa> available_isas() {
  std::vector<Isa> out;
  for (Isa isa : {Isa::Sse2, Isa::Avx2, Isa::Avx512})
    if (isa_available(isa)) out.push_back(isa);
  return out;
}

Isa widest_isa() noexcept {
  for (Isa isa : {Isa::Avx512, Isa::Avx2})
    if (isa_available(isa)) return isa;
  return Isa::Sse2;
}

template <class T>
CrowdKernel<T>::CrowdKernel(const HumanModel<T>& model, Isa isa)
    : isa_(isa),
      table_(&table<T>(isa)),
      model_(table_->make_model(&model), table_->free_model),
      scalar_model_(std::make_unique<const HumanModel<T>>(model)) {}

template <class T>
int CrowdKernel<T>::width() const noexcept {
  return table_->width;
}

template <class T>
typename CrowdKernel<T>::Workspace CrowdKernel<T>::workspace() const {
  return Workspace(table_->make_workspace(model_.get()), table_->free_workspace, *scalar_model_);
}

template <class T>
void CrowdKernel<T>::step(Integrator integrator, Workspace& ws, const CrowdView<T>& crowd, std::size_t begin,
                          std::size_t end, T h, const StepLimits<T>& limits) const noexcept {
  if (integrator == Integrator::BackwardEuler) {
    auto& s = *ws.scalar_;
    step_crowd_backward_euler(*scalar_model_, s.ws, s.x, s.servo, crowd, begin, end, h, limits);
  } else {
    table_->step(int(integrator), model_.get(), ws.get(), &crowd, begin, end, h, &limits);
  }
}

template <class T>
void CrowdKernel<T>::step_backward_euler(Workspace& ws, const CrowdView<T>& crowd,
                                         std::span<BackwardEulerMemory<HumanModel<T>>> memory, std::size_t begin,
                                         std::size_t end, T h, const StepLimits<T>& limits) const noexcept {
  auto& s = *ws.scalar_;
  step_crowd_backward_euler(*scalar_model_, s.ws, s.x, s.servo, crowd, memory, begin, end, h, limits);
}

template <class T>
void CrowdKernel<T>::inverse_dynamics(Workspace& ws, const T* q, const T* qd, const T* qdd, T* tau, std::size_t begin,
                                      std::size_t end) const noexcept {
  table_->inverse_dynamics(model_.get(), ws.get(), q, qd, qdd, tau, begin, end);
}

template class CrowdKernel<double>;
template class CrowdKernel<float>;

}  // namespace humandyn
