# Sourced by the scripts that run firmware under QEMU or read its ELFs:
# the checks for the tools they need, each with how to install it.

# Exits with how to install QEMU unless qemu-system-arm is on the PATH.
need_qemu_arm() {
    command -v qemu-system-arm >/dev/null || {
        echo "qemu-system-arm is not installed (Debian: apt-get install qemu-system-arm)" >&2
        exit 1
    }
}

# Prints the path of the llvm-tools binary $1 (llvm-size, llvm-nm,
# llvm-objdump) of the active toolchain; fails with how to install it.
llvm_tool() {
    local host tool
    host=$(rustc -vV | sed -n 's/^host: //p')
    tool="$(rustc --print sysroot)/lib/rustlib/$host/bin/$1"
    [ -x "$tool" ] || { echo "$1 not found: rustup component add llvm-tools" >&2; exit 1; }
    echo "$tool"
}
