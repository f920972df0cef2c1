# Installs a humandyn build into a fresh prefix, then configures, builds and runs the consumer project
# against that prefix alone. Run with cmake -P and
#   -D BUILD_DIR=<the humandyn build>  -D CONSUMER_DIR=<this folder>  -D WORK_DIR=<scratch folder>
#   -D GENERATOR=<CMake generator>  -D CXX_COMPILER=<compiler>
# and optionally -D CXX_FLAGS=<the build's CMAKE_CXX_FLAGS>: the consumer is compiled with them alone (no
# build type's flags: a sanitizer build's installed libraries need its consumer instrumented alike, and
# compiled as quickly); without them, as a Release build.
cmake_minimum_required(VERSION 3.20)  # modern policies, as a consuming project has them
foreach(var BUILD_DIR CONSUMER_DIR WORK_DIR GENERATOR CXX_COMPILER)
  if(NOT DEFINED ${var})
    message(FATAL_ERROR "check_package.cmake needs -D ${var}=...")
  endif()
endforeach()
set(prefix "${WORK_DIR}/prefix")
file(REMOVE_RECURSE "${WORK_DIR}")

function(run what)
  execute_process(COMMAND ${ARGN} RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  if(NOT result EQUAL 0)
    message(FATAL_ERROR "${what} failed (${result}):\n${out}\n${err}")
  endif()
  message(STATUS "${what}: ok")
  set(last_output "${out}" PARENT_SCOPE)
endfunction()

# install, as a user would
run("install" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${prefix}")
foreach(f include/humandyn/humandyn.hpp share/humandyn/cmake/humandynConfig.cmake
          share/humandyn/cmake/humandynConfigVersion.cmake share/humandyn/cmake/humandynTargets.cmake)
  if(NOT EXISTS "${prefix}/${f}")
    message(FATAL_ERROR "not installed: ${f}")
  endif()
endforeach()

# the header-only engine installed alone (without the `urdf`, `bvh` and `crowd` components) has none of their
# headers
run("install the engine alone" "${CMAKE_COMMAND}" --install "${BUILD_DIR}" --prefix "${WORK_DIR}/engine-only"
    --component Unspecified)
if(NOT EXISTS "${WORK_DIR}/engine-only/include/humandyn/humandyn.hpp" OR
   EXISTS "${WORK_DIR}/engine-only/include/humandyn/urdf.hpp" OR
   EXISTS "${WORK_DIR}/engine-only/include/humandyn/bvh.hpp" OR
   EXISTS "${WORK_DIR}/engine-only/include/humandyn/crowd_kernels.hpp")
  message(FATAL_ERROR "the engine's install must hold the engine's headers and no URDF, BVH or crowd header")
endif()

# the version file is architecture-independent: a header-only package suits a 32-bit consumer too
set(CMAKE_SIZEOF_VOID_P 4)
set(PACKAGE_FIND_NAME humandyn)
set(PACKAGE_FIND_VERSION 0.1)
set(PACKAGE_FIND_VERSION_MAJOR 0)
set(PACKAGE_FIND_VERSION_MINOR 1)
set(PACKAGE_FIND_VERSION_PATCH 0)
set(PACKAGE_FIND_VERSION_COUNT 2)
include("${prefix}/share/humandyn/cmake/humandynConfigVersion.cmake")
if(PACKAGE_VERSION_UNSUITABLE OR NOT PACKAGE_VERSION_COMPATIBLE)
  message(FATAL_ERROR "the version file refuses a consumer of another pointer size (PACKAGE_VERSION ${PACKAGE_VERSION})")
endif()
unset(CMAKE_SIZEOF_VOID_P)

# configure the consumer against the prefix only (no package registry, no build tree)
if(CXX_FLAGS)
  set(build_type "")
else()
  set(build_type Release)
endif()
set(configure_args -G "${GENERATOR}" -DCMAKE_CXX_COMPILER=${CXX_COMPILER} "-DCMAKE_BUILD_TYPE=${build_type}"
    "-DCMAKE_CXX_FLAGS=${CXX_FLAGS}" -DCMAKE_PREFIX_PATH=${prefix} -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF)
run("configure the consumer" "${CMAKE_COMMAND}" -S "${CONSUMER_DIR}" -B "${WORK_DIR}/build" ${configure_args})
file(STRINGS "${WORK_DIR}/build/CMakeCache.txt" found REGEX "^humandyn_DIR:")
if(NOT found STREQUAL "humandyn_DIR:PATH=${prefix}/share/humandyn/cmake")
  message(FATAL_ERROR "the consumer found humandyn elsewhere: ${found}")
endif()
run("build the consumer" "${CMAKE_COMMAND}" --build "${WORK_DIR}/build")
run("run the consumer" "${WORK_DIR}/build/consumer")
message(STATUS "${last_output}")
if(EXISTS "${WORK_DIR}/build/example")  # the consumer of the header-only package has the README's example
  run("run the README example" "${WORK_DIR}/build/example")
  message(STATUS "${last_output}")
endif()
# the engine's consumer (tests/package) also takes the crowd component, where it is built, and asks for a
# component the package does not have, which the error names
if(EXISTS "${CONSUMER_DIR}/crowd.cpp")
  if(EXISTS "${prefix}/share/humandyn/cmake/humandyn_crowd.cmake")
    if(NOT EXISTS "${prefix}/include/humandyn/crowd_kernels.hpp" OR NOT EXISTS "${WORK_DIR}/build/crowd_consumer")
      message(FATAL_ERROR "the crowd component is installed without its header, or the consumer did not find it")
    endif()
    run("run the crowd consumer" "${WORK_DIR}/build/crowd_consumer")
    message(STATUS "${last_output}")
  endif()
  execute_process(COMMAND "${CMAKE_COMMAND}" -S "${CONSUMER_DIR}" -B "${WORK_DIR}/build-nope" ${configure_args}
                  -DHUMANDYN_REQUIRED_COMPONENTS=nope RESULT_VARIABLE result OUTPUT_VARIABLE out ERROR_VARIABLE err)
  string(REGEX REPLACE "[ \n]+" " " err "${err}")  # (CMake wraps the message)
  if(result EQUAL 0 OR NOT err MATCHES "humandyn: component nope is not installed here \\(installed: [a-z, ]+\\)")
    message(FATAL_ERROR "find_package(humandyn COMPONENTS nope) did not name the component:\n${err}")
  endif()
  message(STATUS "find_package(humandyn COMPONENTS nope) refused, naming it: ok")
endif()

# a major version the package does not have is refused
execute_process(COMMAND "${CMAKE_COMMAND}" -S "${CONSUMER_DIR}" -B "${WORK_DIR}/build-v1" ${configure_args}
                -DHUMANDYN_REQUIRED_VERSION=1.0 RESULT_VARIABLE result OUTPUT_QUIET ERROR_QUIET)
if(result EQUAL 0)
  message(FATAL_ERROR "find_package(humandyn 1.0) accepted version 0.x")
endif()
message(STATUS "find_package(humandyn 1.0) refused: ok")
