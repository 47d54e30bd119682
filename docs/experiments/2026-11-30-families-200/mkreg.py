#!/usr/bin/env python3
# mkreg.py OUTDIR GEN RESULTS.jsonl...: every failed episode's scene into OUTDIR (scenario-gen output), and table rows
import json, subprocess, sys, os
out, gen = sys.argv[1], sys.argv[2]
os.makedirs(out, exist_ok=True)
rows = []
for p in sys.argv[3:]:
    for l in open(p):
        r = json.loads(l)
        if r['success']: continue
        name = f"{r['family']}-{r['seed']}.yaml"
        y = subprocess.run([gen, '--family', r['family'], '--seed', str(r['seed'])], capture_output=True, text=True, check=True).stdout
        open(os.path.join(out, name), 'w').write(y)
        what = ['goal' if r['reached_goal'] else 'timeout' if r['timed_out'] else 'no goal']
        if r['at_fault']: what.append('collision at fault')
        elif r['collided']: what.append('contact not at fault')
        rows.append(f"| `{name}` | {', '.join(what)} ({r['min_dist_m']:.2f}) |")
print('\n'.join(rows))
