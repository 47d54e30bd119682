#!/usr/bin/env python3
# diverge.py LOG_A LOG_B [BIN_DIR]: the first PLAN where two lockstep runs of one scene
# differ, and that cycle's inputs side by side: the planner's HEALTH
# counters that differ, the plan's constraints (track ids may differ between
# the runs), and the predicted tracks within 12 m of the robot.
import json, math, subprocess, sys
B = sys.argv[3] if len(sys.argv) > 3 else 'build/bin'

def load(log):
    p = subprocess.run([B + '/lcmlog-export', '--channel', 'PLAN', '--channel', 'HEALTH', '--channel',
                        'OBSTACLE_PREDICTIONS', '--channel', 'SIM_TRUTH', log], capture_output=True, text=True)
    plans, health, preds, T0 = [], [], [], None
    for l in p.stdout.splitlines():
        r = json.loads(l); m = r['msg']; c = r['channel']
        if c == 'SIM_TRUTH':
            if T0 is None: T0 = m['utime']
        elif c == 'PLAN': plans.append(m)
        elif c == 'HEALTH' and m['name'] == 'planner': health.append((m['utime'], {x['name']: x['value'] for x in m['counters']}))
        elif c == 'OBSTACLE_PREDICTIONS': preds.append(m)
    return plans, health, preds, T0

A, Bv = load(sys.argv[1]), load(sys.argv[2])
T0 = A[3]
n = min(len(A[0]), len(Bv[0]))
for i in range(n):
    a, b = A[0][i], Bv[0][i]
    if a['status'] != b['status'] or max(abs(p - q) for p, q in zip(a['x'] + a['y'], b['x'] + b['y'])) > 1e-4:
        break
else:
    print('no divergence in', n, 'plans'); sys.exit()
a, b = A[0][i], Bv[0][i]
t = (a['utime'] - T0) / 1e6
print('first differing plan #%d at t %.2f s: status %d vs %d; end (%.2f, %.2f) vs (%.2f, %.2f); robot (%.2f, %.2f)' % (
    i, t, a['status'], b['status'], a['x'][-1], a['y'][-1], b['x'][-1], b['y'][-1], a['x'][0], a['y'][0]))
print('  constraints A:', ' '.join('%d(%.2f,%.2f)' % z for z in zip(a['obstacle_id'], a['obstacle_x'], a['obstacle_y'])))
print('  constraints B:', ' '.join('%d(%.2f,%.2f)' % z for z in zip(b['obstacle_id'], b['obstacle_x'], b['obstacle_y'])))
def hat(H, u):
    h = {}
    for hu, c in H:
        if hu <= u: h = c
    return h
ha, hb = hat(A[1], a['utime']), hat(Bv[1], b['utime'])
print('  HEALTH differing (A, B):', {k: (ha.get(k), hb.get(k)) for k in sorted(set(ha) | set(hb)) if ha.get(k) != hb.get(k)})
def pred(P, u):
    for m in P:
        if m['utime'] == u: return m
pa, pb = pred(A[2], a['predictions_utime']), pred(Bv[2], b['predictions_utime'])
rx, ry = a['x'][0], a['y'][0]
for name, pm in (('A', pa), ('B', pb)):
    if not pm: print('  predictions', name, 'none'); continue
    tr = sorted(pm['tracks'], key=lambda k: math.hypot(k['x'][0] - rx, k['y'][0] - ry))
    print('  predictions %s: %d tracks; within 12 m:' % (name, len(tr)))
    for k in tr:
        d = math.hypot(k['x'][0] - rx, k['y'][0] - ry)
        if d > 12: break
        print('    %3d at %5.2f m (%.2f, %.2f) v (%.2f, %.2f) a %.2f b %.2f' % (k['id'], d, k['x'][0], k['y'][0], k['vx'], k['vy'], k['a'][0], k['b'][0]))
