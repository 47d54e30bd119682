# evade_add_gtest(NAME SOURCES a.cpp ... LIBS x y LABEL unit|integration [NETNS] [SERIAL] [TIMEOUT s])
#   One GoogleTest binary, each TEST registered with ctest by discovery.
#   NETNS: every test runs through tools/netns-run, inside a private network
#   namespace with multicast routed to lo and ttl=0, so no packet leaves.
set(EVADE_NETNS_RUN ${CMAKE_SOURCE_DIR}/tools/netns-run)
# Every test signs and checks the bus with the committed test-only key
# (test/data/bus_test.key), never the user's: a copy with mode 0600 (git
# keeps no modes, and a key readable by others is refused), named by
# $EVADE_BUS_KEY, which overrides bus.auth.key_file.
file(COPY ${CMAKE_SOURCE_DIR}/test/data/bus_test.key DESTINATION ${CMAKE_BINARY_DIR}/test
     FILE_PERMISSIONS OWNER_READ OWNER_WRITE)
set(EVADE_TEST_KEY ${CMAKE_BINARY_DIR}/test/bus_test.key)
set(EVADE_TEST_ENV EVADE_BUS_KEY=${EVADE_TEST_KEY})
function(evade_add_gtest name)
  cmake_parse_arguments(T "NETNS;SERIAL" "LABEL;TIMEOUT" "SOURCES;LIBS" ${ARGN})
  if(NOT T_LABEL)
    message(FATAL_ERROR "evade_add_gtest(${name}): LABEL unit or integration is required")
  endif()
  if(NOT T_TIMEOUT)
    set(T_TIMEOUT 120)
  endif()
  add_executable(${name} ${T_SOURCES})
  target_link_libraries(${name} PRIVATE ${T_LIBS} GTest::gtest GTest::gtest_main GTest::gmock)
  if(T_NETNS)
    set_target_properties(${name} PROPERTIES CROSSCOMPILING_EMULATOR ${EVADE_NETNS_RUN})
  endif()
  set(serial FALSE)
  if(T_SERIAL)
    set(serial TRUE)
  endif()
  gtest_discover_tests(${name}
    WORKING_DIRECTORY ${CMAKE_SOURCE_DIR}
    PROPERTIES LABELS ${T_LABEL} TIMEOUT ${T_TIMEOUT} RUN_SERIAL ${serial} ENVIRONMENT ${EVADE_TEST_ENV}
    DISCOVERY_TIMEOUT 60
    DISCOVERY_MODE PRE_TEST)
endfunction()
