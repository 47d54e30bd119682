# lateral.py LOG...: for every frame of a bike (a box moving at 1.5 m/s or more) within 8 m of the robot,
# the nearest published track within 1 m (OBSTACLE_PREDICTIONS step 0): its centre's and velocity's
# component across the bike's heading, + away from the robot (the truth has none), by range.
# Run from the repository root after a build.
import json, math, subprocess, sys
rows=[]
for log in sys.argv[1:]:
    out=subprocess.run(['build/bin/lcmlog-export','--channel','SIM_TRUTH','--channel','OBSTACLE_PREDICTIONS','--channel','ODOMETRY',log],capture_output=True,text=True).stdout
    truth=odo=None
    for line in out.splitlines():
        r=json.loads(line); m=r['msg']
        if r['channel']=='SIM_TRUTH': truth=m; continue
        if r['channel']=='ODOMETRY': odo=m; continue
        if truth is None or odo is None: continue
        dyaw=odo['yaw']-truth['yaw']; c,s=math.cos(dyaw),math.sin(dyaw)
        for o in truth['obstacles']:
            sp=math.hypot(o['vx'],o['vy'])
            if o['shape']!='box' or sp<1.5: continue
            rng=math.hypot(o['x']-truth['x'],o['y']-truth['y'])
            if rng>8: continue
            dx,dy=o['x']-truth['x'],o['y']-truth['y']
            ox,oy=odo['x']+c*dx-s*dy, odo['y']+s*dx+c*dy
            hx,hy=(o['vx']*c-o['vy']*s)/sp,(o['vx']*s+o['vy']*c)/sp   # heading in odom frame
            best=None
            for p in m['tracks']:
                d=math.hypot(p['x'][0]-ox,p['y'][0]-oy)
                if d<1.0 and (best is None or d<best[0]): best=(d,p)
            if best is None: continue
            p=best[1]
            # across-heading unit (left of heading)
            nx,ny=-hy,hx
            # sign so that + is away from the robot
            rx,ry=ox-odo['x'],oy-odo['y']
            sgn=1 if rx*nx+ry*ny>=0 else -1
            lat_c=sgn*((p['x'][0]-ox)*nx+(p['y'][0]-oy)*ny)
            lat_v=sgn*(p['vx']*nx+p['vy']*ny)
            rows.append((rng,lat_c,lat_v))
import statistics as st
for lo,hi in ((0,3),(3,5),(5,8)):
    sel=[r for r in rows if lo<=r[0]<hi]
    if not sel: continue
    print(f"range {lo}-{hi} m: frames {len(sel)}, centre across (+ away from robot) median {st.median(r[1] for r in sel):+.3f} m, velocity across median {st.median(r[2] for r in sel):+.3f} m/s, p10 {sorted(r[2] for r in sel)[len(sel)//10]:+.3f}, p90 {sorted(r[2] for r in sel)[9*len(sel)//10]:+.3f}")
