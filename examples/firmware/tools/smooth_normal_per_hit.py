#!/usr/bin/env python3
"""Instructions a hit spends on smooth normals, from a run-qemu.sh dump.

usage: smooth_normal_per_hit.py FRAME_DUMP ELF HITS [FUNCTION]

FRAME_DUMP is a `frame-insns-*.txt` of the plugin (`vaddr count size
bytes` per executed instruction), ELF the program that ran, HITS the run's
`hits=` (9,615 for the `lcd` scene). Counts the instructions whose inline
chain, as `llvm-addr2line -f -i` names it, includes a function whose name
has FUNCTION in it (default `smooth_normal`), plus the two instructions
(`vsqrt.f32`, `bx lr`) of each call they make to `hfray_vsqrt_f32`, which
is out of line. Prints the total, the calls, and the figure per hit.
Needs llvm-addr2line and llvm-objdump.
"""

import re
import subprocess
import sys

VSQRT = "hfray_vsqrt_f32"
VSQRT_INSTRUCTIONS = 2


def main():
    if len(sys.argv) not in (4, 5):
        sys.exit(__doc__.strip())
    dump, elf, hits = sys.argv[1], sys.argv[2], int(sys.argv[3])
    wanted = sys.argv[4] if len(sys.argv) == 5 else "smooth_normal"

    counts = {}
    with open(dump) as f:
        for line in f:
            parts = line.split()
            if len(parts) >= 2 and int(parts[1]) > 0:
                counts[int(parts[0], 16)] = int(parts[1])
    addresses = sorted(counts)

    # One llvm-addr2line for every address: `-a` heads each address's
    # inline chain with the address itself.
    out = subprocess.run(
        ["llvm-addr2line", "-a", "-f", "-i", "-C", "-e", elf],
        input="".join(f"0x{a:x}\n" for a in addresses),
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    in_chain = set()
    current = None
    for line in out.splitlines():
        if re.fullmatch(r"0x[0-9a-f]+", line):
            current = int(line, 16)
        elif current is not None and not line.startswith("/") and wanted in line:
            in_chain.add(current)

    # The calls to the out-of-line square root among those instructions.
    disassembly = subprocess.run(
        ["llvm-objdump", "-d", "--no-show-raw-insn", elf],
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    calls_to_sqrt = set()
    for line in disassembly.splitlines():
        m = re.match(r"\s*([0-9a-f]+):\s+bl\s.*<" + VSQRT + ">", line)
        if m:
            calls_to_sqrt.add(int(m.group(1), 16))

    own = sum(counts[a] for a in in_chain)
    sqrt_calls = sum(counts[a] for a in in_chain & calls_to_sqrt)
    total = own + VSQRT_INSTRUCTIONS * sqrt_calls
    print(
        f"{wanted}: {own} instructions in its inline chains + "
        f"{VSQRT_INSTRUCTIONS} x {sqrt_calls} in {VSQRT} = {total}; "
        f"{total / hits:.1f} a hit over {hits} hits"
    )


if __name__ == "__main__":
    main()
