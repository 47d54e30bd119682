# `cmake --install` and `cpack -G DEB` (layout: cmake/InstallLayout.cmake).
# Test: test/install (ctest -R Install).

# The processes that run on the robot: one evade@NAME.service each, all
# wanted by evade.target. sim is installed but not started.
set(EVADE_ROBOT_PROCESSES lidar_driver base_driver elevation_map tracker predictor planner route)
# Every program of procs/ and tools/src/ (their folder name is the target's).
set(EVADE_INSTALLED_PROGRAMS)
foreach(dir procs tools/src)
  file(GLOB subs RELATIVE ${EVADE_SOURCE_DIR}/${dir} ${EVADE_SOURCE_DIR}/${dir}/*/CMakeLists.txt)
  foreach(s ${subs})
    get_filename_component(name ${s} DIRECTORY)
    if(TARGET ${name})
      get_target_property(type ${name} TYPE)
      if(type STREQUAL "EXECUTABLE")
        list(APPEND EVADE_INSTALLED_PROGRAMS ${name})
      endif()
    endif()
  endforeach()
endforeach()
# The tools a robot or its operator uses (the benchmark tools stay in the tree).
set(EVADE_INSTALLED_TOOLS launch goto bus-firewall health evade-viz lcm-spy lcm-logplayer-gui
    lcmlog-export metrics perception-metrics plan-latency run_scenario netns-run netns-pair scenario-gen config-dump)

install(TARGETS ${EVADE_INSTALLED_PROGRAMS} RUNTIME DESTINATION ${EVADE_INSTALL_LIBEXEC}/bin)
foreach(t ${EVADE_INSTALLED_TOOLS})
  install(PROGRAMS ${EVADE_SOURCE_DIR}/tools/${t} DESTINATION ${EVADE_INSTALL_LIBEXEC}/tools)
endforeach()
install(FILES ${EVADE_SOURCE_DIR}/tools/paths.sh DESTINATION ${EVADE_INSTALL_LIBEXEC}/tools)

set(gen ${CMAKE_BINARY_DIR}/install)
configure_file(${EVADE_SOURCE_DIR}/cmake/install/installed-layout.sh.in ${gen}/installed-layout.sh @ONLY)
configure_file(${EVADE_SOURCE_DIR}/cmake/install/evade.in ${gen}/evade @ONLY)
string(REPLACE ";" " " EVADE_ROBOT_UNITS_WANTED "${EVADE_ROBOT_PROCESSES}")
string(REGEX REPLACE "([^ ]+)" "evade@\\1.service" EVADE_ROBOT_UNITS_WANTED "${EVADE_ROBOT_UNITS_WANTED}")
foreach(u evade@.service evade-bus.service evade.target)
  configure_file(${EVADE_SOURCE_DIR}/cmake/install/${u}.in ${gen}/${u} @ONLY)
  install(FILES ${gen}/${u} DESTINATION ${EVADE_INSTALL_UNITDIR})
endforeach()
install(FILES ${gen}/installed-layout.sh DESTINATION ${EVADE_INSTALL_LIBEXEC}/tools)
install(PROGRAMS ${gen}/evade DESTINATION ${CMAKE_INSTALL_BINDIR})

install(FILES ${EVADE_SOURCE_DIR}/config/robot.yaml ${EVADE_SOURCE_DIR}/config/scenario_families.yaml
              ${EVADE_SOURCE_DIR}/cmake/install/evade.env
        DESTINATION ${EVADE_INSTALL_FULL_SYSCONF})
# The robot profiles beside robot.yaml (lib/config/README.md): the shipped
# scenarios name them (paper_sim: jackal).
install(DIRECTORY ${EVADE_SOURCE_DIR}/config/robots/ DESTINATION ${EVADE_INSTALL_FULL_SYSCONF}/robots
        FILES_MATCHING PATTERN "*.yaml")
install(DIRECTORY ${EVADE_SOURCE_DIR}/config/scenarios/ DESTINATION ${CMAKE_INSTALL_DATADIR}/evade/scenarios
        FILES_MATCHING PATTERN "*.yaml")
foreach(jar evade_lcmtypes evade_tools)
  install(FILES ${CMAKE_BINARY_DIR}/share/java/${jar}.jar DESTINATION ${CMAKE_INSTALL_DATADIR}/java OPTIONAL)
endforeach()

# cpack -G DEB: configure with -DCMAKE_INSTALL_PREFIX=/usr so that the
# units and the configuration rule name /usr/libexec/evade and /etc/evade.
set(CPACK_PACKAGE_NAME evade)
set(CPACK_PACKAGE_VERSION 0.1.0)
set(CPACK_PACKAGE_CONTACT "evade maintainers <evade@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "LiDAR-only dynamic obstacle avoidance (MPC-D-CBF) on an LCM bus")
set(CPACK_PACKAGING_INSTALL_PREFIX ${CMAKE_INSTALL_PREFIX})
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
# Shared libraries found by dpkg-shlibdeps; the rest by name: lcm-logger
# (liblcm-bin), the tools' tmux, nft and ip, and Java for lcm-spy.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_DEBIAN_PACKAGE_DEPENDS "liblcm-bin, iproute2, nftables, tmux, procps")
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "liblcm-java, default-jre-headless, openssh-client")
configure_file(${EVADE_SOURCE_DIR}/cmake/install/conffiles.in ${gen}/conffiles @ONLY)
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA ${gen}/conffiles)
include(CPack)
