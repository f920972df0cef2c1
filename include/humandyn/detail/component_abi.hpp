// The link-time check that a program and the compiled components it links (humandyn::urdf, ::bvh,
// ::crowd) agree on Eigen's alignment: EIGEN_MAX_ALIGN_BYTES and EIGEN_MAX_STATIC_ALIGN_BYTES, which the
// instruction set a file is compiled for sets (16 for generic x86-64, 32 with AVX, 64 with AVX-512). The
// types both sides use are laid out by it (a StepWorkspace holds fixed-size vectors) and Eigen allocates
// and frees by it, so files compiled for different sets and linked together would disagree on them in
// silence. Each component defines one symbol named after its build's alignments
// (HUMANDYN_COMPONENT_ABI_DEFINE, in one of its .cpp files); its header makes every file that includes
// it refer to the symbol named after that file's (HUMANDYN_COMPONENT_ABI_CHECK). A program compiled
// with, say, -march=native against components built for generic x86-64 then fails to link, naming
// both alignments it has: "undefined reference to `humandyn::abi::crowd_eigen_align_64_64'". The cure
// is one set of flags for both (build the components with the program's, docs/architecture.md).
#pragma once

#include <Eigen/Core>

#define HUMANDYN_ABI_NAME_(component, max, max_static) component##_eigen_align_##max##_##max_static
#define HUMANDYN_ABI_NAME(component, max, max_static) HUMANDYN_ABI_NAME_(component, max, max_static)
#define HUMANDYN_ABI_SYMBOL(component) HUMANDYN_ABI_NAME(component, EIGEN_MAX_ALIGN_BYTES, EIGEN_MAX_STATIC_ALIGN_BYTES)

// Kept by the compiler (used) and by the linker, even with --gc-sections (retain, where it is known).
#if defined(__has_attribute) && __has_attribute(retain)
#define HUMANDYN_ABI_KEEP [[gnu::used, gnu::retain]]
#else
#define HUMANDYN_ABI_KEEP [[gnu::used]]
#endif

// In a component's public header: this file's alignments, referred to.
#define HUMANDYN_COMPONENT_ABI_CHECK(component)                                                       \
  namespace humandyn::abi {                                                                           \
  extern const int HUMANDYN_ABI_SYMBOL(component);                                                    \
  HUMANDYN_ABI_KEEP static const int* const component##_alignments = &HUMANDYN_ABI_SYMBOL(component); \
  }

// In one .cpp file of the component: its build's alignments, defined.
#define HUMANDYN_COMPONENT_ABI_DEFINE(component)                                  \
  namespace humandyn::abi {                                                       \
  extern const int HUMANDYN_ABI_SYMBOL(component) = EIGEN_MAX_STATIC_ALIGN_BYTES; \
  }
