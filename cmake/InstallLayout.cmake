# Where `cmake --install` puts evade (cmake/Install.cmake), as GNUInstallDirs
# paths, so a prefix (CMAKE_INSTALL_PREFIX, --prefix) and DESTDIR move it all:
#   <libexecdir>/evade/bin     the programs (procs/ and tools/src/)
#   <libexecdir>/evade/tools   the tools (tools/, they find bin/ beside them)
#   <bindir>/evade             `evade COMMAND ...`: runs a tool or a program
#   <sysconfdir>/evade         robot.yaml, robots/*.yaml (profiles), scenario_families.yaml, evade.env
#   <datadir>/evade/scenarios  the shipped scenarios
#   <datadir>/java             evade_lcmtypes.jar, evade_tools.jar
#   <prefix>/lib/systemd/system  evade@.service, evade-bus.service, evade.target
# Prefix /usr (the .deb) gives /usr/libexec/evade and /etc/evade.
include(GNUInstallDirs)
set(EVADE_INSTALL_LIBEXEC ${CMAKE_INSTALL_LIBEXECDIR}/evade)
set(EVADE_INSTALL_FULL_LIBEXEC ${CMAKE_INSTALL_FULL_LIBEXECDIR}/evade)
set(EVADE_INSTALL_FULL_BIN ${EVADE_INSTALL_FULL_LIBEXEC}/bin)
set(EVADE_INSTALL_FULL_TOOLS ${EVADE_INSTALL_FULL_LIBEXEC}/tools)
set(EVADE_INSTALL_FULL_SYSCONF ${CMAKE_INSTALL_FULL_SYSCONFDIR}/evade)
set(EVADE_INSTALL_FULL_DATA ${CMAKE_INSTALL_FULL_DATADIR}/evade)
set(EVADE_INSTALL_FULL_JAVA ${CMAKE_INSTALL_FULL_DATADIR}/java)
set(EVADE_INSTALL_UNITDIR ${CMAKE_INSTALL_PREFIX}/lib/systemd/system)
# Relative paths, so that a copy under another root (DESTDIR, dpkg-deb -x)
# finds its own configuration: lib/config and the tools use them.
file(RELATIVE_PATH EVADE_INSTALL_BIN_TO_SYSCONF ${EVADE_INSTALL_FULL_BIN} ${EVADE_INSTALL_FULL_SYSCONF})
file(RELATIVE_PATH EVADE_INSTALL_LIBEXEC_TO_SYSCONF ${EVADE_INSTALL_FULL_LIBEXEC} ${EVADE_INSTALL_FULL_SYSCONF})
file(RELATIVE_PATH EVADE_INSTALL_LIBEXEC_TO_DATA ${EVADE_INSTALL_FULL_LIBEXEC} ${EVADE_INSTALL_FULL_DATA})
file(RELATIVE_PATH EVADE_INSTALL_LIBEXEC_TO_JAVA ${EVADE_INSTALL_FULL_LIBEXEC} ${EVADE_INSTALL_FULL_JAVA})
file(RELATIVE_PATH EVADE_INSTALL_BINDIR_TO_LIBEXEC ${CMAKE_INSTALL_FULL_BINDIR} ${EVADE_INSTALL_FULL_LIBEXEC})
