#!/usr/bin/env python3
"""The code-shape numbers issue 31 measures, on the source (tests excluded): files over
800 lines, functions over 120 lines, `too_many_arguments` allowances, each crate's size,
and import circles between a crate's top-level modules (a module that names another
through `crate::`, which names it back, directly or around a longer circle).
Usage: python3 scripts/shape.py [--all]"""
import os, re, sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "crates")
FN = re.compile(r"^\s*(pub(\([^)]*\))?\s+)?(const\s+)?(async\s+)?(unsafe\s+)?fn\s+(\w+)")


PYTHON = os.path.join(ROOT, "..", "python")


def source_files():
    crates = [(c, os.path.join(ROOT, c, "src")) for c in sorted(os.listdir(ROOT))]
    # The Python binding is a crate too (`python/src`, crate tabula-py).
    for crate, src in crates + [("tabula-py", os.path.join(PYTHON, "src"))]:
        for dirpath, _, files in os.walk(src):
            for f in sorted(files):
                if f.endswith(".rs") and f != "tests.rs":
                    yield crate, os.path.join(dirpath, f)


def strip_tests(lines):
    """Lines before a `#[cfg(test)]` module."""
    for i, l in enumerate(lines):
        if l.startswith("#[cfg(test)]"):
            return lines[:i]
    return lines


def functions(lines):
    """(name, first line, length) of every fn with a body, by brace counting."""
    out = []
    for i, l in enumerate(lines):
        m = FN.match(l)
        if not m:
            continue
        depth, started = 0, False
        for j in range(i, len(lines)):
            code = re.sub(r'"(\\.|[^"\\])*"', '""', lines[j].split("//")[0])
            if not started and ";" in code and "{" not in code:
                break
            depth += code.count("{") - code.count("}")
            started = started or "{" in code
            if started and depth <= 0:
                out.append((m.group(6), i + 1, j - i + 1))
                break
    return out


CRATE_PATH = re.compile(r"\bcrate::(\{[^}]*\}|\w+)")


def top_module(crate, path):
    """The top-level module a source file belongs to (`None`: the crate root)."""
    rel = os.path.relpath(path, os.path.join(ROOT, crate, "src")).split(os.sep)
    if len(rel) == 1:
        name = rel[0][:-3]
        return None if name in ("lib", "main") else name
    return rel[0]


def root_reexports(crate):
    """Names the crate root re-exports (`pub use module::{A, B}`), by the module they
    come from: `crate::A` is a path into that module."""
    out = {}
    for root in ("lib.rs", "main.rs"):
        path = os.path.join(ROOT, crate, "src", root)
        if not os.path.exists(path):
            continue
        text = open(path).read()
        for m in re.finditer(r"pub use (\w+)::(\{[^}]*\}|[\w:]+)\s*;", text):
            names = re.findall(r"(\w+)\s*(?:[,}]|$)", m.group(2).strip("{}") + ",")
            for n in names:
                out[n.split("::")[-1]] = m.group(1)
    return out


def circles():
    """Per crate, the strongly connected groups (more than one module) of the graph of
    top-level modules and the `crate::` paths between them (re-exports followed)."""
    edges, modules, reexports = {}, {}, {}
    for crate, path in source_files():
        me = top_module(crate, path)
        if me is None:
            continue
        modules.setdefault(crate, set()).add(me)
        if crate not in reexports:
            reexports[crate] = root_reexports(crate)
        text = "\n".join(strip_tests(open(path).read().split("\n")))
        text = re.sub(r"//.*", "", text)
        for m in CRATE_PATH.finditer(text):
            names = re.findall(r"(?:^|[{,\s])(\w+)", m.group(1).strip("{}")) if m.group(1).startswith("{") else [m.group(1)]
            for n in names:
                n = reexports[crate].get(n, n)
                if n != me:
                    edges.setdefault(crate, {}).setdefault(me, set()).add(n)
    out = {}
    for crate, mods in modules.items():
        graph = {m: {n for n in edges.get(crate, {}).get(m, ()) if n in mods} for m in mods}
        index, low, stack, on, groups = {}, {}, [], set(), []

        def visit(v):
            index[v] = low[v] = len(index)
            stack.append(v)
            on.add(v)
            for w in sorted(graph[v]):
                if w not in index:
                    visit(w)
                    low[v] = min(low[v], low[w])
                elif w in on:
                    low[v] = min(low[v], index[w])
            if low[v] == index[v]:
                group = []
                while True:
                    w = stack.pop()
                    on.discard(w)
                    group.append(w)
                    if w == v:
                        break
                if len(group) > 1:
                    groups.append(sorted(group))

        for m in sorted(mods):
            if m not in index:
                visit(m)
        if groups:
            out[crate] = groups
    return out


def main():
    show_all = "--all" in sys.argv
    big_files, long_fns, allowances, per_crate = [], [], 0, {}
    for crate, path in source_files():
        lines = strip_tests(open(path).read().split("\n"))
        per_crate[crate] = per_crate.get(crate, 0) + len(lines)
        rel = os.path.relpath(path, os.path.join(ROOT, ".."))
        if len(lines) > 800:
            big_files.append((len(lines), rel))
        allowances += sum("too_many_arguments" in l for l in lines)
        for name, line, n in functions(lines):
            if n > 120:
                long_fns.append((n, f"{rel}:{line} {name}"))
    print(f"files over 800 lines: {len(big_files)}")
    for n, f in sorted(big_files, reverse=True):
        print(f"  {n:5} {f}")
    print(f"functions over 120 lines: {len(long_fns)}")
    for n, f in sorted(long_fns, reverse=True)[: None if show_all else 15]:
        print(f"  {n:5} {f}")
    print(f"too_many_arguments allowances: {allowances}")
    for crate, n in sorted(per_crate.items()):
        print(f"  {crate}: {n} lines")
    found = circles()
    print(f"import circles: {sum(len(g) for g in found.values())}")
    for crate, groups in sorted(found.items()):
        for g in groups:
            print(f"  {crate}: {' ↔ '.join(g)}")


if __name__ == "__main__":
    main()
