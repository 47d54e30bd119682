# fit.py DIR...: per DIR, the least-squares line CPU = base + per_iteration x iterations
# through every PLAN cycle (planner,plan rows) of DIR/*.csv (lockstep --profile --samples),
# pooled, and per scene.
import csv, glob, os, sys
def fit(rows):
    n = len(rows); sx = sum(x for x, _ in rows); sy = sum(y for _, y in rows)
    sxx = sum(x * x for x, _ in rows); sxy = sum(x * y for x, y in rows)
    var = sxx - sx * sx / n
    b = (sxy - sx * sy / n) / var if var > 0 else 0.0
    return sy / n - b * sx / n, b, n
for d in sys.argv[1:]:
    allr = []
    for f in sorted(glob.glob(os.path.join(d, '*.csv'))):
        rows = [(float(r['k']), float(r['cpu_s'])) for r in csv.DictReader(open(f)) if r['process'] == 'planner' and r['kind'] == 'plan']
        allr += rows
        a, b, n = fit(rows)
        print(f'{d} {os.path.basename(f)[:-4]:16s} base {a*1e3:.3f} ms  per-iteration {b*1e3:.4f} ms  cycles {n}  mean {sum(y for _, y in rows)/n*1e3:.3f} ms')
    a, b, n = fit(allr)
    print(f'{d} POOLED           base {a*1e3:.3f} ms  per-iteration {b*1e3:.4f} ms  cycles {n}  mean {sum(y for _, y in allr)/n*1e3:.3f} ms')
