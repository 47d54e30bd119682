#!/usr/bin/env bash
# Install.UnitsNameInstalledFilesAndProcessesFindTheInstalledConfig
#   install_test.sh BUILD_DIR
# Installs the build into a scratch DESTDIR and checks, from there:
#  - evade.target wants one evade@NAME.service per robot process, and every
#    unit it names exists;
#  - every unit's ExecStart names an installed executable, and every file it
#    names (--config, EnvironmentFile) is installed;
#  - an installed program, started from an empty folder with nothing but
#    the install, finds the installed configuration (a scenario drawn from
#    the installed robot.yaml and scenario_families.yaml; a broken installed
#    robot.yaml stops a process with that file's name);
#  - the installed tools find the installed programs and configuration
#    (`evade` dispatcher, tools/launch --dry-run).
set -euo pipefail
BUILD=$(realpath "$1")
S=$(mktemp -d /tmp/evade-install-test.XXXXXX)
trap 'rm -rf "$S"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

DESTDIR="$S/root" cmake --install "$BUILD" > "$S/install.log" || { cat "$S/install.log"; fail "cmake --install"; }
R="$S/root"
target=$(find "$R" -name evade.target -path '*systemd/system*' | head -1)
[ -n "$target" ] || fail "no evade.target installed"
UNITS=$(dirname "$target")
echo "units in ${UNITS#$R}"

# The value of KEY= in a unit (first occurrence).
value() { sed -n "s/^$2=//p" "$1" | head -1; }
# ExecStart, EnvironmentFile and every absolute path of a unit must exist under $R.
check_unit() {
  local file=$1 inst=$2 exec env word
  exec=$(value "$file" ExecStart | sed "s/%i/$inst/g")
  [ -n "$exec" ] || fail "$(basename "$file") has no ExecStart"
  word=${exec%% *}
  [ -f "$R$word" ] && [ -x "$R$word" ] || fail "$(basename "$file")${inst:+ ($inst)}: ExecStart names $word, not an installed executable"
  for word in $exec; do
    case "$word" in
      /*) [ -e "$R$word" ] || fail "$(basename "$file")${inst:+ ($inst)}: ExecStart names $word, not installed" ;;
    esac
  done
  env=$(value "$file" EnvironmentFile)
  if [ -n "$env" ]; then [ -f "$R$env" ] || fail "$(basename "$file"): EnvironmentFile $env not installed"; fi
  grep -q '^Restart=on-failure' "$file" || [ "$(value "$file" Type)" = oneshot ] ||
    fail "$(basename "$file") has no Restart=on-failure"
  echo "ok: $(basename "$file")${inst:+ as $inst}: $exec"
}

wants=$(value "$target" Wants)
[ -n "$wants" ] || fail "evade.target wants nothing"
n=0
for u in $wants $(value "$target" Requires); do
  case "$u" in
    evade@*.service)
      inst=${u#evade@}; inst=${inst%.service}
      [ -f "$UNITS/evade@.service" ] || fail "evade@.service not installed"
      check_unit "$UNITS/evade@.service" "$inst"; n=$((n + 1)) ;;
    *)
      [ -f "$UNITS/$u" ] || fail "evade.target names $u, not installed"
      check_unit "$UNITS/$u" "" ;;
  esac
done
[ "$n" -ge 7 ] || fail "evade.target starts $n processes, expected the 7 of the robot"
grep -q 'LCM_DEFAULT_URL=' "$R$(value "$UNITS/evade@.service" EnvironmentFile)" || fail "evade.env has no LCM_DEFAULT_URL"
grep -q '^Requires=evade-bus.service' "$UNITS/evade@.service" || fail "processes do not require the bus closure"

# An installed program started from an empty folder finds the installed configuration.
BIN=$(dirname "$(find "$R" -path '*/evade/bin/scenario-gen' | head -1)")
[ -x "$BIN/scenario-gen" ] || fail "scenario-gen not installed"
CONF=$(dirname "$(find "$R" -path '*/evade/robot.yaml' | head -1)")
[ -f "$CONF/robot.yaml" ] || fail "robot.yaml not installed"
mkdir "$S/empty" && cd "$S/empty"
env -u EVADE_CONFIG "$BIN/scenario-gen" --family crossing --seed 1 > "$S/scene.yaml" || fail "installed scenario-gen did not find its configuration"
grep -q '^name: crossing_1' "$S/scene.yaml" || fail "installed scenario-gen wrote no scenario"
echo "ok: installed scenario-gen, run from an empty folder, drew crossing_1 from ${CONF#$R}"
cp "$CONF/robot.yaml" "$S/robot.yaml.good"
echo "bogus_section: 1" >> "$CONF/robot.yaml"
set +e
env -u EVADE_CONFIG "$BIN/route" > "$S/route.out" 2>&1; status=$?
set -e
[ "$status" -eq 2 ] || fail "route with a broken installed robot.yaml exited $status, not 2: $(cat "$S/route.out")"
grep -q "$CONF/robot.yaml:.*bogus_section" "$S/route.out" || fail "route's error does not name the installed robot.yaml: $(cat "$S/route.out")"
echo "ok: installed route reads ${CONF#$R}/robot.yaml: $(cat "$S/route.out")"
cp "$S/robot.yaml.good" "$CONF/robot.yaml"

# The installed scenarios name robot profiles; the installed ones beside
# robot.yaml resolve them (paper_sim: jackal), --robot names them too.
SCEN=$(dirname "$(find "$R" -path '*/evade/scenarios/paper_sim.yaml' | head -1)")
set +e
env -u EVADE_CONFIG "$BIN/planner" --scenario "$SCEN/paper_sim.yaml" --replay /dev/null > "$S/planner.out" 2>&1
env -u EVADE_CONFIG "$BIN/tracker" --robot scout2 --replay /dev/null > "$S/tracker.out" 2>&1
set -e
grep -q "^planner: footprint 0.46 x 0.42 m, profile jackal, source $CONF/robots/jackal.yaml:" "$S/planner.out" ||
  fail "installed planner did not take paper_sim's profile from ${CONF#$R}/robots: $(cat "$S/planner.out")"
grep -q "^tracker: footprint 0.93 x 0.7 m, profile scout2, source $CONF/robots/scout2.yaml:" "$S/tracker.out" ||
  fail "installed tracker --robot scout2: $(cat "$S/tracker.out")"
echo "ok: installed profiles: $(head -1 "$S/planner.out")"

# The installed tools find the installed programs and configuration.
EVADE=$(find "$R" -path '*/bin/evade' -type f | head -1)
[ -x "$EVADE" ] || fail "the evade dispatcher is not installed"
"$EVADE" scenario-info --help > /dev/null || fail "evade scenario-info --help"
"$EVADE" --help > "$S/evade-help.out" && grep -q " goto " "$S/evade-help.out" || fail "evade --help lists no goto"
env -u EVADE_LOG_DIR "$EVADE" launch --dry-run --log "$S/logs" > "$S/launch.out" || fail "installed launch --dry-run: $(cat "$S/launch.out")"
grep -q "^planner:$BIN/planner --config " "$S/launch.out" || fail "installed launch does not start the installed planner: $(cat "$S/launch.out")"
run=$(ls -d "$S"/logs/*/ | head -1); run=${run%/}
cmp -s "$run/robot.yaml" "$CONF/robot.yaml" || fail "installed launch did not record the installed robot.yaml"
echo "ok: installed launch starts $BIN/* with ${CONF#$R}/robot.yaml"
echo "PASS"
