#!/usr/bin/env python3
# Usage: scripts/import-circles.py crates/splinegpu/src   (one crate's src folder)
"""Import circles among a crate's modules: file A imports B when it names crate::B (or, in a
child module, super::). Strongly connected components of more than one file are printed."""
import re, sys, os
root = sys.argv[1]
mods = {}
for dp, _, fs in os.walk(root):
    for f in fs:
        if f.endswith('.rs'):
            p = os.path.join(dp, f); rel = os.path.relpath(p, root)[:-3]
            rel = rel.replace('/mod', '') if rel.endswith('/mod') else rel
            mods[rel] = open(p).read()
names = set(mods)
edges = {m: set() for m in mods}
for m, s in mods.items():
    for path in re.findall(r'crate::((?:\w+::)*\w+)', s):
        parts = path.split('::')
        for i in range(len(parts), 0, -1):
            cand = '/'.join(parts[:i])
            if cand in names and cand != m:
                edges[m].add(cand); break
    for block in re.findall(r'use crate::\{([^;]*)\}', s, re.S):
        for item in re.findall(r'\b(\w+)\b', block):
            if item in names and item != m: edges[m].add(item)
    if '/' in m and re.search(r'\bsuper::', s):
        edges[m].add(m.rsplit('/', 1)[0])
# Tarjan
index, low, st, on, out = {}, {}, [], set(), []
sys.setrecursionlimit(10000)
def sc(v):
    index[v] = low[v] = len(index); st.append(v); on.add(v)
    for w in edges[v]:
        if w not in index: sc(w); low[v] = min(low[v], low[w])
        elif w in on: low[v] = min(low[v], index[w])
    if low[v] == index[v]:
        comp = []
        while True:
            w = st.pop(); on.discard(w); comp.append(w)
            if w == v: break
        if len(comp) > 1: out.append(sorted(comp))
for v in sorted(mods):
    if v not in index: sc(v)
for c in out: print('{' + ', '.join(c) + '}')
print(f'{len(out)} circles among {len(mods)} files')
