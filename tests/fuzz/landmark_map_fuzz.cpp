// libFuzzer target: the landmark map parser fed arbitrary bytes (bvh_inputs.hpp says what it must do).
// Build with clang and -DHUMANDYN_BUILD_FUZZER=ON; seeds in tests/data/fuzz/landmark_map (docs/motion.md).
#include "bvh_inputs.hpp"

#include <cstddef>
#include <cstdint>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    humandyn::fuzz::landmark_map_input(std::string(reinterpret_cast<const char*>(data), size));
  } catch (const humandyn::motion::BvhError&) {
  }
  return 0;
}
