import json,sys,subprocess,statistics
# python3 docs/experiments/2026-12-02-brake-ahead/decel.py LOG... (from the source root): over every PLAN whose first two steps brake at the limit
# (v0 - v1 >= 0.149) with the robot above 0.2 m/s, the robot's true
# deceleration (SIM_TRUTH) over the 0.1 s after the plan was sent.
for f in sys.argv[1:]:
    out=subprocess.run(['build/bin/lcmlog-export',f,'--channel','SIM_TRUTH','--channel','PLAN'],capture_output=True,text=True).stdout
    truth=[]; plans=[]
    for l in out.splitlines():
        r=json.loads(l); m=r['msg']
        if r['channel']=='SIM_TRUTH': truth.append((r['utime'],m['v']))
        else: plans.append((r['utime'],m['v']))
    import bisect
    ts=[t for t,_ in truth]
    d=[]
    for t,v in plans:
        if len(v)<2 or v[0]-v[1]<0.149: continue
        i=bisect.bisect_left(ts,t); j=bisect.bisect_left(ts,t+100000)
        if j>=len(ts) or truth[i][1]<0.2: continue
        d.append((truth[i][1]-truth[j][1])/((ts[j]-ts[i])/1e6))
    print(f, 'plans braking at the limit', len(d), 'decel median %.2f mean %.2f p10 %.2f' % (statistics.median(d), statistics.mean(d), sorted(d)[len(d)//10]) if d else '')
