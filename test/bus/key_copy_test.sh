#!/usr/bin/env bash
# KeyCopy.TheBusKeyReachesTheSecondHostOwnerOnly (issue 20)
#   key_copy_test.sh SOURCE_DIR
# `bash tools/setup key --copy-to HOST` over the stand-in for ssh that
# BenchmarkTool.TwoHostsOverSsh uses (test/benchmark/fake_ssh: each host a
# home folder of its own): the key arrives with mode 0600 in a 0700 folder
# and the same content; a second copy changes nothing; a different key
# there is kept without --force and replaced with it; a copy readable by
# others is made owner-only; a host that cannot be reached and bad
# arguments fail with a reason.
set -euo pipefail
SRC=$(realpath "$1")
T=$(mktemp -d /tmp/evade-keycopy.XXXXXX)
trap 'rm -rf "$T"' EXIT
fail() { echo "FAIL: $*" >&2; exit 1; }
unset EVADE_BUS_KEY  # the configured ~/.config/evade/bus.key, in this test's homes
export HOME="$T/here" FAKE_SSH_ROOT="$T/hosts" EVADE_SSH="$SRC/test/benchmark/fake_ssh"
mkdir -p "$HOME" "$FAKE_SSH_ROOT"
setup() { bash "$SRC/tools/setup" key "$@"; }
mine="$HOME/.config/evade/bus.key"
there="$FAKE_SSH_ROOT/nuc2/.config/evade/bus.key"

setup --copy-to nuc2 > "$T/out" 2>&1 || fail "copy: $(cat "$T/out")"
[ -f "$mine" ] || fail "no key made here"
[ "$(stat -c %a "$there")" = 600 ] || fail "mode $(stat -c %a "$there") on nuc2"
[ "$(stat -c %a "$(dirname "$there")")" = 700 ] || fail "folder mode $(stat -c %a "$(dirname "$there")")"
cmp -s "$mine" "$there" || fail "the copy differs"
grep -q "copied to nuc2:$there (mode 0600" "$T/out" || fail "output: $(cat "$T/out")"
[ -z "$(ls "$(dirname "$there")" | grep -v '^bus.key$')" ] || fail "left over: $(ls "$(dirname "$there")")"
echo "ok: copied, mode 0600, same content"

setup --copy-to nuc2 > "$T/out" 2>&1 || fail "a second copy of the same key: $(cat "$T/out")"
cmp -s "$mine" "$there" || fail "the second copy changed the key"

# Another robot's key on nuc2: kept, unless --force.
other=$(od -An -tx1 -N32 /dev/urandom | tr -d ' \n')
(umask 077 && echo "$other" > "$there")
status=0
setup --copy-to nuc2 > "$T/out" 2>&1 || status=$?
[ $status = 1 ] || fail "a different key was replaced without --force (exit $status)"
grep -q "holds a different key; not replaced" "$T/out" || fail "no reason given: $(cat "$T/out")"
[ "$(cat "$there")" = "$other" ] || fail "the other key was changed"
setup --copy-to nuc2 --force > "$T/out" 2>&1 || fail "--force: $(cat "$T/out")"
cmp -s "$mine" "$there" || fail "--force did not replace the key"
[ "$(stat -c %a "$there")" = 600 ] || fail "mode after --force: $(stat -c %a "$there")"
echo "ok: a different key refused without --force, replaced with it"

chmod 644 "$there"
setup --copy-to nuc2 > "$T/out" 2>&1 || fail "copy over a readable copy: $(cat "$T/out")"
[ "$(stat -c %a "$there")" = 600 ] || fail "a readable copy stayed $(stat -c %a "$there")"
echo "ok: a copy readable by others made owner-only"

status=0
EVADE_SSH=false setup --copy-to nuc3 > "$T/out" 2>&1 || status=$?
[ $status = 1 ] && grep -q "could not copy the bus key to nuc3" "$T/out" || fail "unreachable host: $status $(cat "$T/out")"
for args in "--force" "--copy-to" "--copy-to -oProxyCommand=x" "--bogus"; do
  status=0
  # shellcheck disable=SC2086
  setup $args > "$T/out" 2>&1 || status=$?
  [ $status = 2 ] || fail "'key $args' exit $status: $(cat "$T/out")"
done
[ ! -e "$FAKE_SSH_ROOT/nuc3" ] || fail "nuc3 was reached"
echo "ok: unreachable host and bad arguments refused"
echo PASS
