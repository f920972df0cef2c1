# The README's example is tests/package/example.cpp from its first #include on, as the README says, so the
# example the package test builds and runs is the one a reader copies. Run with cmake -P and
#   -D README=<README.md>  -D EXAMPLE=<example.cpp>
file(READ "${README}" readme)
file(READ "${EXAMPLE}" example)
string(FIND "${example}" "#include" at)
string(SUBSTRING "${example}" ${at} -1 example)
if(NOT readme MATCHES "```cpp\n([^`]*)```")
  message(FATAL_ERROR "${README} has no C++ example")
endif()
if(NOT CMAKE_MATCH_1 STREQUAL example)
  message(FATAL_ERROR "the example in ${README} is not ${EXAMPLE} (from its first #include on):\n${CMAKE_MATCH_1}")
endif()
message(STATUS "the README's example is ${EXAMPLE}")
