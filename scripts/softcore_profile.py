#!/usr/bin/env python3
"""The per-instruction cycle profile of one call of the `cycles` binary on
VexRiscv (scripts/softcore --profile): formats the profile the LiteX SoC's
driver writes (demo/softcore/litex_sim.cpp with LITEX_SIM_PROFILE and
LITEX_SIM_PROFILE_ROOT: every call of the root function, callees included,
each cycle charged to the next instruction that leaves the last stage)
with the image's disassembly (llvm-objdump).

Usage:
  softcore_profile.py --root-address ELF SYMBOL   prints the address of the
      function whose demangled name is SYMBOL (e.g. `cycles::trilinear`)
  softcore_profile.py --report ELF PROFILE TITLE  prints the profile: per
      function and per instruction, instructions and cycles per call
  softcore_profile.py --window ELF SYMBOL LOOP  prints the addresses of
      the two `rdcycle`s around the call of SYMBOL in the timed loop LOOP
      (`timed_a` or `timed_b` of `counters::series`): the timed window,
      for the per-call profile
  softcore_profile.py --calls ELF CALLS TITLE  prints the calls one by
      one (litex_sim.cpp's LITEX_SIM_PROFILE_CALLS file): the cycles of
      every call, and the slowest timed call beside the fastest (the
      warm-up calls of `counters::series` left out), instruction by
      instruction, with the bus beats in them (the lines refilled and
      whose symbol they hold)
  softcore_profile.py --self-test
"""
import re
import subprocess
import sys

# The texture co-processor's custom-0 instructions by (funct7, funct3)
# (src/coproc/mod.rs has the encoding): llvm-objdump prints them as
# `<unknown>`.
CUSTOM0 = 0b0001011
CUSTOM_NAMES = {
    (0, 0): "tex.log2pl", (0, 1): "tex.lod", (0, 2): "tex.bw", (0, 3): "tex.bt", (0, 4): "tex.bb",
    (0, 5): "tex.blend", (1, 0): "tex.lvl", (1, 1): "tex.addr", (1, 2): "tex.tap10", (1, 3): "tex.tap01",
    (1, 4): "tex.tap11", (2, 0): "tex.ram", (2, 1): "tex.sel", (2, 2): "tex.tri", (2, 3): "tex.bil",
}
SYM_RE = re.compile(r"^([0-9a-f]{8}) <(.+)>:$")
INSN_RE = re.compile(r"^\s*([0-9a-f]+):\s+((?:[0-9a-f]{2} )+)\s*(.*)$")


def custom_name(word):
    """The co-processor instruction of the 32-bit `word` (its registers),
    or None when it is no custom-0 instruction."""
    if word & 0x7F != CUSTOM0:
        return None
    f3, f7 = (word >> 12) & 7, word >> 25
    rd, rs1, rs2 = (word >> 7) & 31, (word >> 15) & 31, (word >> 20) & 31
    name = CUSTOM_NAMES.get((f7, f3), f"custom-0 f7={f7} f3={f3}")
    return f"{name} x{rd}, x{rs1}, x{rs2}"


def disassemble(elf):
    """[(address, function, text)] of every instruction of the image, in
    address order (function: the demangled symbol it is in)."""
    out = subprocess.run(["llvm-objdump", "-d", "-C", "--mattr=+m", elf], check=True,
                         capture_output=True, text=True).stdout
    return parse_disassembly(out)


def parse_disassembly(text):
    insns, func = [], None
    for line in text.splitlines():
        m = SYM_RE.match(line)
        if m:
            # Local labels (`.L0 `, `.LBB…`) and the mapping symbols
            # (`$x`, `$d`) do not start a function.
            if not m.group(2).startswith((".L", "$")):
                func = m.group(2)
            continue
        m = INSN_RE.match(line)
        if m and func:
            raw = bytes.fromhex(m.group(2).replace(" ", ""))
            text_ = " ".join(m.group(3).split())
            if len(raw) == 4:
                c = custom_name(int.from_bytes(raw, "little"))
                if c:
                    text_ = c
            insns.append((int(m.group(1), 16), func, text_))
    return insns


def root_address(insns, symbol):
    """The first address of the function whose name, without its hash
    suffix, is `symbol`."""
    for addr, func, _ in insns:
        if re.sub(r"::h[0-9a-f]{16}$", "", func) == symbol:
            return addr
    sys.exit(f"softcore_profile.py: no function {symbol} in the image")


def parse_profile(text):
    """(calls, {pc: (retired, cycles)})."""
    calls, prof = None, {}
    for line in text.splitlines():
        p = line.split()
        if p[0] == "calls":
            calls = int(p[1])
        elif len(p) == 3:
            prof[int(p[0], 16)] = (int(p[1]), int(p[2]))
    if not calls:
        sys.exit("softcore_profile.py: the profile has no calls")
    return calls, prof


# Instructions listed by their cycles above one.
TOP = 12


def kind(text):
    """The kind of a disassembled instruction, for the profile's summary."""
    m = text.split()[0] if text else "?"
    if m.startswith("tex.") or m.startswith("custom-0"):
        return "co-processor"
    if m in ("lw", "lh", "lhu", "lb", "lbu"):
        return "load"
    if m in ("sw", "sh", "sb"):
        return "store"
    if m.startswith("b") or m in ("j", "jal", "jalr", "jr", "ret", "call", "tail"):
        return "branch, jump, call, return"
    if m.startswith("mul") or m.startswith("div") or m.startswith("rem"):
        return "multiply, divide"
    return "other"


def report(insns, calls, prof, title):
    """The profile as text lines: totals, per function, per instruction."""
    short = lambda f: re.sub(r"::h[0-9a-f]{16}$", "", f)
    where = {a: (f, t) for a, f, t in insns}
    missing = sorted(pc for pc in prof if pc not in where)
    if missing:
        sys.exit(f"softcore_profile.py: profiled addresses outside the image: {[hex(p) for p in missing[:4]]}")
    tot_i = sum(r for r, _ in prof.values())
    tot_c = sum(c for _, c in prof.values())
    L = [f"profile {title}: {calls} calls, per call {tot_i / calls:.1f} instructions, {tot_c / calls:.1f} cycles "
         f"(every call of the run: warm-up and timed passes)"]
    funcs = {}
    for pc, (r, c) in prof.items():
        f = short(where[pc][0])
        fr, fc = funcs.get(f, (0, 0))
        funcs[f] = (fr + r, fc + c)
    L.append("  per function: instructions / cycles per call")
    for f, (r, c) in sorted(funcs.items(), key=lambda x: -x[1][1]):
        L.append(f"    {r / calls:7.1f} {c / calls:7.1f}  {f}")
    # The cycles above one per instruction, by kind of instruction.
    kinds = {}
    for pc, (r, c) in prof.items():
        k = kind(where[pc][1])
        kr, kc = kinds.get(k, (0, 0))
        kinds[k] = (kr + r, kc + c - r)
    L.append("  per kind: instructions / cycles above one each, per call")
    for k, (r, x) in sorted(kinds.items(), key=lambda x: -x[1][1]):
        L.append(f"    {r / calls:7.1f} {x / calls:7.1f}  {k}")
    top = sorted((pc for pc in prof if prof[pc][1] > prof[pc][0]), key=lambda pc: -(prof[pc][1] - prof[pc][0]))[:TOP]
    L.append(f"  the instructions with the most cycles above one (at most {TOP}), per call")
    for pc in sorted(top):
        r, c = prof[pc]
        L.append(f"    {pc:08x} {(c - r) / calls:6.2f}  {where[pc][1]}")
    L.append("  per instruction: address, executions and cycles per call, cycles per execution, instruction")
    for pc in sorted(prof):
        r, c = prof[pc]
        f, t = where[pc]
        L.append(f"    {pc:08x} {r / calls:5.2f} {c / calls:6.2f} {c / r:5.2f}  {t}  <{short(f)}>")
    return L


def parse_calls(text):
    """[(cycles, [(pc, cycles)], [(kind, address)])] of every call in the
    order of the run; kind `dr`/`dw` a data-bus read/write beat, `f` an
    instruction-bus beat."""
    calls, insns, beats = [], [], []
    for line in text.splitlines():
        p = line.split()
        if p[0] == "i":
            insns.append((int(p[1], 16), int(p[2])))
        elif p[0] == "d":
            beats.append(("d" + p[1], int(p[2], 16)))
        elif p[0] == "f":
            beats.append(("f", int(p[1], 16)))
        elif p[0] == "call":
            calls.append((int(p[3]), insns, beats))
            insns, beats = [], []
    if not calls:
        sys.exit("softcore_profile.py: the per-call profile has no calls")
    return calls


def symbols(elf):
    """[(address, size, name)] of the image's symbols with a size, by address."""
    out = subprocess.run(["llvm-nm", "-S", "-C", "--numeric-sort", elf], check=True,
                         capture_output=True, text=True).stdout
    syms = []
    for line in out.splitlines():
        p = line.split(maxsplit=3)
        if len(p) == 4:
            syms.append((int(p[0], 16), int(p[1], 16), p[3]))
    return syms


def line_owner(syms, addr):
    """The symbols overlapping the 32-byte line of `addr`, or `stack or
    data` for none."""
    lo = addr & ~31
    names = [re.sub(r"::h[0-9a-f]{16}$", "", n) for a, sz, n in syms if a < lo + 32 and a + sz > lo]
    return ", ".join(names[:3]) if names else "no symbol (stack, data)"


def lines_of(beats):
    """The beats collapsed to (kind, 32-byte line, beats) in order."""
    out = []
    for k, a in beats:
        if out and out[-1][0] == k and out[-1][1] == a & ~31:
            out[-1] = (k, a & ~31, out[-1][2] + 1)
        else:
            out.append((k, a & ~31, 1))
    return out


# The inputs of a series (demo/firmware/src/inputs.rs `N`).
N = 64


def timed_calls(n):
    """The indices of the timed calls among `n` calls of one timed loop of
    a series: `timed_a` runs the untimed pass, then the timed pass (2·N
    calls), `timed_b` one untimed call, then the timed pass (N + 1); all
    of them for another count."""
    if n == 2 * N:
        return list(range(N, 2 * N))
    if n == N + 1:
        return list(range(1, N + 1))
    return list(range(n))


def timed_window(insns, symbol, loop):
    """(first, last): the addresses of the two `rdcycle`s around the call
    of `symbol` in the timed loop `loop` (`timed_a` or `timed_b`, the two
    places of `counters::series`) that calls it: the driver's
    LITEX_SIM_PROFILE_ROOT and _END for the timed window, the harness's
    instructions around the call included."""
    target = root_address(insns, symbol)
    by_func = {}
    for a, f, t in insns:
        by_func.setdefault(f, []).append((a, t))
    for f, body in by_func.items():
        if not re.sub(r"::h[0-9a-f]{16}$", "", f).endswith(f"counters::{loop}"):
            continue
        hi = None
        for i, (a, t) in enumerate(body):
            p = t.split()
            callee = None
            if p[0] == "auipc":
                hi = a + (int(p[-1]) << 12)
                continue
            if p[0] == "jalr" and hi is not None:
                m = re.match(r"(-?\d+)\(ra\)$", p[-1])
                callee = hi + int(m.group(1)) if m else None
            elif p[0] in ("jal", "call"):
                callee = int(p[-1], 16) if re.match(r"0x[0-9a-f]+$", p[-1]) else None
            hi = None
            if callee == target:
                before = [b for b, u in body[:i] if u.startswith("rdcycle")]
                after = [b for b, u in body[i:] if u.startswith("rdcycle")]
                if before and after:
                    return before[-1], after[0]
    sys.exit(f"softcore_profile.py: no {loop} calls {symbol}")


def calls_report(insns, syms, calls, title):
    """The per-call profile as text lines."""
    where = {a: t for a, _, t in insns}
    cyc = [c for c, _, _ in calls]
    timed = timed_calls(len(calls))
    L = [f"calls {title}: {len(calls)} calls, cycles min {min(cyc)} max {max(cyc)}",
         "  cycles of every call in the order of the run (16 a line)"]
    for i in range(0, len(cyc), 16):
        L.append(f"    {i:4d}: " + " ".join(f"{c:4d}" for c in cyc[i:i + 16]))
    slow = max(timed, key=lambda i: cyc[i])
    fast = min(timed, key=lambda i: cyc[i])
    L.append(f"  the slowest timed call ({slow}, {cyc[slow]} cycles) beside the fastest ({fast}, {cyc[fast]}): "
             "address, cycles slow / fast, instruction")
    si, fi = calls[slow][1], calls[fast][1]
    for n, (pc, c) in enumerate(si):
        f = fi[n][1] if n < len(fi) and fi[n][0] == pc else None
        mark = " <" if f is not None and c > f else ""
        L.append(f"    {pc:08x} {c:4d} / {'-' if f is None else f:>4}  {where.get(pc, '?')}{mark}")
    for name, i in (("slowest", slow), ("fastest", fast)):
        L.append(f"  bus beats of the {name} call: kind, 32-byte line, beats, what the line holds")
        for k, a, n in lines_of(calls[i][2]):
            kind_ = {"f": "instruction fetch", "dr": "data read", "dw": "data write"}[k]
            L.append(f"    {kind_:17s} {a:08x} {n}  {line_owner(syms, a)}")
    return L


def self_test():
    dis = """
40007fa0 <cycles::trilinear::hb6c9bbe5464bdb49>:
40007fa0: 03 46 c5 3b   lbu     a2, 956(a0)
40007fa4 <.L0 >:
40007fa4: 0b 16 b5 04   <unknown>
"""
    insns = parse_disassembly(dis)
    assert insns == [(0x40007FA0, "cycles::trilinear::hb6c9bbe5464bdb49", "lbu a2, 956(a0)"),
                     (0x40007FA4, "cycles::trilinear::hb6c9bbe5464bdb49", "tex.sel x12, x10, x11")], insns
    assert root_address(insns, "cycles::trilinear") == 0x40007FA0
    calls, prof = parse_profile("calls 2\n40007fa0 2 10\n40007fa4 2 6\n")
    assert (calls, prof) == (2, {0x40007FA0: (2, 10), 0x40007FA4: (2, 6)})
    lines = report(insns, calls, prof, "t")
    assert lines[0].startswith("profile t: 2 calls, per call 2.0 instructions, 8.0 cycles"), lines[0]
    assert "    40007fa4  1.00   3.00  3.00  tex.sel x12, x10, x11  <cycles::trilinear>" in lines, lines
    assert "        1.0     4.0  load" in lines and "        1.0     2.0  co-processor" in lines, lines
    assert kind("bltu a0, a1, 0x10") == kind("ret") and kind("mulhu a0, a1, a2") == "multiply, divide"
    calls = parse_calls("i 40007fa0 3\nd r 40001004\nd r 40001008\ni 40007fa4 9\ncall 0 cycles 12\n"
                        "i 40007fa0 1\ni 40007fa4 3\ncall 1 cycles 4\n")
    assert [c for c, _, _ in calls] == [12, 4] and lines_of(calls[0][2]) == [("dr", 0x40001000, 2)], calls
    L = calls_report(insns, [(0x40001000, 8, "cycles::TABLE")], calls, "t")
    assert "    40007fa4    9 /    3  tex.sel x12, x10, x11 <" in L, L
    assert "    data read         40001000 2  cycles::TABLE" in L, L
    print("softcore_profile.py: self-test passed")


def main():
    a = sys.argv[1:]
    if a == ["--self-test"]:
        self_test()
    elif len(a) == 3 and a[0] == "--root-address":
        print(f"0x{root_address(disassemble(a[1]), a[2]):08x}")
    elif len(a) == 4 and a[0] == "--report":
        calls, prof = parse_profile(open(a[2]).read())
        print("\n".join(report(disassemble(a[1]), calls, prof, a[3])))
    elif len(a) == 4 and a[0] == "--window" and a[3] in ("timed_a", "timed_b"):
        first, last = timed_window(disassemble(a[1]), a[2], a[3])
        print(f"0x{first:08x} 0x{last:08x}")
    elif len(a) == 4 and a[0] == "--calls":
        calls = parse_calls(open(a[2]).read())
        print("\n".join(calls_report(disassemble(a[1]), symbols(a[1]), calls, a[3])))
    else:
        sys.exit(__doc__)


if __name__ == "__main__":
    main()
