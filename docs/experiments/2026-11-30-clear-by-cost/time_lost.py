#!/usr/bin/env python3
# time_lost.py [--bin DIR] EPISODE_DIR...: where a lockstep episode's time
# went, from its log's SIM_TRUTH (the true robot) and PLAN (the status
# sent). Per episode: seconds standing (|v| < 0.05 m/s), of them turning on
# the spot (|omega| > 0.2 rad/s); seconds moving backwards along x (the
# families' routes run along +x); the largest |y| (off the route); the
# turning on the spot split by the status of the plan in force. Needs
# build/bin/lcmlog-export (--bin).
import json, os, subprocess, sys
from collections import Counter

args = sys.argv[1:]
bindir = 'build/bin'
if args and args[0] == '--bin':
    bindir, args = args[1], args[2:]
ST = {0: 'OK', 1: 'FALLBACK', 2: 'STOPPING', 3: 'STALE', 4: 'NO_ROUTE', 5: 'GOAL', 6: 'RECOVERING', 7: 'BLOCKED'}
total = Counter()
for d in args:
    log = os.path.join(d, 'run', 'run.lcmlog')
    out = subprocess.run([os.path.join(bindir, 'lcmlog-export'), '--channel', 'SIM_TRUTH', '--channel', 'PLAN', log],
                         capture_output=True, text=True).stdout
    status, prev, c = '?', None, Counter()
    max_off = 0.0
    for line in out.splitlines():
        r = json.loads(line)
        m = r['msg']
        if r['channel'] == 'PLAN':
            status = ST.get(m['status'], '?')
            continue
        t = m['utime'] / 1e6
        if prev is not None:
            dt = t - prev[0]
            if abs(m['v']) < 0.05:
                c['stand'] += dt
                if abs(m['omega']) > 0.2:
                    c['turn'] += dt
                    c['turn ' + status] += dt
            if (m['x'] - prev[1]) / max(dt, 1e-6) < -0.1:
                c['back'] += dt
        max_off = max(max_off, abs(m['y']))
        prev = (t, m['x'])
    total.update(c)
    by_status = ' '.join('%s %.0f' % (k[5:], v) for k, v in c.most_common() if k.startswith('turn '))
    print('%s stand %.0f s (turning on the spot %.0f: %s) backwards %.0f s, |y| up to %.1f m' %
          (os.path.basename(d.rstrip('/')), c['stand'], c['turn'], by_status, c['back'], max_off))
if len(args) > 1:
    print('all: stand %.0f s, turning on the spot %.0f s, backwards %.0f s' % (total['stand'], total['turn'], total['back']))
