#!/usr/bin/env python3
# sign.py NEW.jsonl BASE.jsonl: paired episodes (family, seed) whose success
# differs: gained, lost, and the two-sided exact sign test's p.
import json, sys
from math import comb

def rows(path):
    out = {}
    for line in open(path):
        r = json.loads(line)
        if 'success' in r:
            out[(r['family'], r['seed'])] = r
    return out

new, base = rows(sys.argv[1]), rows(sys.argv[2])
keys = sorted(set(new) & set(base))
gained = sum(1 for k in keys if new[k]['success'] and not base[k]['success'])
lost = sum(1 for k in keys if base[k]['success'] and not new[k]['success'])
n = gained + lost
tail = sum(comb(n, i) for i in range(0, min(gained, lost) + 1)) / 2 ** n if n else 1.0
print('paired %d: gained %d, lost %d, sign test p = %.3f' % (len(keys), gained, lost, min(1.0, 2 * tail)))
