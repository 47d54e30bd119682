# bound_check.py EPISODE_DIR... : for the first contact at fault of each
# episode (DIR/run/{metrics.json,run.lcmlog}), each plan of the 2 s before
# it: its status, the robot's measured speed, and the passive-safety bound
# (lib/planning/passive_safety.h) the planner would have computed from the
# prediction list that plan names, over every track within 4 m: a mover's
# body (its step-0 ellipse less sigma) to the robot's front edge, the
# mover's speed the fastest step of its prediction (at least UNKNOWN m/s
# while tracked less than YOUNG s), tracks slower than SLOW m/s and older
# than YOUNG s left out. Prints one line per plan and a summary per episode:
# when the bound first fell below the measured speed, and the speed the
# robot had at the contact. Needs build/bin/lcmlog-export.
import collections, json, math, subprocess, sys

EXPORT = 'build/bin/lcmlog-export'
TAU, DECEL, UNKNOWN, YOUNG, SLOW, LENGTH, WIDTH = 0.3, 1.5, 1.6, 0.5, 0.2, 0.42, 0.31


def load(ep):
    out = subprocess.run([EXPORT, '--channel', 'PLAN', '--channel', 'OBSTACLE_PREDICTIONS', ep + '/run/run.lcmlog'],
                         capture_output=True, text=True).stdout
    ch = collections.defaultdict(list)
    for line in out.splitlines():
        r = json.loads(line)
        ch[r['channel']].append(r['msg'])
    return ch


def radial_gap(px, py, cx, cy, a, b, th):
    dx, dy = px - cx, py - cy
    d = math.hypot(dx, dy)
    if d < 1e-9:
        return -min(a, b)
    c, s = math.cos(th), math.sin(th)
    u, v = c * dx + s * dy, -s * dx + c * dy
    return d - a * b * d / math.sqrt(b * b * u * u + a * a * v * v)


def bound(gap, s):
    g = gap - s * TAU
    if g <= 0:
        return 0.0
    p = TAU + s / DECEL
    return DECEL * (-p + math.sqrt(p * p + 2 * g / DECEL))


def front_points(x, y, yaw):
    c, s = math.cos(yaw), math.sin(yaw)
    fx, fy = x + 0.5 * LENGTH * c, y + 0.5 * LENGTH * s
    return [(fx - s * w, fy + c * w) for w in (-0.5 * WIDTH + WIDTH * i / 4 for i in range(5))]


def plan_bound(plan, preds, first_seen):
    pts = front_points(plan['x'][0], plan['y'][0], plan['yaw'][0])
    best, who = 9.9, None
    for t in preds['tracks']:
        dt = preds['dt']
        age = (preds['utime'] - first_seen[t['id']]) * 1e-6
        sp = max(math.hypot(t['x'][k + 1] - t['x'][k], t['y'][k + 1] - t['y'][k]) / dt for k in range(len(t['x']) - 1))
        if age < YOUNG:
            sp = max(sp, UNKNOWN)
        elif sp < SLOW:
            continue
        a, b = max(t['a'][0] - t['sigma'][0], 0.05), max(t['b'][0] - t['sigma'][0], 0.05)
        gap = min(radial_gap(px, py, t['x'][0], t['y'][0], a, b, t['theta'][0]) for px, py in pts)
        if gap > 4.0:
            continue
        v = bound(gap, sp)
        if v < best:
            best, who = v, (t['id'], round(gap, 2), round(sp, 2))
    return best, who


def main(eps):
    for ep in eps:
        m = json.load(open(ep + '/run/metrics.json'))
        c = next(c for c in m['contacts'] if c['at_fault'])
        ch = load(ep)
        t0 = ch['PLAN'][0]['utime']
        first_seen, preds_by_utime = {}, {}
        for p in ch['OBSTACLE_PREDICTIONS']:
            for t in p['tracks']:
                first_seen.setdefault(t['id'], p['utime'])
            preds_by_utime[p['utime']] = p
        first_below = None
        print('#', ep, 'contact at %.2f s, robot %.2f m/s' % (c['t_start_s'], c['robot_speed_mps']))
        for plan in ch['PLAN']:
            t = (plan['utime'] - t0) * 1e-6
            if t < c['t_start_s'] - 2.0 or t > c['t_start_s']:
                continue
            pr = preds_by_utime.get(plan['predictions_utime'])
            if not pr:
                continue
            v, who = plan_bound(plan, pr, first_seen)
            speed = plan['v'][0]
            if v < speed - 0.05 and plan['status'] != 0 and first_below is None:
                first_below = c['t_start_s'] - t
            print('  %6.2f st %d v0 %.2f bound %.2f %s' % (t - c['t_start_s'], plan['status'], speed, v, who))
        print('SUMMARY', ep, 'bound first below a recovery plan\'s speed %s s before the contact' %
              ('%.2f' % first_below if first_below is not None else 'never'))


if __name__ == '__main__':
    main(sys.argv[1:])
