#!/usr/bin/env python3
"""Splits a frame's instructions into its stages, from the inclusive cost
of the functions that the renderer's files give each stage.

    scripts/callgrind-phases.py CALLGRIND_OUT FRAMES

CALLGRIND_OUT comes from `valgrind --tool=callgrind` (as
scripts/count-instructions.sh writes them to target/callgrind/). The
stages, by function (src/render/):

    vertex_stage::run, less transform   frame set-up and checks
    vertex_stage::transform             vertex stage
    bin::Bins::pass                     binning: classification, bins
    tile_loop::raster_tile              rasterization and shading
    the rest of Renderer::render_profiled: per tile, clear and sink

Needs python3 and valgrind's callgrind_annotate.
"""

import re
import subprocess
import sys

STAGES = [
    ("frame set-up and checks", None),
    ("vertex stage", "render::vertex_stage::transform"),
    ("binning (classification, bins)", "render::bin::Bins::pass"),
    ("tiles (clear, sink)", None),
    ("rasterization + shading (raster_tile)", "render::tile_loop::raster_tile"),
]


def inclusive(path):
    """Inclusive cost per function: its own instructions plus the
    inclusive cost of every call it makes (callgrind's `calls=` lines),
    with callgrind's name compression ("(id) name") undone."""
    names, cost = {}, {}
    fn, in_call = None, False

    def name(v):
        m = re.match(r"\((\d+)\)\s*(.*)", v)
        if not m:
            return v
        if m.group(2):
            names[m.group(1)] = m.group(2)
        return names.get(m.group(1), v)

    for line in open(path):
        line = line.rstrip("\n")
        if line.startswith("fn="):
            fn = name(line[3:])
            cost.setdefault(fn, 0)
            continue
        if line.startswith("cfn="):
            name(line[4:])
            continue
        if line.startswith("calls="):
            in_call = True
            continue
        if fn is None or not line or not (line[0].isdigit() or line[0] in "+-*"):
            continue
        f = line.split()
        if len(f) >= 2:
            cost[fn] += int(f[-1])
        in_call = False
    return cost


def find(cost, suffix):
    """The summed cost of the functions whose name ends with `suffix`
    (ignoring generic arguments)."""
    total = 0
    for name, c in cost.items():
        bare = re.sub(r"<[^<>]*>", "", re.sub(r"<[^<>]*>", "", name))
        if bare.endswith(suffix):
            total += c
    return total


def main():
    if len(sys.argv) < 3:
        print(__doc__)
        sys.exit(2)
    path, frames = sys.argv[1], int(sys.argv[2])
    cost = inclusive(path)
    frame = find(cost, "Renderer::render_profiled")
    run = find(cost, "render::vertex_stage::run")
    agg = {name: find(cost, f) for name, f in STAGES if f}
    agg["frame set-up and checks"] = run - agg["vertex stage"]
    agg["tiles (clear, sink)"] = frame - run - sum(
        agg[n] for n in ("binning (classification, bins)", "rasterization + shading (raster_tile)")
    )
    total = find(cost, "count::frame") or frame
    print("%12s  %6s  %s" % ("instr/frame", "share", "stage"))
    for name, _ in STAGES:
        print("%12d  %5.1f%%  %s" % (agg[name] // frames, 100.0 * agg[name] / max(total, 1), name))
    rest = total - frame
    print("%12d  %5.1f%%  %s" % (rest // frames, 100.0 * rest / max(total, 1), "outside render (scene building)"))
    print("%12d  %5.1f%%  %s" % (total // frames, 100.0, "total"))


if __name__ == "__main__":
    main()
