#!/usr/bin/env bash
# Launch.ProcessesPlacedOnAnotherHostRunOverSsh (run inside tools/netns-run)
#   launch_hosts_test.sh SOURCE_DIR
# tools/launch with a layout file and --host flags: the placed windows'
# commands go through ssh (test/benchmark/fake_ssh stands in for it), the
# configuration is copied to the other host first, bad layouts are refused
# with the file and line, and a real launch in a private tmux server brings
# up every process, the remote ones through fake ssh, all heard on HEALTH.
set -euo pipefail
SRC=$(realpath "$1")
[ "${EVADE_IN_NETNS:-}" = 1 ] || { echo "run me through tools/netns-run" >&2; exit 2; }
T=$(mktemp -d /tmp/evade-launch-test.XXXXXX)
export FAKE_SSH_ROOT="$T/ssh" EVADE_SSH="$SRC/test/benchmark/fake_ssh" TMUX_TMPDIR="$T/tmux"
mkdir -p "$FAKE_SSH_ROOT" "$TMUX_TMPDIR"
# Each window's job (its own process group, the fake ssh's children in it)
# gets SIGTERM, then the private tmux server goes.
cleanup() {
  local p g
  for p in $(tmux list-panes -a -F '#{pane_pid}' 2>/dev/null); do
    for g in $(ps -o pgid= --ppid "$p" | sort -u); do kill -TERM -- "-$g" 2>/dev/null || true; done
  done
  sleep 1
  tmux kill-server 2>/dev/null || true
  rm -rf "$T"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
L="$SRC/tools/launch"

printf '# perception on the first NUC, planning on the second\nplanner nuc2\n\npredictor   nuc2\n' > "$T/layout"
"$L" --hosts "$T/layout" --host tracker=nuc2 --host predictor=local --log "$T/dry" --dry-run > "$T/dry.out"
run=$(ls -d "$T"/dry/*/ | head -1); run=${run%/}
grep -q "^planner:$EVADE_SSH -t nuc2 -- " "$run/launch.txt" || fail "planner not sent to nuc2: $(cat "$run/launch.txt")"
grep -q "^tracker:$EVADE_SSH -t nuc2 -- " "$run/launch.txt" || fail "--host tracker=nuc2 ignored"
grep -q "^predictor:$SRC/build/bin/predictor " "$run/launch.txt" || fail "--host predictor=local does not override the file"
grep -q "^map:$SRC/build/bin/elevation_map " "$run/launch.txt" || fail "an unplaced window left this host"
echo "ok: dry run places planner and tracker on nuc2, the rest here"

printf 'planner\n' > "$T/bad1"; printf 'navigator nuc2\n' > "$T/bad2"
set +e
"$L" --hosts "$T/bad1" --log "$T/dry" --dry-run > "$T/bad1.out" 2>&1; s1=$?
"$L" --hosts "$T/bad2" --log "$T/dry" --dry-run > "$T/bad2.out" 2>&1; s2=$?
"$L" --host planner --log "$T/dry" --dry-run > "$T/bad3.out" 2>&1; s3=$?
set -e
[ $s1 = 2 ] && grep -q "$T/bad1:1: expected 'NAME HOST'" "$T/bad1.out" || fail "a line without a host: $s1 $(cat "$T/bad1.out")"
[ $s2 = 2 ] && grep -q "unknown window 'navigator'" "$T/bad2.out" || fail "an unknown window: $s2 $(cat "$T/bad2.out")"
[ $s3 = 2 ] || fail "--host without =HOST accepted"
echo "ok: bad layouts refused"

# The real thing: a private tmux server in this network namespace.
"$L" --hosts "$T/layout" --log "$T/live" --session evtest > "$T/live.out" 2>&1 || fail "launch: $(cat "$T/live.out")"
run=$(ls -d "$T"/live/*/ | head -1); run=${run%/}
grep -q "cat > $run/robot.yaml.part" "$FAKE_SSH_ROOT/nuc2.commands" || fail "robot.yaml not copied to nuc2: $(cat "$FAKE_SSH_ROOT/nuc2.commands")"
heard=1
for i in $(seq 1 20); do
  if "$SRC/build/bin/health" --once --expect route,lidar_driver,base_driver,elevation_map,tracker,predictor,planner \
       --config "$run/robot.yaml" > "$T/health.out" 2>&1; then heard=0; break; fi
  sleep 1
done
[ $heard = 0 ] || fail "not every process heard on HEALTH: $(cat "$T/health.out")"
grep -q "build/bin/planner" "$FAKE_SSH_ROOT/nuc2.commands" || fail "the planner did not run through ssh"
grep -q "build/bin/predictor" "$FAKE_SSH_ROOT/nuc2.commands" || fail "the predictor did not run through ssh"
! grep -q "build/bin/tracker" "$FAKE_SSH_ROOT/nuc2.commands" || fail "the tracker ran through ssh"
echo "ok: live launch: every process on HEALTH, planner and predictor through ssh on nuc2"
echo PASS
