# summary2.py ANATOMY.json... : one row per contact at fault from anatomy2.py's
# --json output: the obstacle, when its track first entered the plans, the
# plans of the last 2 s by kind, the last plan judged clear (and by how much,
# how far ahead), and the prediction's centre error at the meeting.
import collections, json, sys
print('| episode | obstacle | speed (m/s) | turned | tracked before | sent, last 2 s | last judged clear: t, status, kind, clearance at ahead | centre error there | truth along it |')
print('|---|---|---|---|---|---|---|---|---|')
for f in sys.argv[1:]:
    for a in json.load(open(f)):
        ep = ' '.join(a['episode'].rstrip('/').split('/')[-3::2])
        tag = '%s%s' % ('scout ' if '/scout/' in a['episode'] else '', ep)
        ps = a['plans']
        seen = [p for p in ps if p['judge']]
        first = -seen[0]['t'] if seen else 0
        kinds = collections.Counter()
        for p in ps:
            k = p['kind'].split(' ')[0]
            kinds[{'solved': 'OK', 'on': 'on', 'pull-over': 'pull', 'brake': 'brake', 'stand': 'stand'}.get(k, k)] += 1
        ks = ' '.join('%s %d' % kv for kv in sorted(kinds.items(), key=lambda kv: -kv[1]))
        clear = [p for p in seen if p['judge']['judged'] >= 0 and p['status'] != 'OK']
        if clear:
            p = clear[-1]; j = p['judge']
            lc = '%+.2f s %s %s, %+.2f m at %.1f s' % (p['t'], p['status'][:4], p['kind'], j['judged'], j['judged_k'] * 0.1)
            ce = '%.2f m' % j['err']
            tr = '%+.2f m at %.1f s' % (j['real'], j['real_k'] * 0.1)
        else:
            lc, ce, tr = 'none (every recovery plan judged a contact)', '', ''
        print('| %s | %s | %.1f | %s | %s | %s | %s | %s | %s |' % (
            tag, a['shape'] or '?', a['obs_speed'], 'yes' if a['turned'] > 0.5 else 'no',
            '%.1f s' % first if seen and first < 1.95 else '>= 2 s', ks, lc, ce, tr))
