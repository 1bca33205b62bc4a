#!/usr/bin/env python3
# SPDX-License-Identifier: MIT
"""The layer check of Documentation/architecture.rst.

Reads the layer table from architecture.rst (between the comments
``.. layer table begin`` and ``.. layer table end``: one row per layer,
bottom first, the layer's name and then the folders and files it owns),
maps every source file of lib/ and include/ecmxf/ to its layer and checks:

1. every file belongs to a layer;
2. every #include of a project header points to the same layer or one
   below it (a back-arrow is an error naming the file, the line and both
   layers);
3. the include graph between the folders of lib/ and include/ecmxf/ has no
   cycle (the count is printed, and must be 0);
4. no downcast of a link or byte channel outside lib/link/
   (dynamic_cast/static_cast to a *Link or *Channel type);
5. ioctl() and mmap() only where architecture.rst allows them (the rows
   ``.. syscall <name> <file>...`` of the same page).

Usage: check-layers.py [--root DIR] [--quiet]. Exit status 0 when all
hold, 1 with one line per violation otherwise, 2 when the table cannot be
read. The build runs it before compiling the library (lib/CMakeLists.txt)
and make check runs it as the ctest "layers".
"""

import argparse
import os
import re
import sys

SOURCE_SUFFIXES = (".c", ".h", ".cpp", ".hpp")
INCLUDE_RE = re.compile(r'^\s*#\s*include\s*([<"])([^>"]+)[>"]')
DOWNCAST_RE = re.compile(
    r"\b(dynamic|static|reinterpret)_cast\s*<\s*(const\s+)?([\w:]*?)(\w*(Link|Channel))\s*[*&]")
SYSCALL_RE = re.compile(r"(?<![\w.>])(?:::)?(ioctl|mmap)\s*\(")


def fail_table(msg):
    print(f"check-layers: {msg}", file=sys.stderr)
    sys.exit(2)


def read_table(doc):
    """The layer rows and the syscall rows of architecture.rst."""
    try:
        text = open(doc, encoding="utf-8").read().splitlines()
    except OSError as e:
        fail_table(f"cannot read {doc}: {e.strerror}")
    layers = []
    syscalls = {}
    inside = False
    for n, line in enumerate(text, 1):
        s = line.strip()
        if s == ".. layer table begin":
            inside = True
            continue
        if s == ".. layer table end":
            inside = False
            continue
        m = re.match(r"^\.\. syscall (\w+) (.+)$", s)
        if m:
            syscalls.setdefault(m.group(1), []).extend(m.group(2).split())
            continue
        if not inside or not s or s.startswith(("layer ", "====", "::", "---")):
            continue
        parts = s.split()
        if len(parts) < 2:
            fail_table(f"{doc}:{n}: a layer row needs a name and at least one folder")
        layers.append((parts[0], [p.rstrip("/") for p in parts[1:]], n))
    if not layers:
        fail_table(f"{doc}: no layer table (.. layer table begin / end)")
    return layers, syscalls


def source_files(root):
    out = []
    for top in ("lib", "include/ecmxf"):
        for dp, dn, fn in os.walk(os.path.join(root, top)):
            dn.sort()
            for f in sorted(fn):
                if f.endswith(SOURCE_SUFFIXES):
                    out.append(os.path.relpath(os.path.join(dp, f), root))
    return out


def owner(path, layers):
    """(layer index, layer name) of the longest table entry that owns path."""
    best = None
    for i, (name, paths, _) in enumerate(layers):
        for p in paths:
            if path == p or path.startswith(p + "/"):
                if best is None or len(p) > best[2]:
                    best = (i, name, len(p))
    return best


def folder(path):
    """The folder node of the folder graph: lib/X or include/ecmxf/X."""
    parts = path.split("/")
    if parts[0] == "lib":
        return "lib/" + parts[1] if len(parts) > 2 else "lib"
    if len(parts) > 3:
        return "include/ecmxf/" + parts[2]
    return path  # a header at the top of include/ecmxf/ is a node of its own


def resolve(root, src, quote, name):
    cands = []
    if name.startswith("ecmxf/"):
        cands.append(os.path.join("include", name))
    if quote == '"':
        cands.append(os.path.normpath(os.path.join(os.path.dirname(src), name)))
    cands += [os.path.join("lib", name), os.path.join("lib/core", name), os.path.join("lib/sim", name)]
    for c in cands:
        c = os.path.normpath(c)
        if os.path.isfile(os.path.join(root, c)) and (c.startswith("lib/") or c.startswith("include/ecmxf/")):
            return c
    return None


def cycles(graph):
    """Strongly connected components with more than one node (Tarjan)."""
    index, low, stack, on, out = {}, {}, [], set(), []
    counter = [0]

    def visit(v):
        index[v] = low[v] = counter[0]
        counter[0] += 1
        stack.append(v)
        on.add(v)
        for w in sorted(graph.get(v, ())):
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
            if len(comp) > 1:
                out.append(sorted(comp))

    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def strip_comments(line, in_block):
    """The code of one line without // and /* */ comments or strings."""
    out = []
    i = 0
    while i < len(line):
        if in_block:
            j = line.find("*/", i)
            if j < 0:
                return "".join(out), True
            i = j + 2
            in_block = False
            continue
        if line.startswith("//", i):
            break
        if line.startswith("/*", i):
            in_block = True
            i += 2
            continue
        if line[i] == '"':
            j = i + 1
            while j < len(line) and line[j] != '"':
                j += 2 if line[j] == "\\" else 1
            out.append('""')
            i = j + 1
            continue
        out.append(line[i])
        i += 1
    return "".join(out), in_block


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--root", default=os.path.join(os.path.dirname(os.path.abspath(__file__)), ".."))
    ap.add_argument("--quiet", action="store_true", help="print only violations")
    args = ap.parse_args()
    root = os.path.abspath(args.root)
    doc = os.path.join(root, "Documentation/architecture.rst")
    layers, syscalls = read_table(doc)
    names = [l[0] for l in layers]
    if len(set(names)) != len(names):
        fail_table(f"{doc}: a layer is named twice")

    errors = []
    edges = 0
    fgraph = {}
    files = source_files(root)
    for f in files:
        o = owner(f, layers)
        if o is None:
            errors.append(f"{f}: in no layer of Documentation/architecture.rst's table")
            continue
        fi, fname, _ = o
        in_block = False
        with open(os.path.join(root, f), encoding="utf-8", errors="replace") as fh:
            for n, line in enumerate(fh, 1):
                m = INCLUDE_RE.match(line)
                if m:
                    dst = resolve(root, f, m.group(1), m.group(2))
                    if dst is None:
                        continue
                    d = owner(dst, layers)
                    if d is None:
                        continue
                    edges += 1
                    if folder(f) != folder(dst):
                        fgraph.setdefault(folder(f), set()).add(folder(dst))
                    if d[0] > fi:
                        errors.append(f"{f}:{n}: back-arrow: layer '{fname}' includes {dst} "
                                      f"of layer '{d[1]}', which is above it")
                    continue
                code, in_block = strip_comments(line, in_block)
                if not f.startswith("lib/link/"):
                    c = DOWNCAST_RE.search(code)
                    if c:
                        errors.append(f"{f}:{n}: downcast to {c.group(4)} outside lib/link/ "
                                      "(ask the link for a capability instead)")
                for s in SYSCALL_RE.finditer(code):
                    allowed = syscalls.get(s.group(1), [])
                    if f not in allowed and not f.startswith("lib/core/"):
                        errors.append(f"{f}:{n}: {s.group(1)}() outside {', '.join(allowed) or 'the allowed files'}")

    cyc = cycles(fgraph)
    for c in cyc:
        errors.append("include cycle between folders: " + " <-> ".join(c))
    for e in errors:
        print(e)
    if not args.quiet or errors:
        print(f"check-layers: {len(layers)} layers ({' < '.join(names)}), {len(files)} files, "
              f"{edges} project includes, {len(cyc)} cycles between folders, {len(errors)} violations")
    return 1 if errors else 0


if __name__ == "__main__":
    sys.exit(main())
