// The entry points of one instruction set's crowd kernels (kernel.cpp, compiled once per instruction
// set): plain functions on opaque objects. Nothing whose layout depends on the instruction set (Eigen's
// aligned vectors) crosses between the kernels and their callers; the models, crowds, limits and
// statuses handed over are classes without such members, the same in every translation unit.
// This header includes no engine header (kernel.cpp includes the engine after it, in a namespace of
// its own).
#pragma once

#include <cstddef>

namespace humandyn::crowd_kernels {

template <class T>
struct Table {
  int width = 0;                                     // characters per batch
  void* (*make_model)(const void* model) = nullptr;  // a HumanModel<T> broadcast to every lane
  void (*free_model)(void* batch_model) = nullptr;
  void* (*make_workspace)(const void* batch_model) = nullptr;
  void (*free_workspace)(void* workspace) = nullptr;
  // step_crowd of crowd.hpp on a CrowdView<T>, with StepLimits<T>; integrator as the enum's value
  void (*step)(int integrator, const void* batch_model, void* workspace, const void* crowd, std::size_t begin,
               std::size_t end, T h, const void* limits) = nullptr;
  // full inverse dynamics of characters [begin, end), each array character after character (nj each)
  void (*inverse_dynamics)(const void* batch_model, void* workspace, const T* q, const T* qd, const T* qdd, T* tau,
                           std::size_t begin, std::size_t end) = nullptr;
};

struct Kernels {
  Table<double> d;
  Table<float> f;
};

const Kernels& kernels_sse2() noexcept;
const Kernels& kernels_avx2() noexcept;
const Kernels& kernels_avx512() noexcept;

}  // namespace humandyn::crowd_kernels
