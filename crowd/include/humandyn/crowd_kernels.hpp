// The crowd algorithms of crowd.hpp compiled once per instruction set — SSE2 (every x86-64), AVX2 with
// FMA, AVX-512 — each in its native SIMD lanes, and chosen at run time by what the CPU has. For programs
// built for generic x86-64, which is what a program linking Debian's KDL must be (no -march=native): the
// kernels live in translation units of their own and only plain pointers cross into them. A program
// compiled with -march=native can instead call crowd.hpp's step_crowd with NativeBatch<T> directly.
#pragma once

#include "humandyn/crowd.hpp"
#include "humandyn/detail/component_abi.hpp"

#include <cstddef>
#include <cstdint>
#include <memory>
#include <span>
#include <vector>

// (files that include this header link humandyn::crowd built for the same Eigen alignment: component_abi.hpp)
HUMANDYN_COMPONENT_ABI_CHECK(crowd)

namespace humandyn {

namespace crowd_kernels {
template <class T>
struct Table;
}

/// The instruction sets the crowd kernels are compiled for.
enum class Isa : std::uint8_t { Sse2, Avx2, Avx512 };

/// \return "sse2", "avx2" or "avx512"
const char* isa_name(Isa isa) noexcept;

/// \return whether this build holds kernels for `isa` and the CPU (and the OS) runs them
bool isa_available(Isa isa) noexcept;

/// \return every available instruction set, narrowest first (SSE2 always)
std::vector<Isa> available_isas();

/// \return the widest available instruction set
Isa widest_isa() noexcept;

/// One model's crowd algorithms in the lanes of one instruction set: the model broadcast to every lane.
/// \tparam T  double or float
template <class T>
class CrowdKernel {
 public:
  /// Every buffer a call writes; one per thread, made by workspace().
  class Workspace {
   public:
    void* get() const noexcept { return p_.get(); }

   private:
    friend class CrowdKernel;
    Workspace(void* p, void (*free)(void*), const HumanModel<T>& model)
        : p_(p, free), scalar_(std::make_unique<Scalar>(model)) {}
    std::unique_ptr<void, void (*)(void*)> p_;
    struct Scalar {  // backward Euler's, character by character
      explicit Scalar(const HumanModel<T>& model) : ws(model), x(model), servo(model) {}
      StepWorkspace<HumanModel<T>> ws;
      State<HumanModel<T>> x;
      PdServo<HumanModel<T>> servo;
    };
    std::unique_ptr<Scalar> scalar_;
  };

  /// \param model  the model every character runs (copied into the lanes)
  /// \param isa    an available instruction set (isa_available)
  /// \throws std::invalid_argument when `isa` is not available
  explicit CrowdKernel(const HumanModel<T>& model, Isa isa = widest_isa());

  Isa isa() const noexcept { return isa_; }
  /// \return characters per batch (the lanes of T in this instruction set)
  int width() const noexcept;
  Workspace workspace() const;

  /// step_crowd (crowd.hpp) of characters [begin, end): statuses and states as the scalar step() gives them.
  /// SemiImplicitEuler, RungeKutta4 or ImplicitPD in the lanes; BackwardEuler is not batched: it is
  /// step_crowd_backward_euler, the scalar step character by character (in the build's own instruction
  /// set, whatever `isa`), each from a fresh start.
  void step(Integrator integrator, Workspace& ws, const CrowdView<T>& crowd, std::size_t begin, std::size_t end, T h,
            const StepLimits<T>& limits = {}) const noexcept;

  /// Backward Euler for characters [begin, end), each continuing its last step from its memory
  /// (step_crowd_backward_euler with `memory`, crowd.hpp: memory[c] for character c, at least `end` of them).
  void step_backward_euler(Workspace& ws, const CrowdView<T>& crowd,
                           std::span<BackwardEulerMemory<HumanModel<T>>> memory, std::size_t begin, std::size_t end,
                           T h, const StepLimits<T>& limits = {}) const noexcept;

  /// inverse_dynamics_crowd (crowd.hpp) of characters [begin, end).
  void inverse_dynamics(Workspace& ws, const T* q, const T* qd, const T* qdd, T* tau, std::size_t begin,
                        std::size_t end) const noexcept;

 private:
  Isa isa_;
  const crowd_kernels::Table<T>* table_;
  std::unique_ptr<void, void (*)(void*)> model_;
  std::unique_ptr<const HumanModel<T>> scalar_model_;  // backward Euler's
};

extern template class CrowdKernel<double>;
extern template class CrowdKernel<float>;

}  // namespace humandyn
