#!/usr/bin/env bash
# Cargo runner for thumbv7m-none-eabi: boots a firmware ELF on QEMU's
# emulated LM3S6965EVB, whose SSI0 drives the SSD0323 OLED. With a desktop
# ($DISPLAY set) QEMU shows the OLED in a window; otherwise it runs headless
# and only the firmware's semihosting output is seen. Ctrl-C stops it.
set -euo pipefail
elf="$1"
shift
source "$(dirname "$0")/tools.sh"
need_qemu_arm
display=(-display none)
if [ -n "${DISPLAY:-}" ]; then
    display=()
fi
exec qemu-system-arm -M lm3s6965evb "${display[@]}" -serial none -monitor none \
    -semihosting-config enable=on,target=native -kernel "$elf" "$@"
