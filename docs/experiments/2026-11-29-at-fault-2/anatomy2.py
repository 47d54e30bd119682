# anatomy2.py [--json OUT] EPISODE_DIR... : for the first contact at fault of
# each benchmark episode (DIR/run/{metrics.json,run.lcmlog,robot.yaml}), the
# plans sent in the 2 s before it: status, what kind of plan (by its
# controls), the outcome as plan_outcome judged it against the contact's
# obstacle (its predicted ellipse less sigma, the footprint's 3 discs, the
# horizon and one more), and what the obstacle truly did (SIM_TRUTH) along
# the same plan: the bodies' clearance had the robot followed it, and the
# prediction's centre error at the step the judged clearance is least.
# Needs build/bin/lcmlog-export. Odometry is the simulator's frame in
# lockstep (checked: ODOMETRY equals SIM_TRUTH's pose at the same time).
import bisect, collections, json, math, subprocess, sys

EXPORT = 'build/bin/lcmlog-export'
NAMES = {0: 'OK', 1: 'FALLBACK', 2: 'STOPPING', 3: 'STALE', 4: 'NOROUTE', 5: 'GOAL', 6: 'RECOVERING', 7: 'BLOCKED'}
HEALTH_KEYS = ('solver_infeasible', 'most_clearance', 'fallback', 'stopping', 'restart_skipped', 'escape_turn',
               'blocked', 'detour_movers')


def discs(length, width, n=3):
    sl = length / n
    return [-0.5 * length + sl * (i + 0.5) for i in range(n)], math.hypot(0.5 * sl, 0.5 * width)


def ellipse_dist(px, py, cx, cy, a, b, th):
    # signed distance from a point to an ellipse (sampled boundary; < 0 inside)
    c, s = math.cos(th), math.sin(th)
    lx, ly = c * (px - cx) + s * (py - cy), -s * (px - cx) + c * (py - cy)
    inside = (lx / a) ** 2 + (ly / b) ** 2 < 1.0
    d = min(math.hypot(lx - a * math.cos(t), ly - b * math.sin(t)) for t in (2 * math.pi * i / 90 for i in range(90)))
    return -d if inside else d


def shape_dist(px, py, o):
    # signed distance from a point to a simulator obstacle's body
    if o['shape'] == 'cylinder':
        return math.hypot(px - o['x'], py - o['y']) - o['radius']
    c, s = math.cos(o['yaw']), math.sin(o['yaw'])
    lx, ly = c * (px - o['x']) + s * (py - o['y']), -s * (px - o['x']) + c * (py - o['y'])
    dx, dy = abs(lx) - 0.5 * o['length'], abs(ly) - 0.5 * o['width']
    return math.hypot(max(dx, 0), max(dy, 0)) + min(max(dx, dy), 0)


def body_dist(x, y, yaw, offs, r, f):
    return min(f(x + o * math.cos(yaw), y + o * math.sin(yaw)) for o in offs) - r


def extend(xs, n):
    # xs carried on for n more steps at its last step's displacement
    d = xs[-1] - xs[-2]
    return xs + [xs[-1] + j * d for j in range(1, n + 1)]


def kind_of(p):
    v, w = p['v'], p['omega']
    lat = -math.sin(p['yaw'][0]) * (p['x'][-1] - p['x'][0]) + math.cos(p['yaw'][0]) * (p['y'][-1] - p['y'][0])
    if p['status'] == 0:
        return 'solved'
    if max(v) < 0.02:
        return 'stand'
    if v[-1] < 0.02 and all(b <= a + 1e-6 for a, b in zip(v, v[1:])) and abs(lat) < 0.05:
        return 'brake'
    if v[-1] < 0.02:
        return 'pull-over %+.2f' % lat
    return 'on %.1f m/s %+.2f' % (v[-1], lat)


def load(ep):
    out = subprocess.run([EXPORT, '--channel', 'SIM_TRUTH', '--channel', 'PLAN', '--channel', 'OBSTACLE_PREDICTIONS',
                          '--channel', 'HEALTH', ep + '/run/run.lcmlog'], capture_output=True, text=True).stdout
    ch = collections.defaultdict(list)
    for line in out.splitlines():
        r = json.loads(line)
        ch[r['channel']].append(r['msg'])
    return ch


def health_delta(hs, t0, ts):
    hs = [h for h in hs if h['name'] == 'planner']
    def at(t):
        best = {}
        for h in hs:
            if (h['utime'] - t0) / 1e6 <= t: best = {c['name']: c['value'] for c in h['counters']}
        return best
    a, b = at(ts - 2.0), at(ts + 0.999)
    return {k: b[k] - a.get(k, 0) for k in HEALTH_KEYS if b.get(k, 0) - a.get(k, 0) > 0}


def judge(p, pred, truth_at, oid, offs, r, ext):
    # the contact obstacle's predicted track: nearest its true centre at step 0
    t_obs = truth_at(p['utime'], oid)
    best = None
    for tr in pred['tracks']:
        d = math.hypot(tr['x'][0] - t_obs['x'], tr['y'][0] - t_obs['y'])
        if best is None or d < best[0]: best = (d, tr)
    if best is None or best[0] > 2.5: return None
    tr = best[1]
    # the prediction list is stamped up to a period before the plan: shift by
    # whole steps to the plan's time
    lag = max(0, round((p['utime'] - pred['utime']) / 1e5))
    N = len(p['x']) - 1
    xs, ys, yaws = extend(p['x'], ext), extend(p['y'], ext), p['yaw'] + [p['yaw'][-1]] * ext
    ox, oy = extend(tr['x'], N + ext + lag), extend(tr['y'], N + ext + lag)
    a = [max(tr['a'][min(k, N)] - tr['sigma'][min(k, N)], 1e-3) for k in range(len(ox))]
    b = [max(tr['b'][min(k, N)] - tr['sigma'][min(k, N)], 1e-3) for k in range(len(ox))]
    th = [tr['theta'][min(k, N)] for k in range(len(ox))]
    judged, real = [], []
    for k in range(N + ext + 1):
        j = k + lag
        judged.append(body_dist(xs[k], ys[k], yaws[k], offs, r,
                                lambda px, py: ellipse_dist(px, py, ox[j], oy[j], a[j], b[j], th[j])))
        o = truth_at(p['utime'] + k * 100000, oid)
        real.append(body_dist(xs[k], ys[k], yaws[k], offs, r, lambda px, py: shape_dist(px, py, o)) if o else None)
    k = min(range(1, N + ext + 1), key=lambda i: judged[i])
    o = truth_at(p['utime'] + k * 100000, oid)
    err = math.hypot(ox[k + lag] - o['x'], oy[k + lag] - o['y']) if o else float('nan')
    rk = min((i for i in range(1, N + ext + 1) if real[i] is not None), key=lambda i: real[i])
    o = truth_at(p['utime'] + rk * 100000, oid)
    rerr = math.hypot(ox[rk + lag] - o['x'], oy[rk + lag] - o['y'])
    return dict(judged=judged[k], judged_k=k, start=judged[0], real=real[rk], real_k=rk, err=err, real_err=rerr,
                judged_at_real=judged[rk],
                pred_speed=math.hypot(tr['vx'], tr['vy']))


def analyse(ep, window=2.0):
    met = json.load(open(ep + '/run/metrics.json'))
    cs = [c for c in met.get('contacts', []) if c['at_fault']]
    if not cs: return None
    c = cs[0]
    ch = load(ep)
    truth = ch['SIM_TRUTH']
    t0 = truth[0]['utime']
    tu = [m['utime'] for m in truth]
    fp = truth[0]
    offs, r = discs(fp['footprint_length'], fp['footprint_width'])

    def truth_at(u, oid):
        i = min(bisect.bisect_left(tu, u), len(tu) - 1)
        for o in truth[i]['obstacles']:
            if o['id'] == oid: return o
        return None
    ts, oid = c['t_start_s'], c['obstacle_id']
    preds = {m['utime']: m for m in ch['OBSTACLE_PREDICTIONS']}
    plans = [p for p in ch['PLAN'] if ts - window <= (p['utime'] - t0) / 1e6 <= ts]
    rows = []
    for p in plans:
        pr = preds.get(p['predictions_utime'])
        j = judge(p, pr, truth_at, oid, offs, r, len(p['x']) - 1) if pr else None
        rows.append(dict(t=round((p['utime'] - t0) / 1e6 - ts, 2), status=NAMES.get(p['status'], p['status']),
                         kind=kind_of(p), v0=round(p['v'][0], 2), judge=j))
    vel = [truth_at(t0 + int((ts - window + 0.1 * i) * 1e6), oid) for i in range(int(window * 10) + 1)]
    vel = [o for o in vel if o]
    turned = max((math.hypot(a['vx'] - b['vx'], a['vy'] - b['vy']) for a, b in zip(vel, vel[1:])), default=0.0)
    obs = vel[-1] if vel else {}
    return dict(episode=ep, t=ts, oid=oid, shape=obs.get('shape'), obs_speed=math.hypot(obs.get('vx', 0), obs.get('vy', 0)),
                robot_speed=c['robot_speed_mps'], turned=turned, health=health_delta(ch['HEALTH'], t0, ts), plans=rows)


if __name__ == '__main__':
    args = sys.argv[1:]
    jout = None
    if args and args[0] == '--json': jout, args = args[1], args[2:]
    res = []
    for ep in args:
        a = analyse(ep)
        if not a: continue
        res.append(a)
        st = collections.Counter(p['status'] for p in a['plans'])
        print('==', ep, 't %.2f obstacle %d %s %.2f m/s, robot %.2f m/s, velocity jump %.2f m/s' % (
            a['t'], a['oid'], a['shape'], a['obs_speed'], a['robot_speed'], a['turned']))
        print('   statuses', dict(st), 'health', a['health'])
        for p in a['plans'][-20:]:
            j = p['judge']
            js = ('judged %+.3f at %.1f s (start %+.3f); truth %+.3f at %.1f s (judged there %+.3f, centre error %.2f m)' % (
                j['judged'], j['judged_k'] * 0.1, j['start'], j['real'], j['real_k'] * 0.1, j['judged_at_real'],
                j['real_err'])) if j else 'no track'
            print('   %+.2f %-10s %-22s v0 %.2f  %s' % (p['t'], p['status'], p['kind'], p['v0'], js))
    if jout: json.dump(res, open(jout, 'w'))
