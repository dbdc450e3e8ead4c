#!/usr/bin/env bash
# Cargo runner for thumbv7em-none-eabihf: boots a firmware ELF on QEMU's
# emulated Arm MPS2 board with the AN386 image (Cortex-M4F), headless, with
# semihosting for the firmware's output. Extra arguments go to QEMU, for
# example `cargo run --release --example icount --target
# thumbv7em-none-eabihf -- -icount shift=0`. Ctrl-C stops it.
set -euo pipefail
elf="$1"
shift
source "$(dirname "$0")/tools.sh"
need_qemu_arm
exec qemu-system-arm -M mps2-an386 -display none -serial none -monitor none \
    -semihosting-config enable=on,target=native -kernel "$elf" "$@"
