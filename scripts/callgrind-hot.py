#!/usr/bin/env python3
"""The hottest code of an x86-64 callgrind profile, instruction by
instruction: the host's counterpart of scripts/pcprof.sh.

    scripts/callgrind-hot.py CALLGRIND_OUT BINARY [SHARE]

CALLGRIND_OUT comes from `valgrind --tool=callgrind --dump-instr=yes`
(scripts/count-instructions.sh writes them to target/callgrind/, its
binary is target/release/examples/count). Every instruction whose count is
at least SHARE of the profile's total (default 0.002, 0.2 %) is hot; the
hot instructions within 64 bytes of each other form a region, and each
region is printed as `objdump -d` gives it (from its function's label or
a little before), each instruction's count in front: where a loop's
instructions go, its spills and reloads. Counts are self costs (a call's
line counts the call instruction, not its callee).

Needs python3 and binutils' objdump and nm.
"""

import re
import subprocess
import sys
from collections import Counter


def parse(path):
    """Self cost per instruction address."""
    cost = Counter()
    positions = ["line"]
    last = {}
    skip_next = False
    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            if line.startswith("positions:"):
                positions = line.split()[1:]
                last = {p: 0 for p in positions}
                continue
            if line.startswith("calls="):
                # The next cost line is the call's inclusive cost.
                skip_next = True
                continue
            if not line or not (line[0].isdigit() or line[0] in "+-*"):
                continue
            fields = line.split()
            values = []
            for kind, text in zip(positions, fields):
                if text == "*":
                    v = last[kind]
                elif text[0] in "+-":
                    v = last[kind] + int(text, 0)
                else:
                    v = int(text, 0)
                last[kind] = v
                values.append(v)
            if skip_next:
                skip_next = False
                continue
            if "instr" not in positions:
                sys.exit("no instruction positions: profile with --dump-instr=yes")
            events = fields[len(positions):]
            if events:
                cost[values[positions.index("instr")]] += int(events[0])
    return cost


def regions(hot, gap=64):
    """Runs of hot addresses no more than `gap` bytes apart."""
    out = []
    for a in sorted(hot):
        if out and a - out[-1][1] <= gap:
            out[-1][1] = a
        else:
            out.append([a, a])
    return out


def main():
    if len(sys.argv) < 3:
        sys.exit(__doc__)
    path, binary = sys.argv[1], sys.argv[2]
    share = float(sys.argv[3]) if len(sys.argv) > 3 else 0.002
    cost = parse(path)
    total = sum(cost.values())
    hot = [a for a, c in cost.items() if c >= share * total]
    print(f"{total:,} instructions; {len(hot)} at {share:.1%} or more of them")
    # Disassembled from the start of the function that holds each region
    # (x86 instructions cannot be decoded from an arbitrary byte), shown
    # from a little before the region.
    symbols = sorted(
        int(f[0], 16)
        for f in (
            l.split()
            for l in subprocess.run(
                ["nm", "-n", "--defined-only", binary],
                capture_output=True, text=True, check=True,
            ).stdout.splitlines()
        )
        if len(f) >= 3 and f[1] in "tTwW"
    )
    insn = re.compile(r"^\s*([0-9a-f]+):")
    for start, end in regions(hot):
        below = [a for a in symbols if a <= start]
        dump = subprocess.run(
            [
                "objdump", "-d", "-C", "--no-show-raw-insn",
                f"--start-address={below[-1] if below else start:#x}",
                f"--stop-address={end + 16:#x}",
                binary,
            ],
            capture_output=True, text=True, check=True,
        ).stdout
        region = sum(c for a, c in cost.items() if start - 48 <= a < end + 16)
        print(f"\n== {start:#x}..{end:#x}: {region:,} ({region / total:.1%})")
        for line in dump.splitlines():
            m = insn.match(line)
            if m and int(m.group(1), 16) >= start - 48:
                c = cost.get(int(m.group(1), 16), 0)
                print(f"{c:>12,} {line.strip()}" if c else f"{'':>12} {line.strip()}")
            elif line.endswith(">:"):
                print(line)


if __name__ == "__main__":
    main()
