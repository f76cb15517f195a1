# Shared target conventions: warnings on every project target, optional sanitizers,
# the source and config folders known to tests and programs, what is installed.
include(GNUInstallDirs)

add_library(rbcp_warnings INTERFACE)
target_compile_options(rbcp_warnings INTERFACE -Wall -Wextra -Wpedantic -Wno-unused-parameter)
if(RBCP_SANITIZE)
  # Every UndefinedBehaviorSanitizer check but vptr: with it, GCC 12 miscompiles the calls through
  # pointers to member functions in LCM's C++ header (lcm-cpp-impl.hpp), and a subscription's
  # handler is called on a wrong object.
  target_compile_options(rbcp_warnings INTERFACE -fsanitize=address,undefined -fno-sanitize=vptr
                                                 -fno-omit-frame-pointer)
  target_link_options(rbcp_warnings INTERFACE -fsanitize=address,undefined -fno-sanitize=vptr)
endif()
if(RBCP_FUZZ)
  # Coverage for libFuzzer in every project target (the fuzz targets link -fsanitize=fuzzer), and
  # the sanitizers' reports end the process, so that the fuzzer sees them.
  target_compile_options(rbcp_warnings INTERFACE -fsanitize=fuzzer-no-link,address,undefined
                                                 -fno-sanitize-recover=all -fno-omit-frame-pointer)
  target_link_options(rbcp_warnings INTERFACE -fsanitize=address,undefined)
endif()
add_library(rbcp::warnings ALIAS rbcp_warnings)

# The pure C++ libraries that `cmake --install` puts in the prefix, with their headers, as the
# CMake package rbcp (targets rbcp::<name>; see tools/cmake/rbcpConfig.cmake.in). The LCM and
# Bullet edges (transport, nodes, sim) stay inside the project.
set(RBCP_INSTALLED_LIBRARIES core robot collision limb_database scenario affordance root_planner equilibrium stance
    contact_planner plan_checker controller)

# rbcp_add_library(NAME <name> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# A module library with include/ as its public include folder, aliased rbcp::<name>.
function(rbcp_add_library)
  cmake_parse_arguments(A "" "NAME" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(include_dirs $<BUILD_INTERFACE:${CMAKE_CURRENT_SOURCE_DIR}/include> $<INSTALL_INTERFACE:include>)
  if(A_SOURCES)
    add_library(rbcp_${A_NAME} STATIC ${A_SOURCES})
    target_include_directories(rbcp_${A_NAME} PUBLIC ${include_dirs})
    target_link_libraries(rbcp_${A_NAME} PUBLIC ${A_PUBLIC_DEPS} PRIVATE $<BUILD_INTERFACE:rbcp::warnings> ${A_PRIVATE_DEPS})
    set_target_properties(rbcp_${A_NAME} PROPERTIES POSITION_INDEPENDENT_CODE ON)
  else()
    add_library(rbcp_${A_NAME} INTERFACE)
    target_include_directories(rbcp_${A_NAME} INTERFACE ${include_dirs})
    target_link_libraries(rbcp_${A_NAME} INTERFACE ${A_PUBLIC_DEPS})
  endif()
  add_library(rbcp::${A_NAME} ALIAS rbcp_${A_NAME})
  if(A_NAME IN_LIST RBCP_INSTALLED_LIBRARIES)
    set_target_properties(rbcp_${A_NAME} PROPERTIES EXPORT_NAME ${A_NAME})
    install(TARGETS rbcp_${A_NAME} EXPORT rbcpTargets ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR})
    install(DIRECTORY ${CMAKE_CURRENT_SOURCE_DIR}/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  endif()
endfunction()

# rbcp_add_test(NAME <name> SOURCES ... DEPS ... [LABELS ...])
# A gtest executable registered with ctest; RBCP_SOURCE_DIR points at the checkout so tests
# can read config/ and test data, RBCP_BIN_DIR at the built programs.
function(rbcp_add_test)
  cmake_parse_arguments(A "" "NAME" "SOURCES;DEPS;LABELS" ${ARGN})
  if(NOT RBCP_BUILD_TESTS)
    return()
  endif()
  add_executable(${A_NAME} ${A_SOURCES})
  # The test code itself at -O2 (the libraries and programs it tests keep the build type's -O3):
  # GoogleTest's macros are template-heavy, -O3 compiles them about 15 % slower, and the time a
  # test takes is spent in the libraries and programs.
  target_compile_options(${A_NAME} PRIVATE $<$<CONFIG:Release>:-O2>)
  target_link_libraries(${A_NAME} PRIVATE ${A_DEPS} GTest::gtest_main rbcp::warnings)
  target_compile_definitions(${A_NAME} PRIVATE
    RBCP_SOURCE_DIR="${CMAKE_SOURCE_DIR}" RBCP_BIN_DIR="${CMAKE_BINARY_DIR}/bin")
  set_target_properties(${A_NAME} PROPERTIES RUNTIME_OUTPUT_DIRECTORY ${CMAKE_BINARY_DIR}/tests)
  gtest_discover_tests(${A_NAME} DISCOVERY_TIMEOUT 60 PROPERTIES LABELS "${A_LABELS}")
endfunction()
