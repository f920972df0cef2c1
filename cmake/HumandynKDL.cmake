# KDL (orocos) and kdl_parser as one imported target, humandyn_kdl, with the bridge from a model
# description to a KDL tree or chain (support/kdl/support/kdl_tree.hpp, included as
# "support/kdl_tree.hpp"). Debian 12's kdl_parser CMake package pulls in ROS tooling, so it is found by
# library and header instead.
# Everything linking it must be compiled with flags compatible with Debian's KDL (no -march=native):
# Eigen objects cross the library boundary and must agree on alignment.
find_package(orocos_kdl REQUIRED)
find_library(HUMANDYN_KDL_PARSER_LIBRARY kdl_parser REQUIRED)
find_path(HUMANDYN_KDL_PARSER_INCLUDE kdl_parser/kdl_parser.hpp REQUIRED)
find_package(urdfdom REQUIRED)
add_library(humandyn_kdl INTERFACE)
target_include_directories(humandyn_kdl SYSTEM INTERFACE ${orocos_kdl_INCLUDE_DIRS} ${HUMANDYN_KDL_PARSER_INCLUDE}
  ${PROJECT_SOURCE_DIR}/support/kdl)
target_link_libraries(humandyn_kdl INTERFACE ${orocos_kdl_LIBRARIES} ${HUMANDYN_KDL_PARSER_LIBRARY}
  urdfdom::urdfdom_model)
