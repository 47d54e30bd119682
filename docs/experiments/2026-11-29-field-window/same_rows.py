# same_rows.py BASE.jsonl NEW.jsonl: every episode of NEW against BASE's (family, seed):
# outcome, least distance, time to goal, path length; prints the differing ones.
import json, sys
def rows(p):
    return {(r['family'], r['seed']): r for r in map(json.loads, open(p))}
base, new = rows(sys.argv[1]), rows(sys.argv[2])
keys = ['success', 'at_fault', 'collided', 'timed_out', 'min_dist_m', 'time_to_goal_s', 'path_length_m']
same = diff = 0
for k in sorted(new):
    b = base.get(k)
    if b is None:
        print('no base row', k); continue
    d = [(x, b.get(x), new[k].get(x)) for x in keys if b.get(x) != new[k].get(x)]
    if d: diff += 1; print(k, d)
    else: same += 1
print(f'{same} episodes identical, {diff} differ')
