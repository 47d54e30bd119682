#!/usr/bin/env python3
"""Robot speed when the hidden person steps into view, per occlusion episode.

usage: stepout.py LCMLOG_EXPORT EPISODES_DIR  (EPISODES_DIR/<seed>/run/run.lcmlog)
Step-out: the first SIM_TRUTH whose lidar_returns for the person (the
scenario's only cylinder) is > 0 after it started moving. Prints per seed:
robot speed (SIM_TRUTH v), distance from the robot centre to the person's
centre, the robot's maximum speed over the 2 s before, and the stop margin:
the time the person needs, at their own speed, to the planner's footprint
(3 covering discs) less the robot's stop (0.3 s reaction + v / 1.5 m/s^2).
"""
import json, math, os, statistics, subprocess, sys

exe, root = sys.argv[1], sys.argv[2]
rows = []
for seed in sorted(os.listdir(root), key=int):
    log = os.path.join(root, seed, "run", "run.lcmlog")
    if not os.path.exists(log):
        continue
    out = subprocess.run([exe, log, "--channel", "SIM_TRUTH"], capture_output=True, text=True).stdout
    msgs = [json.loads(l)["msg"] for l in out.splitlines() if l.startswith("{")]
    person = None
    hist = []
    found = None
    for m in msgs:
        obs = m["obstacles"]
        if person is None:
            cyl = [i for i, o in enumerate(obs) if o["shape"] == "cylinder"]
            if len(cyl) != 1:
                break
            person = cyl[0]
        o = obs[person]
        hist.append((m["utime"], m["v"]))
        moving = math.hypot(o["vx"], o["vy"]) > 0.05
        if moving and m["lidar_returns"][person] > 0:
            found = (m, o)
            break
    if not found:
        rows.append((int(seed), None, None, None, None))
        continue
    m, o = found
    before = [v for t, v in hist if t >= m["utime"] - 2_000_000]
    L, W = m["footprint_length"], m["footprint_width"]
    reach = L / 3 + math.hypot(L / 6, W / 2)  # the planner's 3 covering discs
    gap = math.hypot(m["x"] - o["x"], m["y"] - o["y"]) - reach - o["radius"]
    # time the person needs to the footprint at their own speed, less the robot's stop (0.3 s + v / 1.5 m/s^2)
    margin = gap / max(1e-6, math.hypot(o["vx"], o["vy"])) - (0.3 + m["v"] / 1.5)
    rows.append((int(seed), m["v"], math.hypot(m["x"] - o["x"], m["y"] - o["y"]), max(before), margin))
print("# seed\tv (m/s)\tdist (m)\tmax v 2 s before\tstop margin (s)")
for seed, v, d, vmax, margin in rows:
    if v is None:
        print(f"{seed}\t-\t-\t-\t-")
    else:
        print(f"{seed}\t{v:.3f}\t{d:.2f}\t{vmax:.3f}\t{margin:.2f}")
vs = [r[1] for r in rows if r[1] is not None]
if vs:
    ms = [r[4] for r in rows if r[4] is not None]
    ds = [r[2] for r in rows if r[2] is not None]
    print(f"# n {len(vs)} speed mean {statistics.mean(vs):.3f} median {statistics.median(vs):.3f} max {max(vs):.3f};"
          f" distance median {statistics.median(ds):.2f} m;"
          f" could stop in time {sum(1 for x in ms if x >= 0)}/{len(ms)}, margin min {min(ms):.2f} s")
