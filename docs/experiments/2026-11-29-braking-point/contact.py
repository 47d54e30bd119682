# contact.py LOG OBSTACLE_ID T_CONTACT_S [WINDOW_S]: for each PLAN of the
# WINDOW_S (default 2) seconds before a contact (T_CONTACT_S: the contact's
# t_start_s in metrics.json, OBSTACLE_ID its obstacle_id): the plan's status
# and first speed, the robot's truth (position, speed, yaw), the obstacle's
# truth (position, velocity, centre distance) and the predicted track
# nearest to it (id, distance, its prediction's fastest step in m/s).
# Run from the repository root after a build (needs build/bin/lcmlog-export).
# As a module: export(LOG) once per log, window(rows, ...) per contact.
import json, math, subprocess, sys


def export(log):
    """The log's PLAN, SIM_TRUTH and OBSTACLE_PREDICTIONS messages, in order."""
    out = subprocess.run(['build/bin/lcmlog-export', '--channel', 'PLAN', '--channel', 'SIM_TRUTH',
                          '--channel', 'OBSTACLE_PREDICTIONS', log], capture_output=True, text=True).stdout
    return [json.loads(line) for line in out.splitlines()]


def window(rows, oid, tc, win=2.0):
    """One dict per PLAN from tc - win to tc + 0.2 s (see the top of this file)."""
    t0 = None; truth = None; preds = None
    for r in rows:
        m = r['msg']
        if t0 is None: t0 = r['utime']
        t = (r['utime'] - t0) * 1e-6
        if r['channel'] == 'SIM_TRUTH': truth = m; continue
        if r['channel'] == 'OBSTACLE_PREDICTIONS': preds = m; continue
        if t < tc - win or t > tc + 0.2 or truth is None: continue
        o = next(o for o in truth['obstacles'] if o['id'] == oid)
        best = None
        if preds:
            for p in preds.get('predictions', preds.get('tracks', [])):
                px, py = p['x'][0], p['y'][0]
                dd = math.hypot(px - o['x'], py - o['y'])
                sp = max(math.hypot(p['x'][k+1]-p['x'][k], p['y'][k+1]-p['y'][k]) for k in range(len(p['x'])-1)) / preds['dt']
                if best is None or dd < best[1]: best = (p.get('id'), round(dd, 2), round(sp, 2))
        yield dict(t=t, status=m['status'], v0=m['v'][0], truth=truth, obs=o,
                   d=math.hypot(o['x'] - truth['x'], o['y'] - truth['y']), track=best)


def line(w):
    tr, o = w['truth'], w['obs']
    return (f"{w['t']:6.2f} st {w['status']} v0 {w['v0']:.2f} robot ({tr['x']:.2f},{tr['y']:.2f}) v {tr['v']:.2f} yaw {tr['yaw']:.2f} | "
            f"obs ({o['x']:.2f},{o['y']:.2f}) v ({o['vx']:.2f},{o['vy']:.2f}) d {w['d']:.2f} | track {w['track']}")


if __name__ == '__main__':
    log, oid, tc = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
    win = float(sys.argv[4]) if len(sys.argv) > 4 else 2.0
    for w in window(export(log), oid, tc, win):
        print(line(w))
