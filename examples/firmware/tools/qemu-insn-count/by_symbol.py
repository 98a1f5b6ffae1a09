#!/usr/bin/env python3
"""Aggregate insn_count dump (vaddr count size bytes) by ELF symbol using nm."""
import sys, subprocess, bisect, collections
dump, elf = sys.argv[1], sys.argv[2]
nm = sys.argv[3] if len(sys.argv) > 3 else 'nm'
syms = []
for line in subprocess.run([nm, '-n', '-C', '--defined-only', elf], capture_output=True, text=True).stdout.splitlines():
    p = line.split(None, 2)
    if len(p) == 3 and p[1] in 'tTwW':
        if not p[2].startswith('$'):  # skip ARM mapping symbols ($t, $d)
            syms.append((int(p[0], 16) & ~1, p[2]))
syms.sort(); addrs = [a for a, _ in syms]
by = collections.Counter(); cls = collections.Counter(); total = 0
for line in open(dump):
    va, cnt, size, hx = line.split()
    va, cnt = int(va, 16), int(cnt)
    i = bisect.bisect_right(addrs, va) - 1
    name = syms[i][1] if i >= 0 else '?'
    by[name] += cnt; total += cnt
print(f"total {total}")
for name, c in by.most_common(int(sys.argv[4]) if len(sys.argv) > 4 else 25):
    print(f"{c:>12} {100*c/total:5.1f}%  {name[:90]}")
