# newly.py OUTDIR NEW_DIR...: episodes that succeed in the base rows (s12 final r1/r101) and fail in NEW;
# copies each scenario to OUTDIR/<family>-<seed>.yaml and prints README rows.
import json, os, shutil, sys
base = {}
for p in ['/work/out/s12/final/r1/results.jsonl', '/work/out/s12/final/r101/results.jsonl']:
    for r in map(json.loads, open(p)): base[(r['family'], r['seed'])] = r
out = sys.argv[1]
os.makedirs(out, exist_ok=True)
def outcome(r):
    if r.get('error'): return 'error'
    head = 'goal' if r['reached_goal'] else 'timeout' if r['timed_out'] else 'no goal'
    if r['at_fault']: return head + ', collision at fault'
    if r['collided']: return head + ', contact not at fault'
    return head
for d in sys.argv[2:]:
    for r in map(json.loads, open(os.path.join(d, 'results.jsonl'))):
        b = base.get((r['family'], r['seed']))
        if not b or not b.get('success') or r.get('success'): continue
        name = f"{r['family']}-{r['seed']}.yaml"
        src = os.path.join(d, r['dir'], 'scenario.yaml')
        if not os.path.exists(src): src = os.path.join(d, 'episodes', r['family'], 'evade', str(r['seed']), 'scenario.yaml')
        if not os.path.exists(src): src = os.path.join(d, 'failed', r['family'], 'evade', str(r['seed']), 'scenario.yaml')
        shutil.copy(src, os.path.join(out, name))
        print(f"| `{name}` | {outcome(b)}, {b['min_dist_m']:.2f} | {outcome(r)} | {r['min_dist_m']:.2f} |")
