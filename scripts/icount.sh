#!/usr/bin/env bash
# Instruction counts per frame on Cortex-M, under QEMU with -icount shift=0
# (the virtual clock then advances 1 ns per executed instruction; QEMU is not
# cycle-accurate, so these are instructions, never cycles).
#
#   scripts/icount.sh                    # the three boards, every scene
#   SCENES="fill grid4" scripts/icount.sh
#   BOARDS=lm3s6965evb scripts/icount.sh
#   TRACE=1 SCENES=demo BOARDS=mps2-an386-v6m scripts/icount.sh
#   PROFILE=size SCENES=demo BOARDS=lm3s6965evb scripts/icount.sh
#   MICRORASTER_BENCH_TILE=64x32 SCENES=demo scripts/icount.sh
#
# MICRORASTER_BENCH_TILE=WxH (32x32 without it) and MICRORASTER_BENCH_BINS=N
# (4,096 without it) reach every build, the host's too: the renderer's tiles
# and the workspace's bin entries, for a study of the tile size
# (examples/bench_tile). The image hashes fold the tiles in order, so they
# compare a board with the host at the same tiles (examples/tile_image.rs
# compares whole images across tile sizes); the firmware's first line says
# 32x32 whatever the tiles, its statistics line gives their count.
#
# With TRACE=1 the firmware runs once under QEMU's execution trace instead
# (-d in_asm,exec,nochain, through scripts/icount-trace.awk; about a minute
# for one scene, and no disk: the log is never stored), which prints the instructions
# executed per function and the calls of the integer helpers (__aeabi_*,
# __udivmoddi4) by caller, for the whole run: each scene renders four
# frames (plain and profiled, twice), so a single-scene build's figures are
# four frames plus the calibration (the timer's functions) and start-up.
#
# The boards: lm3s6965evb (Cortex-M3, thumbv7m-none-eabi), mps2-an386
# (Cortex-M4F, thumbv7em-none-eabihf) and mps2-an386-v6m: the MPS2-AN386
# running a thumbv6m-none-eabi build, whose ARMv6-M instructions are the
# ones a Cortex-M0+ would execute (no 32x32->64 multiply, no divide). That
# build is told its board with --cfg microraster_board="mps2-an386" (build.rs
# then links it with the MPS2's memory map instead of the RP2040's, and
# Cargo.toml leaves the RP2040's HAL out), in a target directory of its own
# so that it and the Pico firmware do not rebuild each other.
#
# For each board, builds examples/icount.rs in release (or the cargo
# profile PROFILE names, e.g. size: Cargo.toml) for its target, runs
# it twice in QEMU and checks that both runs print the same thing and that
# every scene's image hash equals the host's (the host build of the example
# prints them: the Cortex-M code paths render the host's pixels), then
# prints its tables and the firmware's flash, static RAM (llvm-size -A of
# the linked ELF) and peak stack (which the firmware measures). SCENES (names separated by spaces) is passed to the
# build as MICRORASTER_ICOUNT_SCENES; the scenes are demo, demo-flat, fill,
# grid4 and the fragment-shader fills fill-gouraud-exact,
# fill-nearest-exact, fill-nearest-affine, fill-nearest-quasi16-facing,
# fill-gouraud-quasi16-facing, fill-lit-quasi16-facing, fill-bilinear-exact and
# fill-lit-exact, the small-triangle rock,
# demo-textured-lit and demo-textured-lit-affine
# (examples/icount_scenes/mod.rs). Without SCENES, the LM3S6965 gets eight
# builds (demo demo-flat fill; grid4; rock; the exact and affine shader
# fills; the nearest and Gouraud quasi-perspective fills, whose builds
# link the shaders' quasi-perspective copies too; the lit one;
# demo-textured-lit; demo-textured-lit-affine): its flash
# holds only part of the scenes at a time.
set -euo pipefail
cd "$(dirname "$0")/.."

BOARDS=${BOARDS:-lm3s6965evb mps2-an386 mps2-an386-v6m}
SHADER_SCENES="fill-gouraud-exact fill-nearest-exact fill-nearest-affine fill-bilinear-exact fill-lit-exact"
SCENES=${SCENES:-}
TARGET_DIR=${CARGO_TARGET_DIR:-target}
PROFILE=${PROFILE:-release}
OUT=$TARGET_DIR/icount
mkdir -p "$OUT"

source scripts/tools.sh
need_qemu_arm
size=$(llvm_tool llvm-size)

echo "$(rustc --version); $(qemu-system-arm --version | head -n 1)"

# The host's image of every scene (the host build of the example prints
# their hashes); each board's must be the same.
if [ -z "${TRACE:-}" ]; then
    env -u MICRORASTER_ICOUNT_SCENES CARGO_TARGET_DIR="$TARGET_DIR" \
        cargo run -q --profile "$PROFILE" --example icount >"$OUT/host-images.txt" 2>/dev/null || {
        echo "icount: the host build of the example failed" >&2
        exit 1
    }
fi

footprint=()
for board in $BOARDS; do
    # machine: QEMU's -M; config: extra cargo arguments; dir: its target
    # directory.
    machine=$board config=() dir=$TARGET_DIR
    case $board in
        lm3s6965evb) target=thumbv7m-none-eabi; flash_kib=256; ram_kib=64 ;;
        mps2-an386) target=thumbv7em-none-eabihf; flash_kib=4096; ram_kib=4096 ;;
        mps2-an386-v6m)
            target=thumbv6m-none-eabi; flash_kib=4096; ram_kib=4096
            machine=mps2-an386 dir=$TARGET_DIR/mps2-an386-v6m
            # Appended to .cargo/config.toml's rustflags for the target.
            config=(--config "target.$target.rustflags=[\"--cfg\", \"microraster_board=\\\"mps2-an386\\\"\"]")
            ;;
        *) echo "unknown board $board (lm3s6965evb, mps2-an386 or mps2-an386-v6m)" >&2; exit 1 ;;
    esac
    # The builds per board: every scene at once, except on the LM3S6965,
    # whose 256 KiB of flash hold neither the demo's knot, grid4's grid and
    # the rock together beside the renderer, nor the fragment-shader
    # renderers beside the plain one (a build links only its scenes' meshes
    # and code).
    if [ -n "$SCENES" ]; then
        groups=("$SCENES")
    elif [ "$board" = lm3s6965evb ]; then
        groups=("demo demo-flat fill" "grid4" "rock" "$SHADER_SCENES" "fill-nearest-quasi16-facing fill-gouraud-quasi16-facing" "fill-lit-quasi16-facing" "demo-textured-lit" "demo-textured-lit-affine")
    else
        groups=("")
    fi
    for group in "${groups[@]}"; do
        if [ -n "$group" ]; then
            MICRORASTER_ICOUNT_SCENES="$group" CARGO_TARGET_DIR=$dir \
                cargo build "${config[@]}" --profile "$PROFILE" --example icount --target "$target" >&2
        else
            env -u MICRORASTER_ICOUNT_SCENES CARGO_TARGET_DIR="$dir" \
                cargo build "${config[@]}" --profile "$PROFILE" --example icount --target "$target" >&2
        fi
        elf=$dir/$target/$PROFILE/examples/icount
        if [ -n "${TRACE:-}" ]; then
            nm="$(dirname "$size")/llvm-nm"
            # The helpers' entry addresses, Thumb bit cleared.
            "$nm" "$elf" | awk '$3 ~ /^(__aeabi_|__udivmoddi4$|__divmoddi4$)/ {
                d = index("0123456789abcdef", substr($1, 8, 1)) - 1
                printf "%s%x %s\n", substr($1, 1, 7), d - d % 2, $3 }' \
                >"$OUT/$board.helpers"
            echo
            echo "## $board ($target), scenes: ${group:-all}; execution trace, whole run"
            echo
            timeout 3600 qemu-system-arm -M "$machine" -display none -serial none \
                -monitor none -icount shift=0 -semihosting-config enable=on,target=native \
                -kernel "$elf" -d in_asm,exec,nochain -D /dev/stdout 2>/dev/null |
                awk -v helpers="$OUT/$board.helpers" -f scripts/icount-trace.awk |
                sort -k1,1 -k2,2nr | { c++filt 2>/dev/null || cat; } |
                awk '$1 == "self" && s++ < 30 || $1 == "calls" && c++ < 30'
            continue
        fi
        for run in 1 2; do
            # QEMU's stellaris model says "Timer with period zero, disabling"
            # at every boot; anything else on stderr is shown.
            if ! timeout 600 qemu-system-arm -M "$machine" -display none -serial none \
                -monitor none -icount shift=0 -semihosting-config enable=on,target=native \
                -kernel "$elf" >"$OUT/$board.$run.txt" 2>"$OUT/$board.$run.err"; then
                cat "$OUT/$board.$run.txt" "$OUT/$board.$run.err" >&2
                echo "icount: the $board firmware failed (run $run)" >&2
                exit 1
            fi
            grep -v '^Timer with period zero, disabling$' "$OUT/$board.$run.err" >&2 || true
        done
        if ! cmp -s "$OUT/$board.1.txt" "$OUT/$board.2.txt"; then
            diff "$OUT/$board.1.txt" "$OUT/$board.2.txt" >&2 || true
            echo "icount: two runs on $board differ" >&2
            exit 1
        fi
        # The board's images against the host's: every scene it ran.
        images=$(grep -c '^image: ' "$OUT/$board.1.txt" || true)
        [ "$images" -gt 0 ] || { echo "icount: no image hashes from $board" >&2; exit 1; }
        if ! grep '^image: ' "$OUT/$board.1.txt" | grep -vxF -f "$OUT/host-images.txt" >"$OUT/$board.mismatch"; then
            echo "icount: $board rendered the host's image in all $images scenes"
        else
            echo "icount: $board's image differs from the host's (host: $OUT/host-images.txt):" >&2
            cat "$OUT/$board.mismatch" >&2
            exit 1
        fi
        echo
        echo "## $board ($target), scenes: ${group:-all}; two runs, identical"
        echo
        cat "$OUT/$board.1.txt"

        # Flash: what is loaded (vector table, code, read-only data, the
        # initial values of .data); static RAM: .data, .bss, .uninit.
        # Peak stack: the firmware's own measurement ("peak stack: N B
        # (scene); ..."), commas taken out.
        stack=$(sed -n 's/^peak stack: \([0-9,]*\) B (\([^)]*\)).*/\1 \2/p' "$OUT/$board.1.txt" | tr -d ,)
        [ -n "$stack" ] || { echo "icount: no peak stack from $board" >&2; exit 1; }
        read -r flash ram < <("$size" -A "$elf" | awk '
            $1 == ".vector_table" || $1 == ".text" || $1 == ".rodata" || $1 == ".gnu.sgstubs" { f += $2 }
            $1 == ".data" { f += $2; r += $2 }
            $1 == ".bss" || $1 == ".uninit" { r += $2 }
            END { print f, r }')
        footprint+=("$(awk -v b="$board" -v t="$target" -v f="$flash" -v r="$ram" \
            -v fk="$flash_kib" -v rk="$ram_kib" -v g="${group:-all}" \
            -v st="${stack%% *}" -v deepest="${stack#* }" '
            function sep(n,   s) {
                s = sprintf("%d", n)
                while (s ~ /[0-9][0-9][0-9][0-9]/) sub(/[0-9][0-9][0-9](,|$)/, ",&", s)
                return s
            }
            BEGIN {
                printf "| `icount` on %s (%s) | `%s` | %s B (%.1f of %d KiB) | %s B | %s B (`%s`) | %s B (%.1f of %d KiB) |",
                    b, g, t, sep(f), f / 1024, fk, sep(r), sep(st), deepest,
                    sep(r + st), (r + st) / 1024, rk
            }')")
    done
done

[ -z "${TRACE:-}" ] || exit 0
echo
echo "## Footprint ($PROFILE: llvm-size -A; peak stack measured by the firmware)"
echo
echo "| firmware | target | flash | static RAM | peak stack (deepest scene) | total RAM |"
echo "|---|---|---|---|---|---|"
printf '%s\n' "${footprint[@]}"
