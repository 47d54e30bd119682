#!/usr/bin/env python3
# timeline.py [--bin DIR] [--every S] [--from T] [--to T] EPISODE_DIR_OR_LOG
# A timeline of one lockstep episode: every S seconds the robot's true pose
# (SIM_TRUTH), its progress along the route and distance off it, the
# PLAN statuses sent in the last S seconds, the obstacles in the last plan's
# constraints (track id and slack; -1 the static field), the three nearest
# true obstacles (scenario id and a rough body distance; * moving) and the
# planner's HEALTH counters' rise. Needs build/bin/lcmlog-export (--bin).
import json, math, os, subprocess, sys
from collections import Counter

args = sys.argv[1:]
opt = {'--bin': 'build/bin', '--every': '2', '--from': '0', '--to': '1e9'}
while args and args[0] in opt:
    opt[args[0]] = args[1]; args = args[2:]
path = args[0]
log = path if path.endswith('.lcmlog') else os.path.join(path, 'run', 'run.lcmlog')
if not os.path.exists(log): log = os.path.join(path, 'run.lcmlog')
every, t0s, t1s = float(opt['--every']), float(opt['--from']), float(opt['--to'])
ST = {0: 'OK', 1: 'FALL', 2: 'STOP', 3: 'STALE', 4: 'NOROUTE', 5: 'GOAL', 6: 'RECO', 7: 'BLOC'}

def export(chs):
    cmd = [os.path.join(opt['--bin'], 'lcmlog-export')]
    for c in chs: cmd += ['--channel', c]
    p = subprocess.run(cmd + [log], capture_output=True, text=True)
    for l in p.stdout.splitlines():
        yield json.loads(l)

route = None; truth = []; plans = []; health = []
for r in export(['ROUTE', 'SIM_TRUTH', 'PLAN', 'HEALTH']):
    m = r['msg']; c = r['channel']
    if c == 'ROUTE' and route is None: route = list(zip(m['x'], m['y']))
    elif c == 'SIM_TRUTH': truth.append(m)
    elif c == 'PLAN': plans.append(m)
    elif c == 'HEALTH' and m['name'] == 'planner':
        health.append((m['utime'], {x['name']: x['value'] for x in m['counters']}))
T0 = truth[0]['utime']

def progress(x, y):
    best, acc, s_best = 1e9, 0.0, 0.0
    for (ax, ay), (bx, by) in zip(route, route[1:]):
        dx, dy = bx - ax, by - ay; L = math.hypot(dx, dy)
        u = max(0.0, min(1.0, ((x - ax) * dx + (y - ay) * dy) / (L * L)))
        d = math.hypot(ax + u * dx - x, ay + u * dy - y)
        if d < best: best, s_best = d, acc + u * L
        acc += L
    return s_best, best

def body_dist(rb, o):
    # crude: distance between centres less radii (box: half width), for orientation
    r = o['radius'] if o['shape'] == 'cylinder' else 0.5 * min(o['length'], o['width'])
    return math.hypot(o['x'] - rb['x'], o['y'] - rb['y']) - r - 0.21

ti = 0; pi = 0; hi = 0; last_h = health[0][1] if health else {}
t = t0s
tend = min(t1s, (truth[-1]['utime'] - T0) / 1e6)
while t <= tend + 1e-9:
    while ti + 1 < len(truth) and (truth[ti + 1]['utime'] - T0) / 1e6 <= t: ti += 1
    rb = truth[ti]
    sts = Counter(); lastp = None
    while pi < len(plans) and (plans[pi]['utime'] - T0) / 1e6 <= t:
        if (plans[pi]['utime'] - T0) / 1e6 > t - every: sts[ST.get(plans[pi]['status'], '?')] += 1
        lastp = plans[pi]; pi += 1
    h = last_h
    while hi < len(health) and (health[hi][0] - T0) / 1e6 <= t:
        h = health[hi][1]; hi += 1
    dh = {k: v - last_h.get(k, 0) for k, v in h.items() if v - last_h.get(k, 0)}
    last_h = h
    s, off = progress(rb['x'], rb['y'])
    near = sorted(((body_dist(rb, o), o) for o in rb['obstacles']), key=lambda z: z[0])[:3]
    ns = ' '.join('%d:%.2f%s' % (o['id'], d, '*' if math.hypot(o['vx'], o['vy']) > 0.05 else '') for d, o in near)
    cons = ''
    if lastp:
        cons = ' '.join('%d(%.2f)' % (i, sl) for i, sl in zip(lastp['obstacle_id'], lastp['obstacle_slack']))
        vend = lastp['v'][-1] if lastp['v'] else 0
    print('t %5.1f x %6.2f y %5.2f yaw %5.0f v %4.2f | s %5.2f off %5.2f | %s | cons %s | near %s | %s' % (
        t, rb['x'], rb['y'], math.degrees(rb['yaw']), rb['v'], s, off,
        ' '.join('%s %d' % kv for kv in sts.most_common()), cons, ns,
        ' '.join('%s+%d' % kv for kv in sorted(dh.items()) if kv[0] not in ('cycle_on_obstacles', 'static_field'))))
    t += every
