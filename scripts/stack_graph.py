#!/usr/bin/env python3
"""Static worst-case stack depth of firmware entry points (scripts/stack-sizes).

Reads an ELF built with `-Z emit-stack-sizes` (Cortex-M Thumb or RV32):

* the `.stack_sizes` sections: one entry per function, the function address
  as a 32-bit little-endian word, then its static frame size in bytes as
  ULEB128 (Thumb addresses have bit 0 set; it is cleared);
* the symbol table (STT_FUNC symbols with their sizes: the function bodies);
* the disassembly (`llvm-objdump -d`), from which the call graph is built:
  direct calls (`bl`; `jal`, `auipc`+`jalr`), and branches that leave the
  function (tail calls: `b`/`b.w`/`b<cond>`; `j`, `auipc`+`jr`).

The worst case of a function is its own frame plus the largest worst case of
its callees (a call pushes nothing on either architecture: the return
address goes to `lr`/`ra`). A tail call is counted like a call (the caller's
frame on top), which over-estimates when the frame is popped before the
branch: an upper bound. The depth is "unbounded" (and the run fails) when a
reachable function is recursive or makes an indirect call or jump that is
not resolved (`blx rN`, `bx rN`, writes to `pc`; `jalr rN`, `jr rN`: function
pointers, trait objects, jump tables). A reachable function without a
`.stack_sizes` entry (precompiled `core`/`compiler_builtins` code) fails too,
unless it is a compiler-builtins routine (`__aeabi_*`, `memcpy`, ...,
`compiler_builtins::*`): then its frame is bounded from its body (the sum of all stack-pointer
decrements: `push`, `vpush`, `sub sp`; `addi sp, sp, -N`) and a note says
so; any other write to the stack pointer in such a body fails.

Usage:
  stack_graph.py --arch arm|riscv --elf FILE [--objdump PROG] [--out FILE]
                 LABEL=SYMBOL ...
  stack_graph.py --arch arm|riscv --elf FILE --reachable LABEL=SYMBOL ...
  stack_graph.py --self-test

With --reachable, prints the name of every function the entries reach
through the call graph (the entries included), one per line, and no stack
depth (scripts/link-checks greps them for soft-float routines).

SYMBOL is a mangled or demangled (llvm-cxxfilt) function name. Prints the
worst case and the deepest path of each entry; with --out writes one line
`LABEL BYTES` (or `LABEL unbounded`) per entry. Exit status 1 when any
entry is unbounded or the input cannot be analysed. Standard library only.
"""

from __future__ import annotations

import argparse
import bisect
import re
import shutil
import struct
import subprocess
import sys

BUILTIN = re.compile(
    r"^(__aeabi_\w+|__(u?(div|mod)|mul|ash[lr]|lshr|clz|ctz|popcount|cmp|ucmp)\w*"
    r"|memcpy|memmove|memset|memcmp|bcmp|__llvm_memcpy\w*|__llvm_memset\w*)$"
)


def is_builtin(name):
    """Compiler-builtins routines: precompiled without .stack_sizes."""
    return bool(BUILTIN.match(name)) or "compiler_builtins" in name


class Unbounded(Exception):
    """The depth of an entry cannot be bounded (recursion, indirect call, ...)."""


# --------------------------------------------------------------------------
# The graph computation (independent of ELF and disassembly: the self-test
# drives it with synthetic data).


class Graph:
    """frames: addr -> bytes (None: no .stack_sizes entry); edges: addr ->
    set of callee addrs; problems: addr -> list of reasons the function's
    depth cannot be bounded (indirect calls/jumps); names: addr -> name;
    estimated: addr -> bytes bounded from the body (builtins only)."""

    def __init__(self, frames, edges, problems, names, estimated=None):
        self.frames = frames
        self.edges = edges
        self.problems = problems
        self.names = names
        self.estimated = estimated or {}
        self.notes: list[str] = []

    def name(self, a):
        return self.names.get(a, hex(a))

    def frame(self, a):
        f = self.frames.get(a)
        if f is not None:
            return f
        if a in self.estimated and is_builtin(self.names.get(a, "")):
            note = (f"{self.name(a)}: no .stack_sizes entry (compiler builtin); "
                    f"frame {self.estimated[a]} bytes bounded from its body")
            if note not in self.notes:
                self.notes.append(note)
            return self.estimated[a]
        raise Unbounded(f"{self.name(a)} has no .stack_sizes entry")

    def worst(self, entry):
        """(bytes, path [(name, frame)]) of the deepest call chain from entry."""
        memo: dict[int, tuple[int, list]] = {}
        on_path: list[int] = []

        def go(a):
            if a in memo:
                return memo[a]
            if a in on_path:
                cycle = on_path[on_path.index(a):] + [a]
                raise Unbounded("recursion: " + " -> ".join(self.name(x) for x in cycle))
            for p in self.problems.get(a, []):
                raise Unbounded(f"{self.name(a)}: {p}")
            own = self.frame(a)
            on_path.append(a)
            best = (0, [])
            for c in sorted(self.edges.get(a, ())):
                d = go(c)
                if d[0] > best[0] or not best[1]:
                    best = d
            on_path.pop()
            r = (own + best[0], [(self.name(a), own)] + best[1])
            memo[a] = r
            return r

        return go(entry)


# --------------------------------------------------------------------------
# ELF32 little-endian: symbols and .stack_sizes.


def read_elf(path, need_sizes=True):
    data = open(path, "rb").read()
    if data[:4] != b"\x7fELF" or data[4] != 1 or data[5] != 1:
        raise SystemExit(f"{path}: not a 32-bit little-endian ELF")
    shoff, = struct.unpack_from("<I", data, 0x20)
    shentsize, shnum, shstrndx = struct.unpack_from("<HHH", data, 0x2E)
    secs = []
    for i in range(shnum):
        nm, typ, flags, addr, off, size, link, info, align, entsize = struct.unpack_from(
            "<IIIIIIIIII", data, shoff + i * shentsize)
        secs.append(dict(nm=nm, type=typ, off=off, size=size, link=link, entsize=entsize))
    shstr = secs[shstrndx]

    def cstr(off):
        return data[off:data.index(b"\0", off)].decode()

    for s in secs:
        s["name"] = cstr(shstr["off"] + s["nm"])
    funcs: dict[int, tuple[str, int]] = {}
    for s in secs:
        if s["type"] != 2:  # SHT_SYMTAB
            continue
        strtab = secs[s["link"]]
        for k in range(s["size"] // 16):
            st_name, value, size, info, other, shndx = struct.unpack_from(
                "<IIIBBH", data, s["off"] + 16 * k)
            if info & 0xF != 2 or size == 0:  # STT_FUNC with a body
                continue
            name = cstr(strtab["off"] + st_name)
            a = value & ~1
            old = funcs.get(a)
            # Aliases: keep the global (binding 1) or the first name.
            if old is None or (info >> 4 == 1 and not old[0].startswith("_R")):
                funcs[a] = (name, size)
    sizes: dict[int, int] = {}
    found = False
    for s in secs:
        if s["name"] != ".stack_sizes":
            continue
        found = True
        p, end = s["off"], s["off"] + s["size"]
        while p < end:
            a, = struct.unpack_from("<I", data, p)
            p += 4
            v, shift = 0, 0
            while True:
                b = data[p]
                p += 1
                v |= (b & 0x7F) << shift
                shift += 7
                if b < 0x80:
                    break
            a &= ~1
            sizes[a] = max(v, sizes.get(a, 0))
    if not found and need_sizes:
        raise SystemExit(f"{path}: no .stack_sizes section (build with -Z emit-stack-sizes)")
    return funcs, sizes


# --------------------------------------------------------------------------
# Disassembly: call edges, unresolved indirect transfers, body frame bounds.

INSN = re.compile(r"^\s*([0-9a-f]+):\s+(\S+)\s*(.*)$")
COND = "(?:eq|ne|cs|hs|cc|lo|mi|pl|vs|vc|hi|ls|ge|lt|gt|le|al)?"
ARM_BR = re.compile(rf"^(bl|blx|b|bx|cbz|cbnz){COND}(?:\.w|\.n)?$")
HEX = re.compile(r"0x([0-9a-f]+)")


def reglist_len(ops):
    m = re.search(r"\{([^}]*)\}", ops)
    if not m:
        return None
    n = 0
    for part in m.group(1).split(","):
        part = part.strip()
        r = re.fullmatch(r"([rsd])(\d+)-[rsd](\d+)", part)
        n += int(r.group(3)) - int(r.group(2)) + 1 if r else 1
    return n


def analyse_arm(insns):
    """insns: [(addr, mnemonic, operands)] of one function. Returns
    (targets, problems, sp_decrement_sum or None when unknown)."""
    targets, problems, dec, unknown_sp = [], [], 0, False
    for a, mn, ops in insns:
        ops = ops.split("@")[0].strip()
        m = ARM_BR.match(mn)
        if m:
            kind = m.group(1)
            h = HEX.match(ops.split(",")[-1].strip()) if kind in ("cbz", "cbnz") else HEX.match(ops)
            if h:
                targets.append((a, int(h.group(1), 16), kind == "bl" or kind == "blx"))
            elif kind == "bx" and ops == "lr":
                pass
            else:
                what = "indirect call" if kind == "blx" else "indirect jump"
                problems.append(f"{what} `{mn} {ops}` at {a:#x}")
            continue
        first = ops.split(",")[0].strip()
        if mn.startswith(("pop", "ldm")) and "pc" in ops:
            if mn.startswith("ldm") and not ops.startswith("sp!"):
                problems.append(f"indirect jump `{mn} {ops}` at {a:#x}")
            continue
        if first == "pc" and not mn.startswith(("cmp", "tst", "str")):
            if mn.startswith("ldr") and re.match(r"pc,\s*\[sp\],\s*#4$", ops):
                continue  # pop {pc}
            problems.append(f"indirect jump `{mn} {ops}` at {a:#x}")
            continue
        if mn.startswith(("push", "vpush")) or (mn.startswith("stmdb") and ops.startswith("sp!")):
            n = reglist_len(ops)
            if n is None:
                unknown_sp = True
            else:
                dregs = re.search(r"\{\s*d", ops) is not None
                dec += n * (8 if dregs else 4)
        elif first == "sp" and mn.startswith("sub"):
            h = re.search(r"#(\d+)$", ops)
            if h:
                dec += int(h.group(1))
            else:
                unknown_sp = True
        elif first == "sp" and not mn.startswith(("add", "cmp", "ldr", "str")):
            unknown_sp = True
        elif mn.startswith("str") and re.search(r"\[sp,\s*#-(\d+)\]!", ops):
            dec += int(re.search(r"\[sp,\s*#-(\d+)\]!", ops).group(1))
    return targets, problems, None if unknown_sp else dec


RV_BRANCH = re.compile(r"^(beq|bne|blt|bge|bltu|bgeu|beqz|bnez|blez|bgez|bltz|bgtz|bgt|ble|bgtu|bleu|j|jal)$")
REG_OFF = re.compile(r"^(-?\d+)\((\w+)\)$")


def analyse_riscv(insns):
    targets, problems, dec, unknown_sp = [], [], 0, False
    auipc: dict[str, int] = {}
    for a, mn, ops in insns:
        ops = ops.strip()
        parts = [p.strip() for p in ops.split(",")] if ops else []
        if mn == "auipc":
            imm = int(parts[1])
            if imm >= 1 << 19:
                imm -= 1 << 20
            auipc = {parts[0]: (a + (imm << 12)) & 0xFFFFFFFF}
            continue
        known = auipc
        auipc = {}
        if RV_BRANCH.match(mn):
            h = HEX.match(parts[-1]) if parts else None
            if not h:
                problems.append(f"unparsed branch `{mn} {ops}` at {a:#x}")
                continue
            call = mn == "jal" and (len(parts) == 1 or parts[0] == "ra")
            targets.append((a, int(h.group(1), 16), call))
            continue
        if mn in ("jalr", "jr", "c.jalr", "c.jr"):
            call = mn in ("jalr", "c.jalr") and (len(parts) == 1 or parts[0] == "ra")
            src = parts[-1] if parts else ""
            r = REG_OFF.match(src)
            off, reg = (int(r.group(1)), r.group(2)) if r else (0, src)
            if mn == "jr" and reg == "ra" and off == 0:
                continue  # return
            if reg in known:
                targets.append((a, (known[reg] + off) & 0xFFFFFFFF, call))
            else:
                what = "indirect call" if call else "indirect jump"
                problems.append(f"{what} `{mn} {ops}` at {a:#x}")
            continue
        if mn in ("ret", "c.ret"):
            continue
        if parts and parts[0] == "sp":
            if mn in ("addi", "c.addi", "c.addi16sp") and len(parts) >= 2:
                v = int(parts[-1])
                if v < 0:
                    dec += -v
            elif mn in ("lw", "sw", "c.lwsp", "c.swsp"):
                pass
            else:
                unknown_sp = True
    return targets, problems, None if unknown_sp else dec


def parse_insns(lines):
    """`(address, mnemonic, operands)` of every instruction line of an
    `objdump -d --no-show-raw-insn` listing, in order."""
    out = []
    for line in lines:
        m = INSN.match(line)
        if m:
            out.append((int(m.group(1), 16), m.group(2), m.group(3)))
    return out


def build_graph(arch, elf, objdump, need_sizes=True):
    funcs, sizes = read_elf(elf, need_sizes)
    out = subprocess.run([objdump, "-d", "--no-show-raw-insn", elf], check=True,
                         capture_output=True, text=True).stdout
    starts = sorted(funcs)
    body: dict[int, list] = {a: [] for a in starts}
    for a, mnemonic, operands in parse_insns(out.splitlines()):
        i = bisect.bisect_right(starts, a) - 1
        if i < 0:
            continue
        f = starts[i]
        if a < f + funcs[f][1]:
            body[f].append((a, mnemonic, operands))
    names = {a: n for a, (n, _) in funcs.items()}
    cxxfilt = shutil.which("llvm-cxxfilt")
    if cxxfilt:
        order = list(names)
        dem = subprocess.run([cxxfilt], input="\n".join(names[a] for a in order), check=True,
                             capture_output=True, text=True).stdout.splitlines()
        if len(dem) == len(order):
            names = dict(zip(order, dem))
    analyse = analyse_arm if arch == "arm" else analyse_riscv
    edges, problems, estimated = {}, {}, {}
    for f in starts:
        targets, probs, dec = analyse(body[f])
        end = f + funcs[f][1]
        es = set()
        for at, t, call in targets:
            if f <= t < end and not call:
                continue  # branch inside the function
            if t not in funcs:
                probs.append(f"branch at {at:#x} to {t:#x}, not the start of a function")
                continue
            es.add(t)
        edges[f] = es
        if probs:
            problems[f] = probs
        if dec is not None:
            estimated[f] = dec
    frames = {a: sizes.get(a) for a in starts}
    return Graph(frames, edges, problems, names, estimated), funcs, names


# --------------------------------------------------------------------------


def self_test():
    """Synthetic graphs and instruction lists with known answers."""
    ok = True

    def expect(what, got, want):
        nonlocal ok
        if got != want:
            ok = False
            print(f"self-test FAIL {what}: got {got!r}, want {want!r}")

    def expect_unbounded(what, g):
        """The `Unbounded` message of `g.worst(1)`, or None (a failure)."""
        try:
            g.worst(1)
        except Unbounded as e:
            return str(e)
        expect(what, "bounded", "unbounded")
        return None

    # main(16) -> a(8) -> leaf(4); main -> b(40): worst is main + b = 56;
    # a + leaf = 12 < 40.
    g = Graph({1: 16, 2: 8, 3: 4, 4: 40}, {1: {2, 4}, 2: {3}}, {},
              {1: "main", 2: "a", 3: "leaf", 4: "b"})
    expect("sum", g.worst(1)[0], 56)
    expect("path", [n for n, _ in g.worst(1)[1]], ["main", "b"])
    expect("chain", g.worst(2)[0], 12)
    # Recursion a -> b -> a is unbounded.
    g = Graph({1: 8, 2: 8, 3: 8}, {1: {2}, 2: {3}, 3: {2}}, {}, {1: "m", 2: "a", 3: "b"})
    e = expect_unbounded("recursion detected", g)
    expect("recursion message", e is not None and "recursion: a -> b -> a" in e, True)
    # Indirect call: unbounded; missing frame: unbounded unless a builtin.
    g = Graph({1: 8, 2: 8}, {1: {2}}, {2: ["indirect call `blx r3` at 0x10"]}, {1: "m", 2: "f"})
    expect_unbounded("indirect detected", g)
    g = Graph({1: 8, 2: None}, {1: {2}}, {}, {1: "m", 2: "core_fn"}, {2: 16})
    expect_unbounded("missing frame detected", g)
    g = Graph({1: 8, 2: None}, {1: {2}}, {}, {1: "m", 2: "__aeabi_uldivmod"}, {2: 16})
    expect("builtin from body", g.worst(1)[0], 24)
    # Thumb: push/sub counted, bl is a call, b.w out of the function a tail
    # call, blx reg indirect. The listings are objdump text, read through
    # the parser of a real disassembly.
    t, p, d = analyse_arm(parse_insns("""
     100: push\t{r4, r5, r7, lr}
     102: sub\tsp, #24
     104: vpush\t{d8, d9}
     108: bl\t0x200 <f> @ imm = #248
     10c: beq\t0x104 <x+0x4>
     10e: b.w\t0x300 <g> @ imm = #1
     112: blx\tr3
     114: pop\t{r4, r5, r7, pc}
    """.splitlines()))
    expect("arm targets", t, [(0x108, 0x200, True), (0x10c, 0x104, False), (0x10e, 0x300, False)])
    expect("arm problems", len(p), 1)
    expect("arm decrement", d, 16 + 24 + 16)
    # RISC-V: auipc+jalr call, auipc+jr tail call, jal, jr reg indirect.
    t, p, d = analyse_riscv(parse_insns("""
    1000: addi\tsp, sp, -32
    1004: auipc\tra, 1048575
    1008: jalr\t-8(ra)
    100c: jal\t0x2000 <f>
    1010: jr\ta5
    1012: auipc\tt1, 1
    1016: jr\t8(t1)
    101a: addi\tsp, sp, 32
    101c: ret
    """.splitlines()))
    expect("rv targets", t, [(0x1008, (0x1004 - 4096 - 8) & 0xFFFFFFFF, True), (0x100c, 0x2000, True),
                             (0x1016, 0x1012 + 4096 + 8, False)])
    expect("rv problems", len(p), 1)
    expect("rv decrement", d, 32)
    print("self-test:", "ok" if ok else "FAILED")
    return 0 if ok else 1


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--self-test", action="store_true")
    ap.add_argument("--arch", choices=["arm", "riscv"])
    ap.add_argument("--elf")
    ap.add_argument("--objdump", default="llvm-objdump")
    ap.add_argument("--out")
    ap.add_argument("--reachable", action="store_true")
    ap.add_argument("entries", nargs="*", metavar="LABEL=SYMBOL")
    args = ap.parse_args()
    if args.self_test:
        return self_test()
    if not args.arch or not args.elf or not args.entries:
        ap.error("--arch, --elf and at least one LABEL=SYMBOL are required")
    g, funcs, names = build_graph(args.arch, args.elf, args.objdump, not args.reachable)
    by_name = {}
    for a, (n, _) in funcs.items():
        by_name.setdefault(n, a)
        by_name.setdefault(names[a], a)
    if args.reachable:
        todo = []
        for spec in args.entries:
            sym = spec.partition("=")[2]
            if sym not in by_name:
                print(f"{args.elf}: no function named {sym}", file=sys.stderr)
                return 1
            todo.append(by_name[sym])
        seen = set(todo)
        while todo:
            for c in g.edges.get(todo.pop(), ()):
                if c not in seen:
                    seen.add(c)
                    todo.append(c)
        print("\n".join(sorted(funcs[a][0] for a in seen)))
        return 0
    # The body bound used for builtins, checked against .stack_sizes on every
    # function that has both: it must never be below the compiler's number.
    both = [a for a in g.frames if g.frames[a] is not None and a in g.estimated]
    under = [a for a in both if g.estimated[a] < g.frames[a]]
    print(f"  body bound vs .stack_sizes: {len(both) - len(under)} of {len(both)} functions "
          f"bounded ({sum(g.estimated[a] == g.frames[a] for a in both)} equal)")
    for a in under:
        print(f"  body bound {g.estimated[a]} < .stack_sizes {g.frames[a]}: {names[a]}")
    lines, failed = [], bool(under)
    for spec in args.entries:
        label, _, sym = spec.partition("=")
        if sym not in by_name:
            print(f"{args.elf}: {label}: no function named {sym}")
            return 1
        try:
            total, path = g.worst(by_name[sym])
            chain = " -> ".join(f"{n} ({f})" for n, f in path)
            print(f"  {label}: {total} bytes: {chain}")
            lines.append(f"{label} {total}")
        except Unbounded as e:
            failed = True
            print(f"  {label}: unbounded: {e}")
            lines.append(f"{label} unbounded")
    for n in g.notes:
        print(f"  note: {n}")
    if args.out:
        with open(args.out, "w") as f:
            f.write("\n".join(lines) + "\n")
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
