// libFuzzer target: the joint map parser fed arbitrary bytes (fuzz_inputs.hpp says what it must do).
// Build with clang and -DHUMANDYN_BUILD_FUZZER=ON; seeds in tests/data/fuzz/joint_map (docs/urdf.md).
#include "fuzz_inputs.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    humandyn::fuzz::parse_joint_map_input(std::string(reinterpret_cast<const char*>(data), size));
  } catch (const humandyn::urdf::Error&) {
  }
  return 0;
}
