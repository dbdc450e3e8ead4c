#!/usr/bin/env bash
# Instruction counts of the benchmark scenes under valgrind's callgrind.
#
#   scripts/count-instructions.sh                 # demo and fill (the targets)
#   SCENES="demo demo-flat fill tri4 tri100 tri10000 euc" scripts/count-instructions.sh
#   N=20 TOP=25 scripts/count-instructions.sh
#   MICRORASTER_BENCH_TILE=64x32 SCENES="demo rock" scripts/count-instructions.sh
#
# MICRORASTER_BENCH_TILE=WxH (32x32 without it) and MICRORASTER_BENCH_BINS=N
# (the scenes' own bin pools without it) reach the build of the example:
# the benchmark renderer's tiles and workspaces' bin entries, for a study of
# the tile size (examples/bench_tile; examples/tile_image.rs checks that the
# images are the same).
#
# For each scene, `examples/count.rs` renders N identical frames into a
# NullSink. Two independent measurements are printed:
#
#  * toggled: callgrind collects only inside `count::frame` (one whole frame:
#    scene set-up, vertex stage, binning, rasterization, shading, tile
#    clears); instructions / N;
#  * difference: two uninstrumented-toggle runs of 1 and N+1 frames; the
#    difference / N (includes the few instructions of the frame loop).
#
# Then instructions per shaded pixel (FrameStats::pixels_shaded) and the
# per-function split of one frame: self cost (instructions executed in the
# function's own code, including everything inlined into it) and inclusive
# cost (plus its callees), and (with python3 and binutils) the split of
# `render` into the stages of a frame, by scripts/callgrind-phases.py. Raw
# callgrind files are kept in target/callgrind/ for `callgrind_annotate`.
set -euo pipefail
cd "$(dirname "$0")/.."

N=${N:-10}
TOP=${TOP:-16}
SCENES=${SCENES:-demo fill}
OUT=target/callgrind
BIN=target/release/examples/count

command -v valgrind >/dev/null || { echo "valgrind is not installed" >&2; exit 1; }
cargo build --release --example count >&2
mkdir -p "$OUT"

collected() { sed -n 's/.*Collected : \([0-9]*\).*/\1/p' "$1"; }

# Per-function self and inclusive cost of a callgrind output file, divided by
# the number of frames. Handles callgrind's name compression ("(id) name").
split_functions() {
    local frames=$1 top=$2 file=$3
    awk -v frames="$frames" '
    function name(s, kind,   id, rest) {
        if (s ~ /^\([0-9]+\)/) {
            id = s; sub(/\).*/, "", id); sub(/^\(/, "", id)
            rest = s; sub(/^\([0-9]+\) ?/, "", rest)
            if (rest != "") names[kind, id] = rest
            return names[kind, id]
        }
        return s
    }
    /^(fn|cfn)=/ { kind = "fn"; v = substr($0, index($0, "=") + 1); n = name(v, kind)
                   if ($0 ~ /^fn=/) { fn = n; seen[fn] = 1 } ; next }
    /^(fl|fi|fe|cfi|cfl)=/ { v = substr($0, index($0, "=") + 1); name(v, "fl"); next }
    /^(ob|cob)=/ { v = substr($0, index($0, "=") + 1); name(v, "ob"); next }
    /^positions:/ { npos = NF - 1; next }
    /^calls=/ { incall = 1; next }
    /^[0-9+*-]/ {
        c = (NF > npos) ? $NF : 0
        if (incall) { callcost[fn] += c; incall = 0 } else { self[fn] += c; total += c }
        next
    }
    END {
        printf "    %12s %12s  %s\n", "self/frame", "incl/frame", "function"
        for (f in seen) if (self[f] + callcost[f] > 0)
            printf "    %12d %12d  %s\n", self[f] / frames, (self[f] + callcost[f]) / frames, f
    }' "$file" | { read -r header; echo "$header"; sort -k1,1nr | awk -v top="$top" 'NR <= top'; }
}

printf '%-10s %14s %14s %10s %12s\n' scene "instr/frame" "(difference)" pixels "instr/pixel"
declare -A PER_FRAME PER_PIXEL
for scene in $SCENES; do
    valgrind --tool=callgrind --toggle-collect='*count::frame*' --dump-instr=yes \
        --callgrind-out-file="$OUT/$scene.out" "$BIN" "$scene" "$N" \
        >"$OUT/$scene.stdout" 2>"$OUT/$scene.log"
    toggled=$(( $(collected "$OUT/$scene.log") / N ))
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$BIN" "$scene" 1 \
        >/dev/null 2>"$OUT/$scene.1.log"
    valgrind --tool=callgrind --callgrind-out-file=/dev/null "$BIN" "$scene" $((N + 1)) \
        >/dev/null 2>"$OUT/$scene.n.log"
    diff=$(( ($(collected "$OUT/$scene.n.log") - $(collected "$OUT/$scene.1.log")) / N ))
    pixels=$(sed -n 's/.*pixels_shaded=\([0-9]*\).*/\1/p' "$OUT/$scene.stdout")
    if [ -z "$pixels" ]; then
        pixels=$(sed -n 's/.*pixels_covered=\([0-9]*\).*/\1/p' "$OUT/$scene.stdout")
    fi
    per_pixel=$(awk -v a="$toggled" -v b="$pixels" 'BEGIN { printf "%.2f", a / b }')
    PER_FRAME[$scene]=$toggled
    PER_PIXEL[$scene]=$per_pixel
    printf '%-10s %14d %14d %10d %12s\n' "$scene" "$toggled" "$diff" "$pixels" "$per_pixel"
done

phases=0
if command -v python3 >/dev/null && command -v callgrind_annotate >/dev/null; then phases=1; fi
for scene in $SCENES; do
    echo
    echo "== $scene: $(cat "$OUT/$scene.stdout")"
    split_functions "$N" "$TOP" "$OUT/$scene.out"
    if [ "$phases" = 1 ] && [ "$scene" != euc ]; then
        echo
        python3 scripts/callgrind-phases.py "$OUT/$scene.out" "$N"
    fi
done

echo
check() { # name value limit unit
    awk -v n="$1" -v v="$2" -v l="$3" -v u="$4" 'BEGIN {
        if (v <= l) printf "target %-34s %12s %s <= %s: met\n", n, v, u, l
        else printf "target %-34s %12s %s >  %s: MISSED by %.2fx\n", n, v, u, l, v / l }'
}
if [ -n "${PER_FRAME[demo]:-}" ]; then
    check "(a) demo frame, Gouraud + depth" "${PER_FRAME[demo]}" 3000000 instr/frame
fi
if [ -n "${PER_PIXEL[fill]:-}" ]; then
    check "(b) flat depth-tested fill" "${PER_PIXEL[fill]}" 12 instr/pixel
fi
