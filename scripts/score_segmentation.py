#!/usr/bin/env python3
"""Scores `tabula perceive` on labelled real frames (PCL's mOSD: `segmentation/mOSD`
of PointCloudLibrary/data), per scene category: objects found at IoU >= 0.5, extra
segments (>= 500 points, matching no object), overlap precision / recall / F (OSD's and
OCID's), and the pipeline's time.

    scripts/score_segmentation.py DIR/learn [--format mosd|mosd-parts] [--tabula BIN]

Frames are `learnN.pcd` / `testN.pcd`; categories as the dataset's README gives them.
No dependencies beyond Python's standard library."""
import argparse
import json
import re
import subprocess
import sys
from pathlib import Path

CATEGORIES = {
    "learn": [(0, 16, "boxes"), (17, 24, "stacked boxes"), (25, 32, "occluded objects"), (33, 44, "cylindric objects")],
    "test": [(0, 15, "boxes"), (16, 23, "stacked boxes"), (24, 30, "occluded objects"), (31, 42, "cylindric objects"),
             (43, 54, "mixed objects"), (55, 65, "complex scenes")],
}


def category(name):
    m = re.fullmatch(r"(learn|test)(\d+)", name)
    if not m:
        return "other"
    split, k = m.group(1), int(m.group(2))
    return next((c for lo, hi, c in CATEGORIES[split] if lo <= k <= hi), "other")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("folder")
    ap.add_argument("--format", default="mosd")
    ap.add_argument("--tabula", default=str(Path(__file__).resolve().parents[1] / "target/release/tabula"))
    ap.add_argument("--quiet", action="store_true")
    ap.add_argument("--params", help="a TOML of pipeline parameters for every frame")
    a = ap.parse_args()
    frames = sorted(Path(a.folder).glob("*.pcd"), key=lambda p: (len(p.stem), p.stem))
    rows = {}
    for f in frames:
        out = subprocess.run([a.tabula, "perceive", "--cloud", str(f)] + (["--params", a.params] if a.params else []) + [ "--score", str(f),
                              "--truth-format", a.format, "--json"], capture_output=True, text=True)
        if out.returncode != 0:
            print(f"{f.stem}: {out.stderr.strip()}", file=sys.stderr)
            continue
        v = json.loads(out.stdout)
        s = v["score"]
        if not a.quiet:
            print(f"{f.stem:<8} {category(f.stem):<18} objects {s['objects']:>2} found {s['found_iou50']:>2} "
                  f"extra {s['extra_segments']:>2} F {s['f_measure']:.3f}  {v['ms']:.1f} ms")
        partial = {o["label"] for o in v.get("partial_objects", [])}
        matched = {m["segment"]: m for m in s["per_object"] if m["segment"] != 0}
        # Segments called partial whose object is whole in view, and objects cut by the
        # image's border whose segment is called whole.
        s["partial_whole"] = sum(1 for k in partial if k in matched and not matched[k]["at_image_border"])
        s["whole_cut"] = sum(1 for k, m in matched.items() if m["at_image_border"] and k not in partial)
        s["cut"] = sum(1 for m in s["per_object"] if m["at_image_border"])
        rows.setdefault(category(f.stem), []).append((s, v["ms"]))
    print(f"\n| category | frames | objects | found at IoU ≥ 0.5 | extra segments | overlap P / R / F (mean) | ms (median) | cut by the border: in truth / called whole | whole, called partial |")
    print("|---|---:|---:|---:|---:|---|---:|---:|---:|")
    everything = []
    for cat, rs in list(rows.items()) + [("all", None)]:
        rs = rs if rs is not None else everything
        if cat != "all":
            everything.extend(rs)
        n = sum(s["objects"] for s, _ in rs)
        found = sum(s["found_iou50"] for s, _ in rs)
        extra = sum(s["extra_segments"] for s, _ in rs)
        mean = lambda k: sum(s[k] for s, _ in rs) / max(len(rs), 1)
        ms = sorted(t for _, t in rs)
        tally = lambda k: sum(s.get(k, 0) for s, _ in rs)
        print(f"| {cat} | {len(rs)} | {n} | {found} ({100 * found / max(n, 1):.1f} %) | {extra} ({100 * extra / max(n, 1):.1f} % of objects) | "
              f"{mean('precision'):.3f} / {mean('recall'):.3f} / {mean('f_measure'):.3f} | {ms[len(ms) // 2]:.1f} | "
              f"{tally('cut')} / {tally('whole_cut')} | {tally('partial_whole')} |")


if __name__ == "__main__":
    main()
