# changed.py NEW.jsonl...: episodes whose outcome (goal / at fault / contact not at fault / timeout) differs from the base rows
import json, sys
base = {}
for p in ['/work/out/s12/final/r1/results.jsonl', '/work/out/s12/final/r101/results.jsonl']:
    for r in map(json.loads, open(p)): base[(r['family'], r['seed'])] = r
def oc(r):
    return ('goal' if r['reached_goal'] else 'no goal') + (', at fault' if r['at_fault'] else ', contact' if r['collided'] else '') + (', timeout' if r['timed_out'] else '')
n = ch = same = 0
for p in sys.argv[1:]:
    for r in map(json.loads, open(p)):
        b = base[(r['family'], r['seed'])]; n += 1
        if oc(b) != oc(r): ch += 1; print(f"{r['family']} {r['seed']}: {oc(b)} -> {oc(r)}")
        if all(b.get(k) == r.get(k) for k in ('min_dist_m', 'time_to_goal_s', 'path_length_m', 'success', 'collided', 'timed_out')): same += 1
print(f'{ch} of {n} changed outcome; {same} identical in least distance, time and path')
