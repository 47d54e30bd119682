# planner HEALTH counter increments over the 2 s before each first at-fault contact
import json,sys,subprocess,glob,os
for root in sys.argv[1:]:
  for ep in sorted(glob.glob(root+'/failed/*/evade/*')):
    try: met=json.load(open(ep+'/run/metrics.json'))
    except: continue
    cs=[c for c in met.get('contacts',[]) if c['at_fault']]
    if not cs: continue
    ts=cs[0]['t_start_s']
    out=subprocess.run(['build/bin/lcmlog-export','--channel','HEALTH',ep+'/run/run.lcmlog'],capture_output=True,text=True).stdout
    hs=[json.loads(l)['msg'] for l in out.splitlines()]
    hs=[h for h in hs if h['name']=='planner']
    t0=hs[0]['utime']
    def at(t):
        best=None
        for h in hs:
            if (h['utime']-t0)/1e6<=t: best=h
        return {c['name']:c['value'] for c in best['counters']} if best else {}
    a=at(ts-2.0); b=at(ts+0.999)
    d={k:b[k]-a.get(k,0) for k in b if b[k]-a.get(k,0)>0 and k not in ('cycle_on_obstacles','cycle_on_odometry')}
    print(ep.split('/failed/')[1], ts, d)
