# bike_speed.py LOG...: every frame of a bike (a box moving at 1.5 m/s or more, within 8 m of the robot):
# the nearest published track within 1 m (OBSTACLE_PREDICTIONS step 0), its speed against the
# bike's, by track age, by the gap to the nearest parked box and by the MBE's elongation.
# Run from the repository root after a build. World and odometry frames are related by the
# truth and odometry poses of the same moment. bike_frames() is also what
# docs/experiments/2026-12-01-guidance-3/lateral.py walks.
import json, math, subprocess, sys


def bike_frames(log):
    """Yields (utime, truth, odo, tracks, (c, s), bikes) for every prediction list once truth and odometry
    have come: the world-to-odometry rotation, and for every bike within 8 m (o, (bx, by), track):
    its centre in the odometry frame and the nearest track within 1 m (None if there is none)."""
    out = subprocess.run(['build/bin/lcmlog-export', '--channel', 'SIM_TRUTH', '--channel', 'OBSTACLE_PREDICTIONS', '--channel', 'ODOMETRY', log], capture_output=True, text=True).stdout
    truth = odo = None
    for line in out.splitlines():
        r = json.loads(line); m = r['msg']
        if r['channel'] == 'SIM_TRUTH': truth = m; continue
        if r['channel'] == 'ODOMETRY': odo = m; continue
        if truth is None or odo is None: continue
        dyaw = odo['yaw'] - truth['yaw']; c, s = math.cos(dyaw), math.sin(dyaw)
        bikes = []
        for o in truth['obstacles']:
            sp = math.hypot(o['vx'], o['vy'])
            if o['shape'] != 'box' or sp < 1.5: continue
            if math.hypot(o['x'] - truth['x'], o['y'] - truth['y']) > 8: continue
            dx, dy = o['x'] - truth['x'], o['y'] - truth['y']
            ox, oy = odo['x'] + c*dx - s*dy, odo['y'] + s*dx + c*dy
            best = None
            for p in m['tracks']:
                d = math.hypot(p['x'][0] - ox, p['y'][0] - oy)
                if d < 1.0 and (best is None or d < best[0]): best = (d, p)
            bikes.append((o, (ox, oy), best and best[1]))
        yield r['utime'], truth, odo, m['tracks'], (c, s), bikes


def summ(sel, label):
    n = len(sel); m = [r for r in sel if r['matched']]
    if not m: print(label, n, 'none matched'); return
    print(f"{label:28s} frames {n:5d} matched {len(m)/n:.2f} verr mean {sum(r['verr'] for r in m)/len(m):.2f} speed ratio mean {sum(r['vrel'] for r in m)/len(m):.2f} ratio<0.5 {sum(r['vrel']<0.5 for r in m)/len(m):.2f}")


if __name__ == '__main__':
    rows = []
    for log in sys.argv[1:]:
        first = {}
        for utime, truth, odo, tracks, (c, s), bikes in bike_frames(log):
            for q in tracks: first.setdefault(q['id'], utime)
            statics = [x for x in truth['obstacles'] if x['vx'] == 0 and x['vy'] == 0 and x['shape'] == 'box']
            for o, _, p in bikes:
                # gap to nearest static box (centre distance minus half widths, rough)
                gap = min([math.hypot(o['x'] - st['x'], o['y'] - st['y']) - 0.5 * (st['width'] + o['width']) for st in statics] or [99])
                if p is None: rows.append(dict(matched=False, gap=gap)); continue
                sp = math.hypot(o['vx'], o['vy']); vs = math.hypot(p['vx'], p['vy'])
                verr = math.hypot(p['vx'] - o['vx'] * c + o['vy'] * s, p['vy'] - o['vx'] * s - o['vy'] * c)
                rows.append(dict(matched=True, gap=gap, age=(utime - first[p['id']]) * 1e-6, verr=verr, vrel=vs / sp, a=p['a'][0], b=p['b'][0]))
    summ(rows, 'all')
    for lo, hi in ((0, 0.3), (0.3, 0.6), (0.6, 1.0), (1.0, 99)):
        summ([r for r in rows if not r['matched'] or lo <= r['age'] < hi], f'age {lo}-{hi} s')
    for lo, hi in ((-9, 0.5), (0.5, 1.5), (1.5, 99)):
        summ([r for r in rows if lo <= r['gap'] < hi], f'static gap {lo}-{hi} m')
    for el in ((0, 2), (2, 99)):
        summ([r for r in rows if r['matched'] and el[0] <= r['a'] / r['b'] < el[1]], f'elong {el}')
