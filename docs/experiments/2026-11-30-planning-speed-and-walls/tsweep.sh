#!/bin/bash
# tsweep.sh TREE SCENE OUT [robot-edit]: the scene in lockstep at several per-iteration costs
T=$1; S=$2; O=$3; mkdir -p $O
for c in 0.000060 0.000070 0.000080 0.000090 0.000099 0.000110 0.000120 0.000135 0.000150; do
  d=$O/c$c; mkdir -p $d/cfg; cp -r $T/config/robots $d/cfg/ 2>/dev/null
  sed -e "s/footprint_length_m: 0.42/footprint_length_m: 0.93/" -e "s/footprint_width_m: 0.31/footprint_width_m: 0.70/" \
      -e "s/planner_per_iteration_s: 0.000099/planner_per_iteration_s: $c/" $T/config/robot.yaml > $d/cfg/robot.yaml
  (cd $T && tools/run_scenario $S --out $d/run --lockstep --config $d/cfg/robot.yaml --quiet --no-reaction --force >/dev/null 2>&1)
  python3 -c "
import json;m=json.load(open('$d/run/metrics.json'))
print('$c', 'goal' if m['reached_goal'] else 'nogoal', 'atfault' if m['at_fault'] else '-', 'contacts', len(m['contacts']), 'min %.3f'%m['min_dist_m'])"
  rm -f $d/run/run.lcmlog
done
