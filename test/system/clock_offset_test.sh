#!/usr/bin/env bash
# ClockOffset.AnInjectedOffsetBetweenTwoHostsMovesThePlannersCounter (root)
#   clock_offset_test.sh SOURCE_DIR
# Two hosts (tools/netns-pair): the predictor on A answers CLOCK_SYNC, the
# planner on B asks. With the planner's clock set 200 ms ahead by
# libfaketime (Debian's faketime), its HEALTH reports the predictor's
# offset as -200 ms within 5 ms, it warns once and its counter
# clock_offset_exceeded counts every answer; with the same clock on both,
# the offset is within 5 ms of zero and nothing is counted.
set -euo pipefail
SRC=$(realpath "$1")
BIN="$SRC/build/bin"
command -v faketime > /dev/null || { echo "FAIL: faketime is not installed (bash tools/setup build)" >&2; exit 1; }
T=$(mktemp -d /tmp/evade-clock-offset.XXXXXX)
A="evclk$$a"; B="evclk$$b"
cleanup() { "$SRC/tools/netns-pair" down "$A" "$B"; rm -rf "$T"; }
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
"$SRC/tools/netns-pair" up "$A" "$B"
URL='udpm://239.255.76.67:7667?ttl=1&recv_buf_size=8388608'
CFG="$T/robot.yaml"
sed "s/^  allowed_interfaces: \[lo\]/  allowed_interfaces: [lo, evbus0]/" "$SRC/config/robot.yaml" > "$CFG"

# One exchange of the given length with the planner's clock offset by
# $1 (a faketime offset, "" none); sets health to the planner's last HEALTH.
exchange() {
  local log="$T/run$2.lcmlog" pids=()
  ip netns exec "$A" lcm-logger --lcm-url="$URL" --quiet "$log" > /dev/null 2>&1 &
  pids+=($!)
  ip netns exec "$A" "$BIN/predictor" --config "$CFG" --lcm-url "$URL" > "$T/predictor$2.err" 2>&1 &
  pids+=($!)
  if [ -n "$1" ]; then
    ip netns exec "$B" faketime -m -f "$1" "$BIN/planner" --config "$CFG" --lcm-url "$URL" > "$T/planner$2.err" 2>&1 &
  else
    ip netns exec "$B" "$BIN/planner" --config "$CFG" --lcm-url "$URL" > "$T/planner$2.err" 2>&1 &
  fi
  pids+=($!)
  sleep 6
  # Everything in the two hosts (faketime runs the planner as its child).
  { ip netns pids "$A"; ip netns pids "$B"; } | xargs -r kill -TERM
  wait "${pids[@]}" 2> /dev/null || true
  health=$("$BIN/lcmlog-export" "$log" --channel HEALTH | grep '"name":"planner"' | tail -1)
  [ -n "$health" ] || fail "no HEALTH from the planner: $(cat "$T/planner$2.err")"
}
counter() { echo "$health" | grep -o "\"name\":\"$1\",\"value\":-\?[0-9]*" | grep -o -- '-\?[0-9]*$'; }

exchange "+0.2s" ahead
offset=$(counter clock_offset_us) || fail "no clock_offset_us: $health"
exceeded=$(counter clock_offset_exceeded)
echo "planner 200 ms ahead: clock_offset_us $offset, clock_rtt_us $(counter clock_rtt_us), clock_offset_exceeded $exceeded"
[ "$offset" -gt -205000 ] && [ "$offset" -lt -195000 ] || fail "offset $offset us, expected -200000 +- 5000"
[ "$exceeded" -ge 3 ] || fail "clock_offset_exceeded $exceeded after 6 s at 1 Hz"
[ "$(grep -cE "warning: clock offset to predictor is -(19[5-9]|20[0-4])\.[0-9] ms" "$T/plannerahead.err")" = 1 ] ||
  fail "the planner did not warn once: $(cat "$T/plannerahead.err")"

exchange "" same
offset=$(counter clock_offset_us) || fail "no clock_offset_us: $health"
exceeded=$(counter clock_offset_exceeded)
echo "one clock: clock_offset_us $offset, clock_rtt_us $(counter clock_rtt_us), clock_offset_exceeded $exceeded"
[ "${offset#-}" -lt 5000 ] || fail "offset $offset us on one clock"
[ "$exceeded" = 0 ] || fail "clock_offset_exceeded $exceeded on one clock"
! grep -q "warning: clock offset" "$T/plannersame.err" || fail "a warning on one clock"
echo PASS
