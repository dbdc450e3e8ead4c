# Reads `qemu-system-arm -d in_asm,exec,nochain` on stdin (scripts/icount.sh
# with TRACE=1) and prints, per symbol, the instructions executed in it
# ("self": code inlined into a function counts as its own), and for each
# helper named in the file `helpers` (lines "address name", from llvm-nm),
# its calls by caller.
#
# A translation block's size is its in_asm listing's instruction count; the
# listing comes just before the block's first "Trace" line, which names the
# block by its host address, so later executions of that translation are
# looked up by it. A helper's call is an execution of the block at its
# entry address; the caller is the symbol of the block that ran just before.
BEGIN {
    while ((getline line < helpers) > 0) {
        split(line, w, " ")
        entry[w[1]] = w[2]
    }
}
/^IN:/ { n = 0; listing = 1; next }
listing && /^0x[0-9a-f]+:/ { n++; next }
/^Trace / {
    listing = 0
    host = $3
    if (n > 0) { size[host] = n; n = 0 }
    split($4, f, "/")
    pc = f[2]
    instr[$5] += size[host]
    if (pc in entry) calls[entry[pc] " " prev]++
    prev = $5
}
END {
    for (s in instr) printf "self %d %s\n", instr[s], s
    for (c in calls) printf "calls %d %s\n", calls[c], c
}
