#!/bin/bash
# scenes.sh ROOT OUT [CFG]: every scene of ROOT/config/scenarios (and long/), lockstep, one line each
ROOT=$1; OUT=$2; CFG=${3:-$ROOT/config/robot.yaml}
mkdir -p $OUT
for s in $ROOT/config/scenarios/*.yaml $ROOT/config/scenarios/long/*.yaml; do
  n=$(basename $s .yaml)
  $ROOT/tools/run_scenario $s --out $OUT/$n --lockstep --config $CFG --quiet --no-reaction --force > $OUT/$n.log 2>&1
  python3 - "$OUT/$n/metrics.json" "$n" <<'PY'
import json,sys
m=json.load(open(sys.argv[1]))
g=lambda k: m.get(k)
print(sys.argv[2], "arrived" if g("reached_goal") else "NOT", "at_fault" if g("at_fault") or (g("collisions_at_fault") or 0)>0 else "-", "contact" if g("collided") else "-", "timeout" if g("timed_out") else "-", round(g("min_dist_m") or -9,2), g("time_to_goal_s"))
PY
  rm -f $OUT/$n/run.lcmlog
done
