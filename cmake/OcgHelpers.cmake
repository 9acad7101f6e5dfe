# Helpers that give every module, test, tool and benchmark the same flags.

set(OCG_WARNING_FLAGS -Wall -Wextra -Wpedantic)

function(_ocg_apply_flags target)
  target_compile_options(${target} PRIVATE ${OCG_WARNING_FLAGS})
  if(OCG_WERROR)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
  if(OCG_NATIVE_ARCH)
    target_compile_options(${target} PRIVATE -march=native)
  endif()
endfunction()

# The flags of a test program. The code under test is the libraries', built as the build
# type says; the test bodies (GoogleTest's macros, scene set-up) compile a third faster at
# -O1 than at -O3 and run as fast. On x86-64 without -ffast-math the level does not change
# a floating-point result. Coming after the build type's flags, this -O1 is the one that
# counts.
function(_ocg_apply_test_flags target)
  _ocg_apply_flags(${target})
  target_compile_options(${target} PRIVATE $<$<CONFIG:Release,RelWithDebInfo,MinSizeRel>:-O1>)
  # The fuzzers' sanitizer build (tools/fuzz.sh) builds ocg_test too, for fuzz_smoke: at
  # -O0 its test files and precompiled header took 85 CPU seconds instead of 127 at the
  # build's -O1 (clang 14, address and undefined), and it still runs in under a second.
  if(OCG_FUZZ)
    target_compile_options(${target} PRIVATE -O0)
  endif()
endfunction()

# ocg_add_library(<module> SOURCES ... [PUBLIC_DEPS ...] [PRIVATE_DEPS ...])
# Creates target ocglib_<module> (file libocg_<module>) with alias ocg::<module>, headers under include/ocg/<module>.
function(ocg_add_library module)
  cmake_parse_arguments(ARG "" "" "SOURCES;PUBLIC_DEPS;PRIVATE_DEPS" ${ARGN})
  set(target ocglib_${module})
  add_library(${target} ${ARG_SOURCES})
  add_library(ocg::${module} ALIAS ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${module} OUTPUT_NAME ocg_${module})
  target_include_directories(${target} PUBLIC
    $<BUILD_INTERFACE:${PROJECT_SOURCE_DIR}/include>
    $<INSTALL_INTERFACE:${CMAKE_INSTALL_INCLUDEDIR}>)
  target_link_libraries(${target} PUBLIC ${ARG_PUBLIC_DEPS} PRIVATE ${ARG_PRIVATE_DEPS})
  _ocg_apply_flags(${target})
  install(TARGETS ${target} EXPORT ocgTargets
    ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
    LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR})
  set_property(GLOBAL APPEND PROPERTY OCG_MODULES ${module})
endfunction()

# ocg_add_test(<name> SOURCES ... DEPS ...): a GoogleTest executable registered with CTest.
function(ocg_add_test name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} ocg_test_support GTest::gtest GTest::gtest_main)
  _ocg_apply_test_flags(${name})
  if(TARGET ocg_test_pch_host)
    target_precompile_headers(${name} REUSE_FROM ocg_test_pch_host)
  endif()
  gtest_discover_tests(${name} DISCOVERY_TIMEOUT 60
    PROPERTIES ENVIRONMENT "OCG_SOURCE_DIR=${PROJECT_SOURCE_DIR}")
endfunction()

# ocg_add_tool(<name> SOURCES ... DEPS ... [NO_INSTALL]): a command-line program,
# installed unless NO_INSTALL (benchmark programs).
function(ocg_add_tool name)
  cmake_parse_arguments(ARG "NO_INSTALL" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS})
  _ocg_apply_flags(${name})
  if(NOT ARG_NO_INSTALL)
    install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  endif()
endfunction()

# ocg_add_bench(<name> SOURCES ... DEPS ...): a Google Benchmark program (never run by ctest).
function(ocg_add_bench name)
  cmake_parse_arguments(ARG "" "" "SOURCES;DEPS" ${ARGN})
  add_executable(${name} ${ARG_SOURCES})
  target_link_libraries(${name} PRIVATE ${ARG_DEPS} benchmark::benchmark)
  _ocg_apply_flags(${name})
endfunction()

function(ocg_install_package)
  include(CMakePackageConfigHelpers)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/ocg DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
  install(EXPORT ocgTargets NAMESPACE ocg:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ocg)
  configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/ocgConfig.cmake.in
    ${PROJECT_BINARY_DIR}/ocgConfig.cmake INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ocg)
  write_basic_package_version_file(${PROJECT_BINARY_DIR}/ocgConfigVersion.cmake
    COMPATIBILITY SameMinorVersion)
  install(FILES ${PROJECT_BINARY_DIR}/ocgConfig.cmake ${PROJECT_BINARY_DIR}/ocgConfigVersion.cmake
    DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/ocg)
endfunction()

# Sanitizers on every target, so that a fault inside a library is caught where it happens,
# and libFuzzer's coverage instrumentation; the fuzz targets themselves link -fsanitize=fuzzer.
macro(ocg_enable_fuzzing)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "OCG_FUZZ needs clang (libFuzzer), not ${CMAKE_CXX_COMPILER_ID}: "
                        "configure with -DCMAKE_CXX_COMPILER=clang++, or use tools/fuzz.sh")
  endif()
  set(OCG_SANITIZE_FLAGS -fsanitize=address,undefined -fno-sanitize-recover=undefined)
  add_compile_options(${OCG_SANITIZE_FLAGS} -fsanitize=fuzzer-no-link -fno-omit-frame-pointer)
  add_link_options(${OCG_SANITIZE_FLAGS})
endmacro()
