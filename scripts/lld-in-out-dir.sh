#!/bin/sh
# Linker for the boards whose memory map is not the root memory.x (that one
# is the LM3S6965EVB's): runs rustc's own lld from memory/, a directory
# without a file named memory.x, so cortex-m-rt's `INCLUDE memory.x` finds
# the board's map that build.rs put on the search path instead of the root
# file (lld looks in its working directory first). rustc passes absolute
# paths only, so the change of directory is harmless.
cd "$(dirname "$0")/../memory" || exit 1
exec rust-lld "$@"
