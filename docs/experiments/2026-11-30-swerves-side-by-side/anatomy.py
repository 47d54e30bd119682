# anatomy.py DIAG.txt...: where a crowd cycle's Ceres iterations go (debug prints of plan_cycle,
# swerve_restarts, recover_chain's relaxed solve)
import sys
def cycles(path):
    out=[];cur={'sw':[],'el':[]}
    for l in open(path):
        if not l.startswith('DIAG'): continue
        f=l.split(); d=dict(x.split('=') for x in f[2:])
        if f[1]=='swerve': cur['sw'].append((int(d['its']),int(d['feas'])))
        elif f[1]=='elastic': cur['el'].append((int(d['its']),int(d['feas'])))
        else:
            d['sw']=cur['sw'];d['el']=cur['el'];out.append(d);cur={'sw':[],'el':[]}
    return out
print('| scene | cycles | hard failed | hard its (ok / failed, mean) | swerve solves (feasible) | elastic solves (feasible) | iterations: hard / swerves / elastic | top 5 % cycles: hard / swerves / elastic | cycle iterations p99 |')
print('|---|---|---|---|---|---|---|---|---|')
for p in sys.argv[1:]:
    c=cycles(p); n=len(c)
    ok=[x for x in c if x['hard_feas']=='1']; bad=[x for x in c if x['hard_feas']=='0']
    hs=sum(int(x['hard_its']) for x in c)
    sw=sum(s[0] for x in c for s in x['sw']); swn=sum(len(x['sw']) for x in c); swf=sum(s[1] for x in c for s in x['sw'])
    el=sum(e[0] for x in c for e in x['el']); eln=sum(len(x['el']) for x in c); elf=sum(e[1] for x in c for e in x['el'])
    tot=hs+sw+el
    big=sorted(c,key=lambda x:-int(x['total']))[:max(1,n//20)]
    bh=sum(int(x['hard_its']) for x in big); bs=sum(s[0] for x in big for s in x['sw']); be=sum(e[0] for x in big for e in x['el'])
    bt=bh+bs+be
    t=sorted(int(x['total']) for x in c)
    print(f"| {p.split('/')[-1]} | {n} | {len(bad)} | {sum(int(x['hard_its']) for x in ok)/max(1,len(ok)):.0f} / {sum(int(x['hard_its']) for x in bad)/max(1,len(bad)):.0f} | {swn} ({swf}) | {eln} ({elf}) | {100*hs/tot:.0f} / {100*sw/tot:.0f} / {100*el/tot:.0f} % | {100*bh/bt:.0f} / {100*bs/bt:.0f} / {100*be/bt:.0f} % | {t[int(0.99*n)]} |")
