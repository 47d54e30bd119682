# For every at-fault contact in a benchmark's failed episodes: the planner's
# status over the 2 s before it, the robot's speed then, and whether the
# obstacle changed velocity (a scripted turn) within 2 s before the contact.
import json,sys,subprocess,math,os,glob,collections
names={0:'OK',1:'FALLBACK',2:'STOPPING',3:'STALE',4:'NOROUTE',5:'GOAL',6:'RECOVERING',7:'BLOCKED'}
def analyse(ep):
    met=json.load(open(ep+'/run/metrics.json'))
    cs=[c for c in met.get('contacts',[]) if c['at_fault']]
    if not cs: return []
    out=subprocess.run(['build/bin/lcmlog-export','--channel','SIM_TRUTH','--channel','PLAN',ep+'/run/run.lcmlog'],capture_output=True,text=True).stdout
    truth=[];plans=[];t0=None
    for line in out.splitlines():
        r=json.loads(line);m=r['msg']
        if r['channel']=='SIM_TRUTH':
            if t0 is None:t0=m['utime']
            truth.append(((m['utime']-t0)/1e6,m))
        else: plans.append((m['utime'],m['status']))
    res=[]
    for c in cs[:1]:
        ts=c['t_start_s']; oid=c['obstacle_id']
        st=collections.Counter(); 
        for u,s in plans:
            t=(u-t0)/1e6
            if ts-2.0<=t<=ts: st[names.get(s,s)]+=1
        vel=[(t,[o for o in m['obstacles'] if o['id']==oid][0]) for t,m in truth if ts-2.0<=t<=ts]
        turned=any(math.hypot(a[1]['vx']-b[1]['vx'],a[1]['vy']-b[1]['vy'])>0.5 for a,b in zip(vel,vel[1:]))
        res.append((ep.split('/failed/')[1],round(ts,2),c['robot_speed_mps'],dict(st),turned))
    return res
for root in sys.argv[1:]:
    for ep in sorted(glob.glob(root+'/failed/*/evade/*')):
        if os.path.exists(ep+'/run/metrics.json'):
            for r in analyse(ep): print(*r)
