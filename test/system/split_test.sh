#!/usr/bin/env bash
# Split.PaperSimOnTwoHostsReachesTheGoal (root; issue 19)
#   split_test.sh SOURCE_DIR OUT_DIR
# tools/run_scenario --split runs paper_sim on two network namespaces
# joined by a veth pair: it must reach the goal without contact at fault,
# with perception on host A and planner and base_driver on host B, the
# planner's commands and plans crossing the link to the logger on A, the
# planner planning from A's predictions, no process finding its bus
# exposed, the planner holding the route before the scene's clock starts
# (no PLAN after the first SIM_TRUTH says NO_ROUTE), the hosts' clock offset in the planner's HEALTH (one machine:
# near zero), and both namespaces gone afterwards.
set -euo pipefail
SRC=$(realpath "$1"); OUT=$2
BIN="$SRC/build/bin"
fail() { echo "FAIL: $*" >&2; exit 1; }
rm -rf "$OUT"
mkdir -p "$OUT"
status=0
timeout 100 "$SRC/tools/run_scenario" "$SRC/config/scenarios/paper_sim.yaml" --out "$OUT" --split --no-reaction --quiet \
  > "$OUT.log" 2>&1 || status=$?
cat "$OUT/metrics.json" 2> /dev/null || true
# Where the robot was and what the planner said, every 2 s of the scene
# (a failed run can be read from the test's output alone).
timeline() {
  "$BIN/lcmlog-export" "$OUT/run.lcmlog" --channel SIM_TRUTH --channel PLAN 2> /dev/null | awk '
    function num(key,   m) { return match($0, "\"" key "\":-?[0-9.e+-]+") ? substr($0, RSTART + length(key) + 3, RLENGTH - length(key) - 3) : "?" }
    /"channel":"PLAN"/ { status = num("status"); v0 = $0; sub(/.*"v":\[/, "", v0); sub(/[],].*/, "", v0); next }
    /"channel":"SIM_TRUTH"/ { t = num("utime"); if (t0 == "") t0 = t
      if ((t - t0) / 1e6 >= next_s) { printf "t %5.1f s  robot x %6.2f y %5.2f yaw %5.2f v %4.2f  plan status %s v0 %.2f\n", (t - t0) / 1e6, num("x"), num("y"), num("yaw"), num("v"), status, v0 + 0; next_s += 2 } }'
}
[ $status = 0 ] || { timeline; fail "run_scenario --split exit $status: $(tail -20 "$OUT.log")"; }
grep -q '"reached_goal": true' "$OUT/metrics.json" || { timeline; fail "goal not reached"; }
grep -q '"at_fault": false' "$OUT/metrics.json" || fail "a collision at fault"

# What ran where.
hosts="$OUT/logs/hosts.txt"
ns_of() { awk -v p="$1" '$1 == p { print $2 }' "$hosts"; }
A=$(ns_of predictor); B=$(ns_of planner)
[ -n "$A" ] && [ -n "$B" ] && [ "$A" != "$B" ] || fail "predictor and planner not on two hosts: $(cat "$hosts")"
for p in sim lidar_driver elevation_map tracker predictor logger; do
  [ "$(ns_of $p)" = "$A" ] || fail "$p not on host A: $(cat "$hosts")"
done
for p in planner base_driver route; do
  [ "$(ns_of $p)" = "$B" ] || fail "$p not on host B: $(cat "$hosts")"
done
echo "ok: perception on $A, planner and base_driver on $B"

# Across the link: the logger (A) heard B's signed commands and plans, and
# the planner (B) planned from A's predictions.
cmds=$("$BIN/lcmlog-export" "$OUT/run.lcmlog" --channel CMD_VEL | grep -c '"auth_sender":"planner"' || true)
plans=$("$BIN/lcmlog-export" "$OUT/run.lcmlog" --channel PLAN | wc -l)
from_predictions=$("$BIN/lcmlog-export" "$OUT/run.lcmlog" --channel PLAN | grep -vc '"predictions_utime":-1' || true)
echo "logger on A: $cmds CMD_VEL signed by the planner, $plans PLAN, $from_predictions from A's predictions"
[ "$cmds" -gt 100 ] || fail "only $cmds CMD_VEL from the planner crossed the link"
[ "$from_predictions" -gt 100 ] || fail "only $from_predictions plans made from predictions"
! grep -l "warning: the LCM bus" "$OUT"/logs/*.log || fail "a process found its bus exposed"

# The simulator starts once the planner has the route (run_scenario waits
# on the planner's HEALTH), as every core has it at t = 0 in lockstep.
no_route=$("$BIN/lcmlog-export" "$OUT/run.lcmlog" --channel SIM_TRUTH --channel PLAN |
  awk '/"channel":"SIM_TRUTH"/ { sim = 1 } sim && /"channel":"PLAN"/ && /"status":4,/ { n++ } END { print n + 0 }')
echo "plans saying NO_ROUTE after the simulator started: $no_route"
[ "$no_route" = 0 ] || fail "$no_route plans without a route after the scene began"

# The clock offset between the hosts (one machine: one clock).
health=$("$BIN/lcmlog-export" "$OUT/run.lcmlog" --channel HEALTH | grep '"name":"planner"' | tail -1)
counter() { echo "$health" | grep -o "\"name\":\"$1\",\"value\":-\?[0-9]*" | grep -o -- '-\?[0-9]*$'; }
offset=$(counter clock_offset_us) || fail "no clock_offset_us in the planner's HEALTH: $health"
rtt=$(counter clock_rtt_us) || fail "no clock_rtt_us in the planner's HEALTH"
exceeded=$(counter clock_offset_exceeded) || fail "no clock_offset_exceeded in the planner's HEALTH"
echo "planner's HEALTH: clock_offset_us $offset, clock_rtt_us $rtt, clock_offset_exceeded $exceeded"
[ "${offset#-}" -lt 5000 ] || fail "clock offset $offset us between two namespaces of one machine"
[ "$rtt" -gt 0 ] && [ "$rtt" -lt 100000 ] || fail "round trip $rtt us"
[ "$exceeded" = 0 ] || fail "the offset bound was exceeded $exceeded times on one clock"

ip netns list | grep -q "^$A\b\|^$B\b" && fail "namespaces left behind: $(ip netns list)"
echo PASS
