# Sourced by the tools (not a tool itself): where they find evade's parts.
#   ROOT        the working tree, or <libexecdir>/evade when installed
#   BIN         the programs (ROOT/build/bin; installed: <libexecdir>/evade/bin)
#   JAVA_DIR    evade_lcmtypes.jar, evade_tools.jar (installed: <datadir>/java)
#   CONFIG_DIR  robot.yaml, scenario_families.yaml (installed: <sysconfdir>/evade)
#   SCENARIO_DIR the shipped scenarios (installed: <datadir>/evade/scenarios)
# `cmake --install` writes tools/installed-layout.sh beside the installed
# copy (cmake/Install.cmake), which sets the installed values.
ROOT=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
BIN="$ROOT/build/bin"
JAVA_DIR="$ROOT/build/share/java"
CONFIG_DIR="$ROOT/config"
SCENARIO_DIR="$ROOT/config/scenarios"
if [ -f "$ROOT/tools/installed-layout.sh" ]; then
  . "$ROOT/tools/installed-layout.sh"
fi
