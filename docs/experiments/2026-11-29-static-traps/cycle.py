#!/usr/bin/env python3
# cycle.py [--bin DIR] RUN.lcmlog T: the PLAN at T s after the log's first PLAN and the
# OBSTACLE_PREDICTIONS list it was made from (PLAN.predictions_utime). Per track in the
# plan's constraints: centre, raw axes (a - sigma), the inflation sigma at steps 0, 1, 2, 5
# and N, predicted speed and displacement over the horizon, the robot centre's distance to
# the edge of the raw ellipse, of step 0's and of step N's (sampled; negative inside), and
# the constraint's slack (PLAN.obstacle_slack; id -1 the static field).
# Needs build/bin/lcmlog-export (--bin).
import json, math, subprocess, sys
args = sys.argv[1:]
bindir = 'build/bin'
if args[0] == '--bin': bindir = args[1]; args = args[2:]
log, T = args[0], float(args[1])
BIN = bindir + '/lcmlog-export'
def export(chs):
    cmd=[BIN]
    for c in chs: cmd+=['--channel',c]
    p=subprocess.run(cmd+[log],capture_output=True,text=True)
    for l in p.stdout.splitlines(): yield json.loads(l)
plans=[]; preds={}
t0=None
for r in export(['PLAN','OBSTACLE_PREDICTIONS']):
    m=r['msg']
    if r['channel']=='PLAN':
        if t0 is None: t0=m['utime']
        if abs((m['utime']-t0)/1e6-T)<0.06: plans.append(m)
    else: preds[m['utime']]=m
def edge_dist(px,py,cx,cy,a,b,th):
    # min distance from point to ellipse boundary (negative inside), sampled
    best=1e9
    c,s=math.cos(th),math.sin(th)
    lx=(px-cx)*c+(py-cy)*s; ly=-(px-cx)*s+(py-cy)*c
    inside=(lx/a)**2+(ly/b)**2<1
    for i in range(720):
        t=2*math.pi*i/720; ex=a*math.cos(t); ey=b*math.sin(t)
        best=min(best,math.hypot(lx-ex,ly-ey))
    return -best if inside else best
ST={0:'OK',1:'FALL',2:'STOP',3:'STALE',4:'NOROUTE',5:'GOAL',6:'RECO',7:'BLOC'}
for p in plans[:1]:
    print('plan t=%.2f status %s x %.2f y %.2f yaw %.0f v0 %.2f w0 %.2f  end (%.2f,%.2f) iters %d maxviol %.3f'%((p['utime']-t0)/1e6,ST[p['status']],p['x'][0],p['y'][0],math.degrees(p['yaw'][0]),p['v'][0],p['omega'][0],p['x'][-1],p['y'][-1],p['iterations'],p['max_violation']))
    pl=preds.get(p['predictions_utime'])
    if not pl: print('no prediction list'); continue
    tr={t['id']:t for t in pl['tracks']}
    for i,oid in enumerate(p['obstacle_id']):
        if oid<0: print('  id -1 static field slack %.3f'%p['obstacle_slack'][i]); continue
        t=tr.get(oid)
        if not t: print('  id',oid,'not in list'); continue
        sg=t['sigma']; N=len(sg)-1
        sp=math.hypot(t['vx'],t['vy'])
        d0=edge_dist(p['x'][0],p['y'][0],t['x'][0],t['y'][0],t['a'][0],t['b'][0],t['theta'][0])
        dN=edge_dist(p['x'][0],p['y'][0],t['x'][N],t['y'][N],t['a'][N],t['b'][N],t['theta'][N])
        draw=edge_dist(p['x'][0],p['y'][0],t['x'][0],t['y'][0],t['a'][0]-sg[0],t['b'][0]-sg[0],t['theta'][0])
        print('  id %3d c (%.2f,%.2f) raw a %.2f b %.2f sigma k0 %.2f k1 %.2f k2 %.2f k5 %.2f kN %.2f speed %.3f moved %.2f | robot-centre to edge: raw %.2f k0 %.2f kN %.2f | slack %.3f'%(
            oid,t['x'][0],t['y'][0],t['a'][0]-sg[0],t['b'][0]-sg[0],sg[0],sg[1],sg[2],sg[5],sg[N],sp,math.hypot(t['x'][N]-t['x'][0],t['y'][N]-t['y'][0]),draw,d0,dN,p['obstacle_slack'][i]))
