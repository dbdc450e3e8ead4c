# Reads `qemu-system-arm -d in_asm,exec,nochain` on stdin and prints, for
# every guest instruction executed, "address count" (address in lower-case
# hex without leading zeros).
#
# Each translation block's in_asm listing ("IN:" and one line per guest
# instruction) comes just before the block's first "Trace" line, which
# names the block by its host address; every later "Trace" line of that
# host address is one more execution of the same guest instructions.
# (`nochain` makes QEMU log every execution: chained blocks would not be.)
/^IN:/ { n = 0; listing = 1; next }
listing && /^0x[0-9a-f]+:/ {
    a = substr($1, 3, length($1) - 3)
    sub(/^0+/, "", a)
    pcs[n++] = a
    next
}
/^Trace / {
    host = $3
    if (listing) {
        listing = 0
        s = ""
        for (i = 0; i < n; i++) s = s " " pcs[i]
        block[host] = s
    }
    runs[host]++
}
END {
    for (h in runs) {
        m = split(block[h], p, " ")
        for (i = 1; i <= m; i++) count[p[i]] += runs[h]
    }
    for (a in count) printf "%s %d\n", a, count[a]
}
