# contact.py LOG OBSTACLE_ID T_CONTACT_S [WINDOW_S]: for each PLAN of the
# WINDOW_S (default 2) seconds before a contact (T_CONTACT_S: the contact's
# t_start_s in metrics.json, OBSTACLE_ID its obstacle_id): the plan's status
# and first speed, the robot's truth (position, speed, yaw), the obstacle's
# truth (position, velocity, centre distance) and the predicted track
# nearest to it (id, distance, its prediction's fastest step in m/s).
# Run from the repository root after a build (needs build/bin/lcmlog-export).
import json, math, subprocess, sys
log, oid, tc = sys.argv[1], int(sys.argv[2]), float(sys.argv[3])
win = float(sys.argv[4]) if len(sys.argv) > 4 else 2.0
out = subprocess.run(['build/bin/lcmlog-export', '--channel', 'PLAN', '--channel', 'SIM_TRUTH',
                      '--channel', 'OBSTACLE_PREDICTIONS', log], capture_output=True, text=True).stdout
t0 = None; truth = None; preds = None
for line in out.splitlines():
    r = json.loads(line); m = r['msg']
    if t0 is None: t0 = r['utime']
    t = (r['utime'] - t0) * 1e-6
    if r['channel'] == 'SIM_TRUTH': truth = m; continue
    if r['channel'] == 'OBSTACLE_PREDICTIONS': preds = m; continue
    if t < tc - win or t > tc + 0.2 or truth is None: continue
    o = next(o for o in truth['obstacles'] if o['id'] == oid)
    d = math.hypot(o['x'] - truth['x'], o['y'] - truth['y'])
    best = None
    if preds:
        for p in preds.get('predictions', preds.get('tracks', [])):
            px, py = p['x'][0], p['y'][0]
            dd = math.hypot(px - o['x'], py - o['y'])
            sp = max(math.hypot(p['x'][k+1]-p['x'][k], p['y'][k+1]-p['y'][k]) for k in range(len(p['x'])-1)) / preds['dt']
            if best is None or dd < best[1]: best = (p.get('id'), round(dd, 2), round(sp, 2))
    print(f"{t:6.2f} st {m['status']} v0 {m['v'][0]:.2f} robot ({truth['x']:.2f},{truth['y']:.2f}) v {truth['v']:.2f} yaw {truth['yaw']:.2f} | obs ({o['x']:.2f},{o['y']:.2f}) v ({o['vx']:.2f},{o['vy']:.2f}) d {d:.2f} | track {best}")
