#!/usr/bin/env python3
# SPDX-License-Identifier: GPL-3.0-or-later
# Per-instruction self cost (Ir) of one function from a callgrind file recorded with
# --dump-instr=yes, printed next to objdump's disassembly: where the pair kernel's instructions go.
# Usage: instr_costs.py callgrind.out BINARY FUNCTION_SUBSTRING [min_count]
import re
import subprocess
import sys


def parse(path):
    costs = {}  # addr -> Ir (self)
    fn = None
    last = 0
    skip_next = False
    names = {}
    with open(path) as f:
        for line in f:
            line = line.rstrip("\n")
            if not line:
                continue
            if line.startswith("cfn="):
                m = re.match(r"cfn=\((\d+)\) (.*)", line)
                if m:
                    names[m.group(1)] = m.group(2)
                continue
            if line.startswith(("fn=",)):
                m = re.match(r"fn=\((\d+)\)(?: (.*))?", line)
                if m:
                    if m.group(2):
                        names[m.group(1)] = m.group(2)
                    fn = names.get(m.group(1))
                else:
                    fn = line[3:]
                continue
            if line.startswith("calls="):
                skip_next = True
                continue
            if line[0] in "0123456789+-*":
                parts = line.split()
                pos = parts[0]
                if pos.startswith("0x"):
                    addr = int(pos, 16)
                elif pos[0] == "+":
                    addr = last + int(pos[1:], 16) if pos[1:].startswith("0x") else last + int(pos[1:])
                elif pos[0] == "-":
                    addr = last - int(pos[1:], 16) if pos[1:].startswith("0x") else last - int(pos[1:])
                elif pos == "*":
                    addr = last
                else:
                    addr = int(pos)
                last = addr
                if skip_next:
                    skip_next = False
                    continue
                # positions: instr line -> parts[1] may be the line number, cost follows.
                if len(parts) >= 3:
                    ir = int(parts[2])
                elif len(parts) == 2:
                    ir = int(parts[1])
                else:
                    continue
                costs.setdefault(fn, {})
                costs[fn][addr] = costs[fn].get(addr, 0) + ir
            # other lines (fl=, fi=, fe=, ob=, cob=, cfn=, ...) ignored
    return costs


def main():
    path, binary, sub = sys.argv[1:4]
    min_count = int(sys.argv[4]) if len(sys.argv) > 4 else 0
    costs = parse(path)
    fns = [f for f in costs if f and sub in f]
    total = {}
    for f in fns:
        for a, c in costs[f].items():
            total[a] = total.get(a, 0) + c
    if not total:
        sys.exit("no such function in the profile")
    lo, hi = min(total), max(total)
    dis = subprocess.run(["objdump", "-d", "--no-show-raw-insn", "-l", "-C",
                          f"--start-address={lo:#x}", f"--stop-address={hi + 16:#x}", binary],
                         capture_output=True, text=True).stdout
    s = 0
    for line in dis.splitlines():
        m = re.match(r"\s*([0-9a-f]+):\s+(.*)", line)
        if m:
            a = int(m.group(1), 16)
            c = total.get(a, 0)
            s += c
            if c >= min_count:
                print(f"{c:12d}  {a:x}: {m.group(2)}")
        elif line.startswith("/"):
            print("            " + line.split("/work/main/")[-1])
    print(f"total {s}")


main()
