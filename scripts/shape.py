#!/usr/bin/env python3
"""The code-shape numbers issue 31 measures, on the source (tests excluded): files over
800 lines, functions over 120 lines, `too_many_arguments` allowances, the CLI crate's
size. Usage: python3 scripts/shape.py [--all]"""
import os, re, sys

ROOT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "crates")
FN = re.compile(r"^\s*(pub(\([^)]*\))?\s+)?(const\s+)?(async\s+)?(unsafe\s+)?fn\s+(\w+)")


def source_files():
    for crate in sorted(os.listdir(ROOT)):
        src = os.path.join(ROOT, crate, "src")
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


if __name__ == "__main__":
    main()
