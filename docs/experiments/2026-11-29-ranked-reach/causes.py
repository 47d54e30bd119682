#!/usr/bin/env python3
"""causes.py DIR... (run from the repository root after a build): for every contact at fault in the failed episodes of
benchmark DIRs, what the last 2 s before it looked like (contact.py's lines):
whether the obstacle's velocity turned by more than 90 deg, the plans'
statuses in the last second, the robot's speed, the nearest track."""
import json, math, os, re, subprocess, sys, glob
LINE = re.compile(r"\s*([\d.]+) st (\d+) v0 ([-\d.]+) robot \(([-\d.]+),([-\d.]+)\) v ([-\d.]+) yaw ([-\d.]+) \| obs \(([-\d.]+),([-\d.]+)\) v \(([-\d.]+),([-\d.]+)\) d ([-\d.]+) \| track (.*)")
NAMES = {0: "OK", 1: "FALLBACK", 2: "STOPPING", 6: "RECOVERING", 7: "BLOCKED"}
for d in sys.argv[1:]:
    for m in sorted(glob.glob(os.path.join(d, "failed/*/*/*/run/metrics.json"))):
        met = json.load(open(m))
        for c in met.get("contacts", []):
            if not c.get("at_fault"): continue
            log = os.path.join(os.path.dirname(m), "run.lcmlog")
            out = subprocess.run(["python3", "docs/experiments/2026-11-29-braking-point/contact.py", log, str(c["obstacle_id"]), str(c["t_start_s"])],
                                 capture_output=True, text=True).stdout
            rows = [LINE.match(l) for l in out.splitlines()]
            rows = [r for r in rows if r]
            if not rows: print(m, "no lines"); continue
            vs = [(float(r[10]), float(r[11])) for r in rows]
            turned = any(math.hypot(*a) > 0.2 and math.hypot(*b) > 0.2 and (a[0]*b[0]+a[1]*b[1]) < 0 for a in vs for b in vs)
            tc = float(c["t_start_s"])
            last = [r for r in rows if float(r[1]) >= tc - 1.0]
            st = {}
            for r in last: st[NAMES.get(int(r[2]), r[2])] = st.get(NAMES.get(int(r[2]), r[2]), 0) + 1
            fastest_robot = max(float(r[6]) for r in last) if last else float("nan")
            ob_speed = math.hypot(*vs[-1])
            tracks = rows[-1][13]
            ep = "/".join(m.split("/")[-6:-2])
            print(f"{os.path.basename(d.rstrip('/'))} {ep} obs {c['obstacle_id']} t {tc:.1f} robot {c['robot_speed_mps']:.2f} m/s (fastest in last 1 s {fastest_robot:.2f}) "
                  f"approach {c['approach_speed_mps']:.2f} | obstacle {ob_speed:.2f} m/s turned {turned} | statuses {st} | track {tracks}")
