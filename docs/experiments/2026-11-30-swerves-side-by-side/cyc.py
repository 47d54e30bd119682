# cyc.py BASE.jsonl NEW.jsonl: modelled planner cycle p99 per family, median and largest over episodes
import json,sys,statistics,collections
def load(p): return {(r['family'],r['seed']):r for r in map(json.loads,open(p))}
B,N=load(sys.argv[1]),load(sys.argv[2])
fam=collections.defaultdict(lambda:([],[]))
for k in N:
    if k in B and B[k].get('planner_cycle_ms_p99') is not None and N[k].get('planner_cycle_ms_p99') is not None:
        fam[k[0]][0].append(B[k]['planner_cycle_ms_p99']); fam[k[0]][1].append(N[k]['planner_cycle_ms_p99'])
for f,(b,n) in sorted(fam.items()):
    print(f"| {f} | {len(b)} | {statistics.median(b):.1f} -> {statistics.median(n):.1f} | {max(b):.1f} -> {max(n):.1f} |")
