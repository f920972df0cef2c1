// Joint names: the one rule for a name that heads CSV columns (text/names.hpp holds it).
#include "text/names.hpp"
#include "humandyn/urdf.hpp"

// this build's Eigen alignment (humandyn/detail/component_abi.hpp), in the component's smallest file
HUMANDYN_COMPONENT_ABI_DEFINE(urdf)

namespace humandyn::urdf {

std::string name_fault(const std::string& name) { return text::name_fault(name); }

}  // namespace humandyn::urdf
