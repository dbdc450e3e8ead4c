#!/usr/bin/env bash
# Per-instruction execution counts of a Cortex-M firmware under QEMU: where
# a function's instructions go, line by line of its disassembly.
#
#   scripts/pcprof.sh ELF [MACHINE] [OUT]
#   SCENES=demo BOARDS=mps2-an386 scripts/icount.sh   # builds the ELF first
#   scripts/pcprof.sh target/thumbv7em-none-eabihf/release/examples/icount mps2-an386
#   less target/pcprof/icount.annot                   # counts beside each instruction
#
# MACHINE is QEMU's -M (lm3s6965evb, or mps2-an386 also for the ARMv6-M
# build in target/mps2-an386-v6m/thumbv6m-none-eabi/release/examples/icount);
# OUT is the output prefix (default target/pcprof/<ELF's name>). The firmware
# runs once under -d in_asm,exec,nochain (the log goes through a pipe to
# scripts/pcprof.awk, never to disk; a minute or two for a single-scene icount
# build), and the script writes
#
#   OUT.pcs    "address count" for every instruction executed;
#   OUT.annot  llvm-objdump -d -C of the ELF, each instruction's count in front;
#   OUT.funcs  instructions executed per function, largest first;
#
# and prints the total and the 25 largest functions. Counts cover the whole
# run: an icount build renders each scene four times (plain and profiled,
# twice) besides its start-up and calibration. scripts/icount.sh with
# TRACE=1 gives per-function figures and the integer helpers' calls by
# caller; this gives the instructions inside a function.
set -euo pipefail
cd "$(dirname "$0")/.."

elf=${1:?usage: scripts/pcprof.sh ELF [MACHINE] [OUT]}
machine=${2:-mps2-an386}
out=${3:-target/pcprof/$(basename "$elf")}
mkdir -p "$(dirname "$out")"

source scripts/tools.sh
need_qemu_arm
objdump=$(llvm_tool llvm-objdump)

timeout 3600 qemu-system-arm -M "$machine" -display none -serial none \
    -monitor none -icount shift=0 -semihosting-config enable=on,target=native \
    -kernel "$elf" -d in_asm,exec,nochain -D /dev/stdout 2>/dev/null |
    awk -f scripts/pcprof.awk | sort >"$out.pcs"

"$objdump" -d -C --no-show-raw-insn "$elf" >"$out.dis"
# Each instruction line of the disassembly gets its count in front; each
# function's total goes to OUT.funcs.
awk -v pcs="$out.pcs" -v funcs="$out.funcs.tmp" '
BEGIN { while ((getline l < pcs) > 0) { split(l, w, " "); c[w[1]] = w[2] } }
/^[0-9a-f]+ <.*>:$/ { fn = substr($0, index($0, "<")); print; next }
/^ *[0-9a-f]+:/ {
    a = $1; sub(":", "", a); sub(/^0+/, "", a)
    k = (a in c) ? c[a] : 0
    total[fn] += k
    printf "%10d %s\n", k, $0
    next
}
{ print }
END { for (f in total) if (total[f]) printf "%d %s\n", total[f], f > funcs }
' "$out.dis" >"$out.annot"
rm -f "$out.dis"
sort -k1,1nr "$out.funcs.tmp" >"$out.funcs"
rm -f "$out.funcs.tmp"
awk '{ s += $1 } END { printf "total %d instructions executed\n", s }' "$out.funcs"
head -n 25 "$out.funcs"
