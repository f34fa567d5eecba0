#!/usr/bin/env python3
"""Checks that the files of a module call each other downwards only (no circle of calls).

    scripts/floors.py OBJDIR [OBJDIR ...] [--show]

Reads the object files (*.o) under each OBJDIR with `nm`, links each undefined symbol to the
object that defines it, and looks for cycles in that file-level call graph. Prints the floors
(bottom first: each file calls only files on floors below it) and exits 0, or prints each
circle found and exits 1. The test suite runs it over core/, server/ and client/ (DESIGN.md section 2,
"the server as it grows").
"""
import os
import subprocess
import sys


def symbols(obj):
    out = subprocess.run(["nm", "-P", obj], check=True, capture_output=True, text=True).stdout
    defined, undefined = set(), set()
    for line in out.splitlines():
        parts = line.split()
        if len(parts) < 2:
            continue
        name, kind = parts[0], parts[1]
        if kind in "TDBR":  # global text, data, bss, read-only data
            defined.add(name)
        elif kind == "U":
            undefined.add(name)
    return defined, undefined


def short(obj):
    base = os.path.basename(obj)
    return base[:-2] if base.endswith(".o") else base


def main(argv):
    show = "--show" in argv
    dirs = [a for a in argv if not a.startswith("--")]
    if not dirs:
        print(__doc__.strip(), file=sys.stderr)
        return 64
    objs = []
    for d in dirs:
        for root, _, files in os.walk(d):
            objs += [os.path.join(root, f) for f in files if f.endswith(".o")]
    if not objs:
        print(f"floors: no object files under {' '.join(dirs)} (build first)", file=sys.stderr)
        return 66
    owner, needs = {}, {}
    for o in sorted(objs):
        name = short(o)
        d, u = symbols(o)
        for s in d:
            owner.setdefault(s, name)
        needs[name] = needs.get(name, set()) | u
    calls = {n: sorted({owner[s] for s in u if s in owner and owner[s] != n}) for n, u in needs.items()}

    # Tarjan's strongly connected components: a component of more than one file is a circle.
    index, low, stack, on, comps = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in calls[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on.discard(w)
                comp.append(w)
                if w == v:
                    break
            comps.append(comp)

    sys.setrecursionlimit(10000)
    for v in sorted(calls):
        if v not in index:
            visit(v)
    circles = [sorted(c) for c in comps if len(c) > 1]
    if circles:
        for c in circles:
            print("floors: these files call each other in a circle: " + ", ".join(c))
            for a in c:
                up = [b for b in calls[a] if b in c]
                syms = sorted(s for s in needs[a] if owner.get(s) in up)
                print(f"  {a} -> {', '.join(up)}  ({', '.join(syms[:6])}{' ...' if len(syms) > 6 else ''})")
        return 1
    floor = {}

    def level(v):
        if v not in floor:
            floor[v] = 1 + max((level(w) for w in calls[v]), default=-1)
        return floor[v]

    for v in calls:
        level(v)
    top = max(floor.values())
    for f in range(top + 1):
        names = sorted(v for v in floor if floor[v] == f)
        print(f"floor {f}: {' '.join(names)}")
        if show:
            for v in names:
                print(f"    {v} -> {' '.join(calls[v]) or '-'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
