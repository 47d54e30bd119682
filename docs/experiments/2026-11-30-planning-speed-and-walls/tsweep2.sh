#!/bin/bash
# tsweep2.sh TREE OUT SCENE...: scenes (default robot) in lockstep at several per-iteration costs
T=$1; O=$2; shift 2; mkdir -p $O
for S in "$@"; do
 n=$(basename $S .yaml)
 for c in 0.000060 0.000080 0.000099 0.000120 0.000150; do
  d=$O/$n/c$c; mkdir -p $d/cfg; cp -r $T/config/robots $d/cfg/ 2>/dev/null
  sed -e "s/planner_per_iteration_s: 0.000099/planner_per_iteration_s: $c/" $T/config/robot.yaml > $d/cfg/robot.yaml
  (cd $T && tools/run_scenario $S --out $d/run --lockstep --config $d/cfg/robot.yaml --quiet --no-reaction --force >/dev/null 2>&1)
  python3 -c "
import json;m=json.load(open('$d/run/metrics.json'))
print('$n $c', 'goal' if m['reached_goal'] else 'nogoal', 'atfault' if m['at_fault'] else '-', 'contacts', len(m['contacts']), 'min %.3f'%m['min_dist_m'], 't', m.get('time_to_goal_s'))"
  rm -f $d/run/run.lcmlog
 done
done
