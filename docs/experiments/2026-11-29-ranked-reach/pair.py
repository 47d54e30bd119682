#!/usr/bin/env python3
"""Pair benchmark rows (results.jsonl) by (family, seed, mode): before -> after per family.

pair.py NEW.jsonl... --base BASE.jsonl...  (one robot per call: rows carry no robot name)
Success with the Wilson 95 % interval of the new rows; "contact not at fault"
counts episodes with a contact and none at fault.
"""
import argparse, json, math, statistics, collections

def load(paths):
    rows = {}
    for p in paths:
        for line in open(p):
            r = json.loads(line)
            rows[(r["family"], r["seed"], r["mode"])] = r
    return rows

def wilson(k, n, z=1.96):
    if n == 0: return (0, 0)
    p = k / n; d = 1 + z * z / n
    c = (p + z * z / (2 * n)) / d; h = z * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n)) / d
    return (max(0, c - h), min(1, c + h))

def outcome(r):
    if r["success"]: return "success"
    if r["at_fault"]: return "at_fault"
    if r["timed_out"]: return "timeout"
    if r["collided"]: return "contact"
    return "fail"

def stats(rs):
    n = len(rs)
    return dict(n=n, succ=sum(r["success"] for r in rs), fault=sum(bool(r["at_fault"]) for r in rs),
                cnf=sum(1 for r in rs if r["collided"] and not r["at_fault"]),
                to=sum(bool(r["timed_out"]) for r in rs),
                md=statistics.median([r["min_dist_m"] for r in rs if r["min_dist_m"] is not None] or [float("nan")]),
                tt=statistics.median([r["time_to_goal_s"] for r in rs if r["time_to_goal_s"] is not None] or [float("nan")]))

ap = argparse.ArgumentParser()
ap.add_argument("new", nargs="+")
ap.add_argument("--base", nargs="+", required=True)
a = ap.parse_args()
B, N = load(a.base), load(a.new)
keys = sorted(set(B) & set(N))
missing = sorted(set(N) - set(B))
fams = sorted({k[0] for k in keys})
print("| family | n | success | at fault | contact not at fault | timeouts | median least distance (m) | median time (s) | outcomes changed |")
print("|---|---|---|---|---|---|---|---|---|")
changed = []
for fam in fams + ["all"]:
    ks = [k for k in keys if fam == "all" or k[0] == fam]
    b, n = stats([B[k] for k in ks]), stats([N[k] for k in ks])
    lo, hi = wilson(n["succ"], n["n"])
    ch = sum(outcome(B[k]) != outcome(N[k]) for k in ks)
    print(f"| {fam} | {n['n']} | {b['succ']} -> {n['succ']} ({100*lo:.0f}-{100*hi:.0f} %) | {b['fault']} -> {n['fault']} | "
          f"{b['cnf']} -> {n['cnf']} | {b['to']} -> {n['to']} | {b['md']:.2f} -> {n['md']:.2f} | {b['tt']:.1f} -> {n['tt']:.1f} | {ch} |")
    if fam == "all":
        changed = [f"{k[0]} {k[1]}: {outcome(B[k])} -> {outcome(N[k])}" for k in ks if outcome(B[k]) != outcome(N[k])]
print("\noutcomes changed (before -> after):")
for line in changed:
    print("  " + line)
if missing:
    print("unpaired:", missing)
