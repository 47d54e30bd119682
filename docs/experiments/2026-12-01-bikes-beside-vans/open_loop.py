# open_loop.py CONFIG OUTDIR LOG...: build/bin/perception-replay over each log with CONFIG
# (JSON per log in OUTDIR, reused when present), pooled: per object class the centre error,
# coverage and body coverage at steps 0, 10, 25 (weighted by class_n), the static-motion
# share, MOTA, identity switches per 100 track-s, walker ADE at 1 s. Run from the repository root.
# MOTA, switches, the static share and walker ADE pool as pool_perception does
# (lib/benchmark/benchmark_summary.h); the class figures are not pooled there.
import json, subprocess, sys, os, concurrent.futures as cf
cfg, outdir, logs = sys.argv[1], sys.argv[2], sys.argv[3:]
os.makedirs(outdir, exist_ok=True)
def run(log):
    name = os.path.relpath(log).replace('/', '_')
    out = os.path.join(outdir, name + '.json')
    if not os.path.exists(out):
        # a failed replay (a config this build refuses) stops here with its message
        subprocess.run(['build/bin/perception-replay', '--config', cfg, '--out', out, log], stdout=subprocess.DEVNULL,
                       check=True)
    return json.load(open(out))
with cf.ThreadPoolExecutor(2) as ex: ds = list(ex.map(run, logs))
def pool(key, cls, k):
    num = sum(d[key][cls][k] * d['class_n'][cls][k] for d in ds if cls in d.get('class_n', {}) and d['class_n'][cls][k] > 0)
    den = sum(d['class_n'][cls][k] for d in ds if cls in d.get('class_n', {}) and d['class_n'][cls][k] > 0)
    return num / den if den else float('nan'), den
res = {}
for cls in ('walker', 'bike', 'static'):
    for key in ('class_error_m', 'class_coverage', 'class_body_coverage'):
        for k in (0, 10, 25):
            v, n = pool(key, cls, k); res[f'{cls}.{key[6:]}[{k}]'] = round(v, 3)
    res[f'{cls}.n[10]'] = pool('class_error_m', cls, 10)[1]
tot = lambda k: sum(d[k] for d in ds)
res['static_moving_fraction'] = round(tot('static_moving_frames') / max(1, tot('static_track_frames')), 4)
res['mota'] = round(1 - (tot('misses') + tot('false_positives') + tot('id_switches')) / tot('objects'), 4)
res['id_sw_per_100s'] = round(100 * tot('id_switches') / tot('track_s'), 2)
ds2 = [d for d in ds if d['walker_ade_1s_m'] is not None]; wp = sum(d['walker_predictions'] for d in ds2)
res['walker_ade_1s'] = round(sum(d['walker_ade_1s_m'] * d['walker_predictions'] for d in ds2) / max(1, wp), 4)
print(json.dumps(res))
