# lateral.py LOG...: for every frame of a bike (a box moving at 1.5 m/s or more) within 8 m of the robot,
# the nearest published track within 1 m (OBSTACLE_PREDICTIONS step 0): its centre's and velocity's
# component across the bike's heading, + away from the robot (the truth has none), by range.
# Run from the repository root after a build; the frames are bike_speed.py's bike_frames().
import math, os, statistics as st, sys
sys.dont_write_bytecode = True  # no __pycache__ beside the pages
sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', '2026-12-01-bikes-beside-vans'))
from bike_speed import bike_frames

rows = []
for log in sys.argv[1:]:
    for _, truth, odo, _, (c, s), bikes in bike_frames(log):
        for o, (ox, oy), p in bikes:
            if p is None: continue
            sp = math.hypot(o['vx'], o['vy'])
            rng = math.hypot(o['x'] - truth['x'], o['y'] - truth['y'])
            hx, hy = (o['vx']*c - o['vy']*s) / sp, (o['vx']*s + o['vy']*c) / sp  # heading in the odometry frame
            nx, ny = -hy, hx  # across the heading, to its left
            sgn = 1 if (ox - odo['x'])*nx + (oy - odo['y'])*ny >= 0 else -1  # + away from the robot
            lat_c = sgn * ((p['x'][0] - ox)*nx + (p['y'][0] - oy)*ny)
            lat_v = sgn * (p['vx']*nx + p['vy']*ny)
            rows.append((rng, lat_c, lat_v))
for lo, hi in ((0, 3), (3, 5), (5, 8)):
    sel = [r for r in rows if lo <= r[0] < hi]
    if not sel: continue
    v = sorted(r[2] for r in sel)
    print(f"range {lo}-{hi} m: frames {len(sel)}, centre across (+ away from robot) median {st.median(r[1] for r in sel):+.3f} m, velocity across median {st.median(v):+.3f} m/s, p10 {v[len(v)//10]:+.3f}, p90 {v[9*len(v)//10]:+.3f}")
