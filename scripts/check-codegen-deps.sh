#!/usr/bin/env bash
# Keeps compiler/codegen layered (docs/codegen.md, "Files and which may use
# which"): fails on any dependency circle between its files and on codegen
# including the runtime's implementation (runtime/src) rather than the C ABI
# headers. Reads the #include "..." lines only; run by ctest
# (codegen.dependencies) so CI catches a circle the day it is made.
#   scripts/check-codegen-deps.sh [repository root]   exit 0 clean, 1 not
set -euo pipefail
root="${1:-$(cd "$(dirname "$0")/.." && pwd)}"
exec /usr/bin/python3 - "$root" <<'PY'
# A file and its header are one unit (Foo.h + Foo.cpp = "Foo"): a circle
# through one file's header and another's source is a circle all the same,
# since neither can be built, read or tested without the other. Circles are
# the strongly connected components of more than one unit.
import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s*"([^"]+)"', re.M)


def unit_of(name):
    base = os.path.basename(name)
    for ext in (".h.in", ".h", ".cpp"):
        if base.endswith(ext):
            return base[: -len(ext)]
    return base


def main():
    root = os.path.abspath(sys.argv[1])
    codegen = os.path.join(root, "compiler", "codegen")
    runtime_src = os.path.join(root, "runtime", "src")
    runtime_src_names = set()
    for dirpath, _, files in os.walk(runtime_src):
        for f in files:
            rel = os.path.relpath(os.path.join(dirpath, f), runtime_src)
            runtime_src_names.add(rel)
    units = {}
    edges = {}
    problems = []
    for f in sorted(os.listdir(codegen)):
        if not f.endswith((".h", ".cpp", ".h.in")):
            continue
        u = unit_of(f)
        units.setdefault(u, []).append(f)
        edges.setdefault(u, set())
        text = open(os.path.join(codegen, f), encoding="utf-8").read()
        for inc in INCLUDE.findall(text):
            if inc.startswith("codegen/"):
                target = inc[len("codegen/"):]
                if (os.path.exists(os.path.join(codegen, target)) or
                        target == "EmbeddedText.h"):
                    v = unit_of(target)
                    if v != u:
                        edges[u].add(v)
                    continue
            if "runtime/src" in inc or (inc in runtime_src_names and
                                        not inc.startswith(("ldae/", "codegen/"))):
                problems.append(
                    f"compiler/codegen/{f}: includes '{inc}' from runtime/src "
                    "(codegen may use the C ABI headers only)")
    # Tarjan's strongly connected components, in a fixed order.
    index, low, on_stack, stack, sccs = {}, {}, set(), [], []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on_stack.add(v)
        for w in sorted(edges.get(v, ())):
            if w not in edges:
                continue
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on_stack:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            comp = []
            while True:
                w = stack.pop()
                on_stack.discard(w)
                comp.append(w)
                if w == v:
                    break
            sccs.append(sorted(comp))

    sys.setrecursionlimit(10000)
    for v in sorted(edges):
        if v not in index:
            visit(v)
    for comp in sccs:
        if len(comp) > 1:
            detail = "; ".join(
                f"{a} -> {b}" for a in comp for b in sorted(edges[a]) if b in comp)
            problems.append("compiler/codegen: dependency circle between "
                            + ", ".join(comp) + " (" + detail + ")")
    for p in problems:
        print("check-codegen-deps: error: " + p)
    if not problems:
        print(f"check-codegen-deps: {len(units)} units of compiler/codegen, "
              "no circle, no runtime/src include")
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
PY
