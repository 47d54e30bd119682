# Fuzz targets for parsers of outside bytes (LiDAR packets, serial frames).
#
#   include(${EVADE_SOURCE_DIR}/cmake/Fuzz.cmake)
#   evade_add_fuzzer(NAME
#     SOURCES harness.cpp ...        # defines LLVMFuzzerTestOneInput
#     LIBS evade_x ...               # what the harness links
#     CORPUS dir                     # small committed seed corpus (test/fuzz/corpus/NAME)
#     [SECONDS 20]                   # libFuzzer run length in ctest
#     [MUTATIONS 20000]              # corpus-regression mutated inputs
#     [CLANG_FLAGS -I... -D...]      # extra flags for the clang build
#     [CLANG_LINK -lpcap ...])       # extra link flags for the clang build
#
# Always: bin/fuzz_NAME_regression, the harness built with the project's
# compiler plus test/fuzz/fuzz_driver.cpp, which runs every seed and then a
# fixed number of deterministic mutations of them; ctest
# fuzz_NAME_regression (label "fuzz").
#
# When clang++-14 (or clang++) links -fsanitize=fuzzer,address: also
# bin/fuzz_NAME, a real libFuzzer binary. The project is built with gcc, so
# the harness and the sources of LIBS (the library targets' own .cpp files,
# not their dependencies') are compiled again with clang, instrumented;
# ctest fuzz_NAME_libfuzzer runs it for SECONDS on a scratch copy of the
# corpus (build/fuzz/NAME/), crashes saved there too.
include_guard(GLOBAL)

# Cache variables: the guard means only the first includer's scope runs
# this file, and every later caller of the function must still see them.
get_filename_component(_evade_fuzz_driver ${CMAKE_CURRENT_LIST_DIR}/../test/fuzz/fuzz_driver.cpp ABSOLUTE)
set(EVADE_FUZZ_DRIVER ${_evade_fuzz_driver} CACHE INTERNAL "corpus-regression main for fuzz targets")

find_program(EVADE_CLANGXX NAMES clang++-14 clang++)
if(EVADE_CLANGXX AND NOT DEFINED EVADE_LIBFUZZER_WORKS)
  set(_probe_dir ${CMAKE_BINARY_DIR}/fuzz/probe)
  file(MAKE_DIRECTORY ${_probe_dir})
  file(WRITE ${_probe_dir}/probe.cpp
       "#include <cstdint>\n#include <cstddef>\nextern \"C\" int LLVMFuzzerTestOneInput(const uint8_t*, size_t) { return 0; }\n")
  execute_process(
    COMMAND ${EVADE_CLANGXX} -fsanitize=fuzzer,address ${_probe_dir}/probe.cpp -o ${_probe_dir}/probe
    RESULT_VARIABLE _probe_rc OUTPUT_QUIET ERROR_QUIET)
  if(_probe_rc EQUAL 0)
    set(EVADE_LIBFUZZER_WORKS ON CACHE BOOL "clang links -fsanitize=fuzzer,address")
  else()
    set(EVADE_LIBFUZZER_WORKS OFF CACHE BOOL "clang links -fsanitize=fuzzer,address")
  endif()
  message(STATUS "libFuzzer with ${EVADE_CLANGXX}: ${EVADE_LIBFUZZER_WORKS}")
endif()

function(evade_add_fuzzer name)
  cmake_parse_arguments(F "" "CORPUS;SECONDS;MUTATIONS" "SOURCES;LIBS;CLANG_FLAGS;CLANG_LINK" ${ARGN})
  if(NOT F_CORPUS)
    message(FATAL_ERROR "evade_add_fuzzer(${name}): CORPUS is required")
  endif()
  if(NOT F_SECONDS)
    set(F_SECONDS 20)
  endif()
  if(NOT F_MUTATIONS)
    set(F_MUTATIONS 20000)
  endif()
  set(harness)
  foreach(s ${F_SOURCES})
    get_filename_component(abs ${s} ABSOLUTE BASE_DIR ${CMAKE_CURRENT_SOURCE_DIR})
    list(APPEND harness ${abs})
  endforeach()

  # Corpus regression with the project's compiler.
  add_executable(fuzz_${name}_regression ${harness} ${EVADE_FUZZ_DRIVER})
  target_link_libraries(fuzz_${name}_regression PRIVATE ${F_LIBS})
  if(EVADE_BUILD_TESTS)
    add_test(NAME fuzz_${name}_regression
             COMMAND fuzz_${name}_regression --mutations ${F_MUTATIONS} ${F_CORPUS})
    set_tests_properties(fuzz_${name}_regression PROPERTIES LABELS fuzz TIMEOUT 300)
  endif()

  if(NOT EVADE_LIBFUZZER_WORKS)
    return()
  endif()
  # The same harness and the LIBS' own sources, instrumented by clang.
  set(lib_sources)
  set(lib_defines)
  set(deps ${harness})
  foreach(lib ${F_LIBS})
    if(NOT TARGET ${lib})
      continue()
    endif()
    get_target_property(type ${lib} TYPE)
    if(NOT type MATCHES "STATIC_LIBRARY|SHARED_LIBRARY|OBJECT_LIBRARY")
      continue()
    endif()
    get_target_property(srcs ${lib} SOURCES)
    get_target_property(dir ${lib} SOURCE_DIR)
    # The library's own compile definitions (e.g. lib/config's paths).
    get_target_property(defs ${lib} COMPILE_DEFINITIONS)
    if(defs)
      foreach(d ${defs})
        list(APPEND lib_defines -D${d})
      endforeach()
    endif()
    foreach(s ${srcs})
      get_filename_component(abs ${s} ABSOLUTE BASE_DIR ${dir})
      if(abs MATCHES "\\.(cpp|cc|cxx)$")
        list(APPEND lib_sources ${abs})
      endif()
    endforeach()
  endforeach()
  set(out ${CMAKE_BINARY_DIR}/bin/fuzz_${name})
  add_custom_command(
    OUTPUT ${out}
    COMMAND ${EVADE_CLANGXX} -std=c++17 -g -O1 -fsanitize=fuzzer,address,undefined
            -fno-sanitize-recover=undefined
            -I${EVADE_SOURCE_DIR}/lib -I${CMAKE_BINARY_DIR}/gen/cpp
            -DEVADE_SOURCE_DIR="${EVADE_SOURCE_DIR}" ${lib_defines} ${F_CLANG_FLAGS}
            ${harness} ${lib_sources} ${F_CLANG_LINK} -lcrypto -o ${out}
    DEPENDS ${harness} ${lib_sources}
    COMMENT "clang libFuzzer: fuzz_${name}"
    COMMAND_EXPAND_LISTS VERBATIM)
  add_custom_target(fuzz_${name}_libfuzzer ALL DEPENDS ${out})
  if(TARGET evade_lcmtypes_cpp)
    add_dependencies(fuzz_${name}_libfuzzer evade_lcmtypes_cpp)
  endif()
  if(EVADE_BUILD_TESTS)
    set(work ${CMAKE_BINARY_DIR}/fuzz/${name})
    # A fixed seed: a CI run explores the same mutations every time (as far
    # as its time allows), so a red run is reproducible; longer exploration
    # with other seeds is run by hand (build/bin/fuzz_NAME CORPUS).
    add_test(NAME fuzz_${name}_libfuzzer
             COMMAND sh -c "mkdir -p '${work}/corpus' && exec '${out}' -seed=1 -max_total_time=${F_SECONDS} -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 -artifact_prefix='${work}/' '${work}/corpus' '${F_CORPUS}'")
    math(EXPR timeout "${F_SECONDS} * 2 + 60")
    set_tests_properties(fuzz_${name}_libfuzzer PROPERTIES LABELS fuzz TIMEOUT ${timeout})
  endif()
endfunction()
