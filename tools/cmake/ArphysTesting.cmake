# arphys_add_test(<name> LABEL <unit|integration|slow> [SERIAL] SOURCES <...> LIBS <...>)
# SERIAL: the test measures a running pipeline (frame gaps, counts) and must not share
# the machine's two cores with another test.
# One GoogleTest executable per call; every test case is registered with ctest
# under the given label so `ctest -L unit` etc. select them (ARPHYS_TEST_WHOLE_EXECUTABLES:
# the executable as one test, under that label).
function(arphys_add_test name)
  cmake_parse_arguments(ARG "SERIAL" "LABEL;TIMEOUT" "SOURCES;LIBS" ${ARGN})
  if(NOT ARG_LABEL MATCHES "^(unit|integration|slow)$")
    message(FATAL_ERROR "arphys_add_test(${name}): LABEL must be unit, integration or slow")
  endif()
  if(NOT ARG_TIMEOUT)
    set(ARG_TIMEOUT 300)
  endif()
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_LIBS} GTest::gtest GTest::gtest_main)
  target_include_directories(${name} PRIVATE ${ARPHYS_SOURCE_DIR})  # tests/support/
  target_compile_definitions(${name} PRIVATE
    ARPHYS_SOURCE_DIR="${ARPHYS_SOURCE_DIR}"
    ARPHYS_BINARY_DIR="${CMAKE_BINARY_DIR}")
  # A test's own code checks, it is not what is measured: at -O1 it compiles a third quicker
  # than at Release's -O3 (GCC), and the libraries under test keep the build type's flags.
  if(CMAKE_BUILD_TYPE STREQUAL "Release" AND CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    target_compile_options(${name} PRIVATE -O1)
  endif()
  set(serial FALSE)
  if(ARG_SERIAL)
    set(serial TRUE)
  endif()
  if(ARPHYS_TEST_WHOLE_EXECUTABLES)
    add_test(NAME ${name} COMMAND ${name})
    set_tests_properties(${name} PROPERTIES LABELS ${ARG_LABEL} TIMEOUT ${ARG_TIMEOUT} RUN_SERIAL ${serial})
  else()
    gtest_discover_tests(${name}
      PROPERTIES LABELS ${ARG_LABEL} TIMEOUT ${ARG_TIMEOUT} RUN_SERIAL ${serial}
      DISCOVERY_TIMEOUT 60)
  endif()
endfunction()
