#!/usr/bin/env bash
# The bus closure (tools/bus-firewall) against an attacker on the robot's
# LAN. Two network namespaces joined by a veth pair, created inside the
# namespaces (nothing touches the host's interfaces), under a unique
# prefix, removed on exit:
#   <P>r  the robot: default route over the LAN, LCM on the default URL
#   <P>a  the attacker: publishes the golden log (CMD_VEL among it) with ttl=1
# Phases: open (the premise: an lcm-logger on the robot records the
# attacker's CMD_VEL, and bus-check and a process warn), closed by apply
# (route + nft), route alone, nft alone: the logger records nothing; then
# the LAN allowed as a robot link: the group is routed over it and it works.
#   bus_closure_test.sh BIN_DIR SOURCE_DIR
set -euo pipefail
BIN=$1; SRC=$2
P="evsec$$"
R="${P}r"; A="${P}a"
TMP=$(mktemp -d)
URL='udpm://239.255.76.67:7667?ttl=0&recv_buf_size=8388608'
ATTACK_URL='udpm://239.255.76.67:7667?ttl=1'
LOG="$SRC/logs/paper_sim_crossing/input.lcmlog"
CONFIG="$SRC/config/robot.yaml"
cleanup() {
  ip netns pids "$R" 2> /dev/null | xargs -r kill 2> /dev/null || true
  ip netns pids "$A" 2> /dev/null | xargs -r kill 2> /dev/null || true
  ip netns del "$R" 2> /dev/null || true
  ip netns del "$A" 2> /dev/null || true
  rm -rf "$TMP"
}
trap cleanup EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }

ip netns add "$R"
ip netns add "$A"
ip -n "$R" link add "${P}vr" type veth peer name "${P}va" netns "$A"
ip -n "$R" addr add 10.77.0.1/24 dev "${P}vr"
ip -n "$A" addr add 10.77.0.2/24 dev "${P}va"
for ns in "$R" "$A"; do ip -n "$ns" link set lo up; done
ip -n "$R" link set "${P}vr" up
ip -n "$A" link set "${P}va" up
ip -n "$R" route add default via 10.77.0.2 dev "${P}vr"
ip -n "$A" route add default via 10.77.0.1 dev "${P}va"
in_r() { ip netns exec "$R" env LCM_DEFAULT_URL="$URL" "$@"; }

# Records on the robot while the attacker plays the log's CMD_VEL and the
# robot itself plays its ROUTE; sets n to the number of CMD_VEL recorded
# and fails unless every ROUTE was (a closed bus still works on the host).
attack() {
  local out="$TMP/robot-$1.lcmlog"
  ip netns exec "$R" lcm-logger --lcm-url="$URL" "$out" > /dev/null 2>&1 &
  local logger=$!
  sleep 0.5
  ip netns exec "$A" lcm-logplayer -s 4 -e CMD_VEL --lcm-url="$ATTACK_URL" "$LOG" > /dev/null 2>&1
  ip netns exec "$R" lcm-logplayer -s 4 -e ROUTE --lcm-url="$URL" "$LOG" > /dev/null 2>&1
  sleep 0.5
  kill -INT $logger
  wait $logger 2> /dev/null || true
  n=0
  [ -s "$out" ] && n=$("$BIN/lcmlog-export" "$out" --channel CMD_VEL | wc -l)
  local own
  own=$("$BIN/lcmlog-export" "$out" --channel ROUTE | wc -l)
  [ "$own" -eq "$routes" ] || fail "$1: the robot's own ROUTE: $own of $routes recorded"
  return 0
}
# A process's start-up warning (planner: any live process runs the check);
# sets exposed to its HEALTH counter bus_exposed_interfaces.
planner_warns() {
  local log="$TMP/health-$1.lcmlog"
  ip netns exec "$R" lcm-logger --lcm-url="$URL" "$log" > /dev/null 2>&1 &
  local logger=$!
  sleep 0.3
  in_r timeout 2 "$BIN/planner" --config "$CONFIG" > /dev/null 2> "$TMP/planner-$1.err" || true
  kill -INT $logger
  wait $logger 2> /dev/null || true
  exposed=$("$BIN/lcmlog-export" "$log" --channel HEALTH | grep '"planner"' | head -1 |
            grep -o '"name":"bus_exposed_interfaces","value":[0-9]*' | grep -o '[0-9]*$' || true)
  grep -q "warning: the LCM bus" "$TMP/planner-$1.err"
}
# base_driver runs on the robot (no serial device) while the attacker plays
# the log's CMD_VEL; sets refused to its HEALTH counter auth_outside_window.
replay_refused() {
  local log="$TMP/health-auth.lcmlog"
  ip netns exec "$R" lcm-logger --lcm-url="$URL" "$log" > /dev/null 2>&1 &
  local logger=$!
  ip netns exec "$R" env LCM_DEFAULT_URL="$URL" "$BIN/base_driver" --config "$LINK_CONFIG" \
    --device "$TMP/no-such-device" > /dev/null 2> "$TMP/base_driver.err" &
  local driver=$!
  sleep 0.7
  ip netns exec "$A" lcm-logplayer -s 4 -e CMD_VEL --lcm-url="$ATTACK_URL" "$LOG" > /dev/null 2>&1
  sleep 1.5  # a heartbeat after the last of them
  kill -TERM $driver
  wait $driver 2> /dev/null || true
  kill -INT $logger
  wait $logger 2> /dev/null || true
  refused=$("$BIN/lcmlog-export" "$log" --channel HEALTH | grep '"base_driver"' | tail -1 |
            grep -o '"name":"auth_outside_window","value":[0-9]*' | grep -o '[0-9]*$' || echo 0)
}
sent=$("$BIN/lcmlog-export" "$LOG" --channel CMD_VEL | wc -l)
routes=$("$BIN/lcmlog-export" "$LOG" --channel ROUTE | wc -l)
[ "$sent" -gt 0 ] && [ "$routes" -gt 0 ] || fail "the golden log needs CMD_VEL and ROUTE"

# 1. Open: the premise.
attack open
echo "open: robot recorded $n of $sent attacker CMD_VEL"
[ "$n" -gt 0 ] || fail "premise: without the closure the attacker's CMD_VEL should arrive"
in_r "$BIN/bus-check" --config "$CONFIG" && fail "bus-check says closed on an open bus"
planner_warns open || fail "planner did not warn on an open bus: $(cat "$TMP/planner-open.err")"
[ "$exposed" = 1 ] || fail "planner's HEALTH bus_exposed_interfaces: '$exposed', expected 1"

# 2. Closed: route and nft.
in_r env EVADE_BUS_CHECK="$BIN/bus-check" "$SRC/tools/bus-firewall" apply --config "$CONFIG"
attack closed
echo "closed (route + nft): robot recorded $n"
[ "$n" -eq 0 ] || fail "closed bus: $n attacker CMD_VEL arrived"
in_r "$BIN/bus-check" --config "$CONFIG" > /dev/null || fail "bus-check says exposed on a closed bus"
planner_warns closed && fail "planner warned on a closed bus: $(cat "$TMP/planner-closed.err")"
[ "$exposed" = 0 ] || fail "planner's HEALTH bus_exposed_interfaces on a closed bus: '$exposed', expected 0"

# 3. The route alone.
ip netns exec "$R" nft delete table inet evade_bus
attack route-only
echo "route only: robot recorded $n"
[ "$n" -eq 0 ] || fail "route only: $n attacker CMD_VEL arrived"

# 4. The firewall alone (the group routed over the LAN again).
in_r env EVADE_BUS_CHECK="$BIN/bus-check" "$SRC/tools/bus-firewall" apply --config "$CONFIG" > /dev/null
ip -n "$R" route del 239.255.76.67/32 dev lo
in_r "$BIN/bus-check" --config "$CONFIG" > /dev/null && fail "bus-check should see the route over the LAN"
attack nft-only
echo "nft only: robot recorded $n"
[ "$n" -eq 0 ] || fail "nft only: $n attacker CMD_VEL arrived"

# 5. Two hosts: the LAN is the robot link (allowed). apply routes the group
# over it, the bus is closed by the rule and the link works: a host on the
# link reaches the robot, which only authentication could stop.
LINK_CONFIG="$TMP/link.yaml"
sed "s/^  allowed_interfaces: \[lo\]/  allowed_interfaces: [lo, ${P}vr]/" "$CONFIG" > "$LINK_CONFIG"
grep -q "allowed_interfaces: \[lo, ${P}vr\]" "$LINK_CONFIG" || fail "test setup: bus.allowed_interfaces not found"
ip netns exec "$R" nft delete table inet evade_bus
in_r env EVADE_BUS_CHECK="$BIN/bus-check" "$SRC/tools/bus-firewall" apply --config "$LINK_CONFIG"
[ -n "$(ip -n "$R" route show 239.255.76.67/32 dev "${P}vr")" ] || fail "the group is not routed over the robot link"
attack robot-link
echo "robot link allowed: robot recorded $n of $sent (the link is trusted)"
[ "$n" -eq "$sent" ] || fail "robot link: $n of $sent arrived"
# ... and authentication stops it (issue 20): the attacker's CMD_VEL are
# genuine, signed messages recorded earlier, and base_driver refuses every
# one as outside its time window (HEALTH counter auth_outside_window).
replay_refused
echo "robot link allowed: base_driver refused $refused of $sent replayed CMD_VEL"
[ "$refused" -eq "$sent" ] || fail "base_driver refused $refused of $sent replayed CMD_VEL: $(cat "$TMP/base_driver.err")"
in_r env EVADE_BUS_CHECK="$BIN/bus-check" "$SRC/tools/bus-firewall" remove --config "$LINK_CONFIG" > /dev/null
[ -z "$(ip -n "$R" route show 239.255.76.67/32)" ] || fail "remove left the route"

# remove leaves the namespace as it was
in_r env EVADE_BUS_CHECK="$BIN/bus-check" "$SRC/tools/bus-firewall" remove --config "$CONFIG"
ip netns exec "$R" nft list table inet evade_bus > /dev/null 2>&1 && fail "remove left the nft table"
echo "PASS"
