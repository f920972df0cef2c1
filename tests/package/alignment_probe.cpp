// A program on one compiled component (HUMANDYN_PROBE: crowd, bvh or urdf), compiled by the tests
// component_alignment_* once with the build's flags, when it links, and once for AVX-512 (with and without
// --gc-sections), when Eigen's alignment is 64 bytes where the library's is 16 and it must fail to link,
// naming that alignment (humandyn/detail/component_abi.hpp).
#if HUMANDYN_PROBE == 1
#include <humandyn/crowd_kernels.hpp>
#elif HUMANDYN_PROBE == 2
#include <humandyn/bvh.hpp>
#else
#include <humandyn/urdf.hpp>
#endif

int main() { return 0; }
