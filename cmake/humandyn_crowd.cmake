# The `crowd` component of the humandyn package: the target humandyn::crowd (on Eigen, which the package finds).
include("${CMAKE_CURRENT_LIST_DIR}/humandyn_crowdTargets.cmake")
