// The crowd kernels for one instruction set, chosen by the build (HUMANDYN_CROWD_ISA, with the compiler
// flags of that set): step_crowd and inverse dynamics in the native SIMD lanes of double and float.
// The engine's headers are compiled here inside a namespace of this set's own (HUMANDYN_CROWD_NS), so
// that no inline function compiled for AVX-512 can be merged by the linker with the baseline copy the
// rest of the program calls.
#include "kernel_table.hpp"

#define humandyn HUMANDYN_CROWD_NS
#include "humandyn/algorithm/rnea.hpp"
#include "humandyn/crowd.hpp"
#undef humandyn

#include <cstring>

namespace {

namespace hd = HUMANDYN_CROWD_NS;

template <class T>
using Lanes = hd::NativeBatch<T>;
template <class T>
using BModel = hd::BatchModel<Lanes<T>>;
template <class T>
using Work = hd::CrowdWorkspace<Lanes<T>>;

template <class T>
void* make_model(const void* model) {
  return new BModel<T>(*static_cast<const hd::HumanModel<T>*>(model));
}
template <class T>
void free_model(void* m) {
  delete static_cast<BModel<T>*>(m);
}
template <class T>
void* make_workspace(const void* m) {
  return new Work<T>(*static_cast<const BModel<T>*>(m));
}
template <class T>
void free_workspace(void* w) {
  delete static_cast<Work<T>*>(w);
}

template <class T>
void step(int integrator, const void* m, void* w, const void* crowd, std::size_t begin, std::size_t end, T h,
          const void* limits) {
  const auto& model = *static_cast<const BModel<T>*>(m);
  auto& ws = *static_cast<Work<T>*>(w);
  const auto& view = *static_cast<const hd::CrowdView<T>*>(crowd);
  const auto& lim = *static_cast<const hd::StepLimits<T>*>(limits);
  switch (hd::Integrator(integrator)) {
    case hd::Integrator::SemiImplicitEuler:
      hd::step_crowd<hd::Integrator::SemiImplicitEuler>(model, ws, view, begin, end, h, lim);
      break;
    case hd::Integrator::RungeKutta4:
      hd::step_crowd<hd::Integrator::RungeKutta4>(model, ws, view, begin, end, h, lim);
      break;
    case hd::Integrator::ImplicitPD:
      hd::step_crowd<hd::Integrator::ImplicitPD>(model, ws, view, begin, end, h, lim);
      break;
    case hd::Integrator::BackwardEuler:  // not batched: CrowdKernel::step takes it character by character
      break;
  }
}

template <class T>
void inverse_dynamics(const void* m, void* w, const T* q, const T* qd, const T* qdd, T* tau, std::size_t begin,
                      std::size_t end) {
  const auto& model = *static_cast<const BModel<T>*>(m);
  auto& ws = *static_cast<Work<T>*>(w);
  hd::inverse_dynamics_crowd(model, ws, q, qd, qdd, tau, begin, end);
}

template <class T>
constexpr humandyn::crowd_kernels::Table<T> make_table() {
  return {BModel<T>::width,  make_model<T>, free_model<T>,      make_workspace<T>,
          free_workspace<T>, step<T>,       inverse_dynamics<T>};
}

}  // namespace

const humandyn::crowd_kernels::Kernels& humandyn::crowd_kernels::HUMANDYN_CROWD_ENTRY() noexcept {
  static const Kernels k{make_table<double>(), make_table<float>()};
  return k;
}
