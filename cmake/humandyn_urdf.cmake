# The `urdf` component of the humandyn package: the target humandyn::urdf and what it links.
include(CMakeFindDependencyMacro)
find_dependency(urdfdom)
find_dependency(tinyxml2)
find_dependency(console_bridge)
include("${CMAKE_CURRENT_LIST_DIR}/humandyn_urdfTargets.cmake")
