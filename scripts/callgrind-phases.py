#!/usr/bin/env python3
"""Splits the instructions of `Renderer::render_profiled` (or, in older
trees, `Renderer::render`) into the stages of a frame.

    scripts/callgrind-phases.py CALLGRIND_OUT BINARY FRAMES [RENDER_RS]

CALLGRIND_OUT must come from `valgrind --tool=callgrind --dump-instr=yes`
(scripts/count-instructions.sh writes them to target/callgrind/). Every
instruction executed in `render`'s own code, and every call it makes (with
the callee's inclusive cost), is attributed to the line of `render` it
belongs to, through the inline chain that `addr2line -i` reports; lines map
to stages through markers in src/render.rs:

    "// Vertex stage"         vertex stage
    "// Binning: one pass"    binning: classification, bins
    "for k in 0..bins.tiles()" per tile: clear, raster, sink

Rasterization and shading (`raster_tile`: fetching each binned triangle,
set-up, spans, pixels) are reported on their own.
Needs python3 and binutils (nm, addr2line).
"""

import collections
import re
import subprocess
import sys


def parse(path, binary_suffix):
    """Self cost per instruction address and inclusive cost per call-site
    address, for the objects whose name ends with `binary_suffix`."""
    self_cost = collections.Counter()
    call_cost = collections.Counter()
    names = {}
    obj = None
    last = 0
    in_call = False

    def pos(s, prev):
        if s == "*":
            return prev
        if s[0] == "+":
            return prev + int(s[1:], 0)
        if s[0] == "-":
            return prev - int(s[1:], 0)
        return int(s, 0)

    for line in open(path):
        if line.startswith(("ob=", "cob=")):
            key, v = line.rstrip("\n").split("=", 1)
            m = re.match(r"\((\d+)\)\s*(.*)", v)
            if m:
                if m.group(2):
                    names[m.group(1)] = m.group(2)
                if key == "ob":
                    obj = names.get(m.group(1))
            elif key == "ob":
                obj = v
            continue
        if line.startswith("calls="):
            in_call = True
            continue
        if not (line.startswith("0x") or line[:1] in "+-*"):
            continue
        f = line.split()
        a = pos(f[0], last)
        last = a
        c = int(f[2]) if len(f) >= 3 else 0
        if obj is None or not obj.endswith(binary_suffix):
            in_call = False
            continue
        if in_call:
            call_cost[a] += c
            in_call = False
        else:
            self_cost[a] += c
    return self_cost, call_cost


def symbols(binary):
    out = subprocess.run(["nm", "-C", "-S", binary], capture_output=True, text=True).stdout
    syms = []
    for l in out.splitlines():
        p = l.split(None, 3)
        if len(p) == 4 and p[2] in "tT":
            syms.append((int(p[0], 16), int(p[1], 16), p[3]))
    return syms


def main():
    if len(sys.argv) < 4:
        print(__doc__)
        sys.exit(2)
    path, binary, frames = sys.argv[1], sys.argv[2], int(sys.argv[3])
    render_rs = sys.argv[4] if len(sys.argv) > 4 else "src/render.rs"
    src = open(render_rs).read().splitlines()

    def marker(text):
        for i, l in enumerate(src):
            if text in l:
                return i + 1
        sys.exit(f"marker {text!r} not found in {render_rs}")

    bounds = [
        (marker("// Vertex stage"), "vertex stage"),
        (marker("// Binning: one pass"), "binning (classification, bins)"),
        (marker("for k in 0..bins.tiles()"), "tiles (clear, sink)"),
    ]
    suffix = binary.rsplit("/", 1)[-1]
    self_cost, call_cost = parse(path, "/" + suffix)
    syms = symbols(binary)
    render = [(s, n) for s, n, name in syms if name.endswith(("Renderer<C,_,_>::render", "Renderer<C,_,_>::render_profiled"))]
    raster = [(s, n) for s, n, name in syms if name.endswith(("render::raster_piece", "render::raster_tile"))]

    def inside(a, ranges):
        return any(s <= a < s + n for s, n in ranges)

    addrs = sorted(a for a in set(self_cost) | set(call_cost) if inside(a, render))
    out = subprocess.run(
        ["addr2line", "-e", binary, "-i", "-f", "-C", "-a"] + ["%x" % a for a in addrs],
        capture_output=True,
        text=True,
    ).stdout.splitlines()
    chains, cur, i = {}, None, 0
    while i < len(out):
        if out[i].startswith("0x"):
            cur = int(out[i], 16)
            chains[cur] = []
            i += 1
        else:
            chains[cur].append((out[i], out[i + 1]))
            i += 2

    def stage(a):
        for fn, loc in reversed(chains.get(a, [])):
            m = re.search(r"render\.rs:(\d+)", loc)
            if m and fn.endswith(("Renderer<C,_,_>::render", "Renderer<C,_,_>::render_profiled")):
                line, name = int(m.group(1)), "frame set-up and checks"
                for start, n in bounds:
                    if line >= start:
                        name = n
                return name
        return "frame set-up and checks"

    # Calls into the rasterizer are reported apart, wherever they are made
    # from (the tile loop calls it through a function of its own).
    raster_entries = {s for s, _ in raster}

    def call_target(a):
        out = subprocess.run(
            ["objdump", "-d", "--no-show-raw-insn", binary,
             "--start-address=%#x" % a, "--stop-address=%#x" % (a + 16)],
            capture_output=True, text=True,
        ).stdout
        m = re.search(r"call\s+([0-9a-f]+)\s", out)
        return int(m.group(1), 16) if m else None

    agg = collections.Counter()
    for a in addrs:
        agg[stage(a)] += self_cost[a]
    raster_total = 0
    for a in call_cost:
        if call_cost[a] and call_target(a) in raster_entries:
            raster_total += call_cost[a]
    raster_stage = "rasterization + shading (raster_tile)"
    for a in addrs:
        if not call_cost[a]:
            continue
        if call_target(a) in raster_entries:
            agg[raster_stage] += call_cost[a]
            raster_total -= call_cost[a]
        else:
            agg[stage(a)] += call_cost[a]
    # What is left was called from the tile loop's callees.
    agg["tiles (clear, sink)"] -= raster_total
    agg[raster_stage] += raster_total
    total = sum(self_cost.values())
    render_total = sum(agg.values())
    print("%12s  %6s  %s" % ("instr/frame", "share", "stage"))
    for name in [
        "frame set-up and checks",
        "vertex stage",
        "binning (classification, bins)",
        "tiles (clear, sink)",
        "rasterization + shading (raster_tile)",
    ]:
        print("%12d  %5.1f%%  %s" % (agg[name] // frames, 100.0 * agg[name] / total, name))
    rest = total - render_total
    print("%12d  %5.1f%%  %s" % (rest // frames, 100.0 * rest / total, "outside render (scene building)"))
    print("%12d  %5.1f%%  %s" % (total // frames, 100.0, "total"))


if __name__ == "__main__":
    main()
