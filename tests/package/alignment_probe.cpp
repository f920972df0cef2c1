// A program on the crowd kernels (humandyn::crowd), compiled by the test component_alignment_* once with
// the build's flags, when it links, and once for AVX-512, when Eigen's alignment is 64 bytes where the
// library's is 16 and it must fail to link, naming that alignment (humandyn/detail/component_abi.hpp).
#include <humandyn/crowd_kernels.hpp>

int main() { return humandyn::available_isas().empty() ? 1 : 0; }
