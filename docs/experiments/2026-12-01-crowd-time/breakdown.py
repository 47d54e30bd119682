#!/usr/bin/env python3
"""Where an episode's time goes, from its run log (SIM_TRUTH at 50 Hz, PLAN).

    python3 breakdown.py [--export BIN] LOG [LOG ...]

One markdown row per log: the share of PLAN cycles per status, and the
share of simulated time the robot stood (|v| < 0.05 m/s), stood with no
obstacle's body within 1.5 m, turned on the spot (|v| < 0.05 m/s,
|omega| > 0.2 rad/s), and headed more than 90 deg away from the goal.
"""
import argparse
import collections
import json
import math
import subprocess

STATUS = {0: 'ok', 1: 'fallback', 2: 'stopping', 3: 'stale', 6: 'recovering', 7: 'blocked'}


def read(export, log):
    out = subprocess.run([export, log, '--channel', 'PLAN', '--channel', 'SIM_TRUTH'],
                         capture_output=True, text=True, check=True).stdout
    truth, plans = [], []
    for line in out.splitlines():
        r = json.loads(line)
        (truth if r['channel'] == 'SIM_TRUTH' else plans).append(r['msg'])
    return truth, plans


def shares(truth):
    c = collections.Counter()
    for m in truth:
        if abs(m['v']) < 0.05:
            near = min([math.hypot(o['x'] - m['x'], o['y'] - m['y']) - o.get('radius', 0.0)
                        for o in m['obstacles']] + [math.inf])
            c['still'] += 1
            c['still_nobody_near'] += near > 1.5
            c['spin'] += abs(m['omega']) > 0.2
        to_goal = math.atan2(m['goal_y'] - m['y'], m['goal_x'] - m['x'])
        c['away'] += abs((m['yaw'] - to_goal + math.pi) % (2 * math.pi) - math.pi) > math.pi / 2
    return {k: 100.0 * v / max(1, len(truth)) for k, v in c.items()}


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--export', default='build/bin/lcmlog-export')
    ap.add_argument('logs', nargs='+')
    a = ap.parse_args()
    keys = ['ok', 'recovering', 'blocked', 'stopping']
    print('| log | s | ' + ' | '.join(f'{k} %' for k in keys) +
          ' | still % | still, nobody within 1.5 m % | spin % | heading away % |')
    print('|---' * (2 + len(keys) + 4) + '|')
    for log in a.logs:
        truth, plans = read(a.export, log)
        st = collections.Counter(STATUS.get(p['status'], str(p['status'])) for p in plans)
        n = max(1, len(plans))
        s = shares(truth)
        dur = (truth[-1]['utime'] - truth[0]['utime']) * 1e-6 if truth else 0.0
        cells = [f'{100.0 * st[k] / n:.0f}' for k in keys]
        cells += [f"{s.get(k, 0.0):.0f}" for k in ('still', 'still_nobody_near', 'spin', 'away')]
        print(f'| {log} | {dur:.0f} | ' + ' | '.join(cells) + ' |')


if __name__ == '__main__':
    main()
