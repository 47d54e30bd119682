#!/usr/bin/env python3
"""causes.py DIR... (run from the repository root after a build): for every contact at fault in the failed episodes of
benchmark DIRs, what the last 2 s before it looked like (contact.py's records; each log exported once):
whether the obstacle's velocity turned by more than 90 deg, the plans'
statuses in the last second, the robot's speed, the nearest track."""
import importlib.util, json, math, os, sys, glob
spec = importlib.util.spec_from_file_location("contact", "docs/experiments/2026-11-29-braking-point/contact.py")
contact = importlib.util.module_from_spec(spec)
spec.loader.exec_module(contact)
NAMES = {0: "OK", 1: "FALLBACK", 2: "STOPPING", 6: "RECOVERING", 7: "BLOCKED"}
for d in sys.argv[1:]:
    for m in sorted(glob.glob(os.path.join(d, "failed/*/*/*/run/metrics.json"))):
        met = json.load(open(m))
        at_fault = [c for c in met.get("contacts", []) if c.get("at_fault")]
        if not at_fault: continue
        rows = contact.export(os.path.join(os.path.dirname(m), "run.lcmlog"))
        for c in at_fault:
            ws = list(contact.window(rows, c["obstacle_id"], float(c["t_start_s"])))
            if not ws: print(m, "no lines"); continue
            vs = [(round(w["obs"]["vx"], 2), round(w["obs"]["vy"], 2)) for w in ws]
            turned = any(math.hypot(*a) > 0.2 and math.hypot(*b) > 0.2 and (a[0]*b[0]+a[1]*b[1]) < 0 for a in vs for b in vs)
            tc = float(c["t_start_s"])
            last = [w for w in ws if round(w["t"], 2) >= tc - 1.0]
            st = {}
            for w in last: st[NAMES.get(w["status"], str(w["status"]))] = st.get(NAMES.get(w["status"], str(w["status"])), 0) + 1
            fastest_robot = max(round(w["truth"]["v"], 2) for w in last) if last else float("nan")
            ob_speed = math.hypot(*vs[-1])
            ep = "/".join(m.split("/")[-6:-2])
            print(f"{os.path.basename(d.rstrip('/'))} {ep} obs {c['obstacle_id']} t {tc:.1f} robot {c['robot_speed_mps']:.2f} m/s (fastest in last 1 s {fastest_robot:.2f}) "
                  f"approach {c['approach_speed_mps']:.2f} | obstacle {ob_speed:.2f} m/s turned {turned} | statuses {st} | track {ws[-1]['track']}")
