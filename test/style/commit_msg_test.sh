#!/usr/bin/env bash
# tools/githooks/commit-msg accepts a 72-character subject with a body and
# rejects a 73-character subject, an empty one and a body with no blank
# line before it.
set -euo pipefail
hook="$1/tools/githooks/commit-msg"
dir=$(mktemp -d)
trap 'rm -rf "$dir"' EXIT
fails=0
expect() {  # expect accept|reject NAME < message
  local want=$1 name=$2 got
  cat > "$dir/msg"
  if bash "$hook" "$dir/msg" 2>"$dir/err"; then got=accept; else got=reject; fi
  if [ "$got" != "$want" ]; then
    echo "FAIL $name: expected $want, got $got ($(cat "$dir/err"))"
    fails=$((fails + 1))
  else
    echo "ok   $name"
  fi
}
s72=$(printf 'a%.0s' $(seq 72))
s73=$(printf 'a%.0s' $(seq 73))
printf '%s\n\nWhy it is so.\n# a comment line git strips\n' "$s72" | expect accept subject-of-72
printf '%s\n\nWhy.\n' "$s73" | expect reject subject-of-73
printf '# only comments\n\n' | expect reject empty-subject
printf 'short subject\nbody with no blank line\n' | expect reject no-blank-line
printf '# git template line first\nshort subject\n' | expect accept comment-before-subject
exit $fails
