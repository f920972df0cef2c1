# The `bvh` component of the humandyn package: the target humandyn::bvh (on Eigen, which the package finds).
include("${CMAKE_CURRENT_LIST_DIR}/humandyn_bvhTargets.cmake")
