#!/usr/bin/env python3
"""Writes BUDGETS.md from the measurements `scripts/budgets` collected.

Usage: budgets.py WORKDIR ROOT [--check]

WORKDIR holds what scripts/budgets produced: per ISA variant (m4, rv, rvzbb)
the QEMU execution trace (NAME.trace), the semihosting output (NAME.out) and
the symbol table (NAME.nm) of the budget binary; size-T-B.txt (`size -A`),
demo-T.out (demo output), static-T.txt (scripts/stack-sizes).

Counts every call of each `rm_bench_*` / `rm_batch_*` wrapper from its entry
to the return into `rm_budget_driver`, checks the ceilings below (exit 1 and
FAIL lines when one is exceeded) and writes ROOT/BUDGETS.md and the
sampler-budgets block of ROOT/docs/texture-sampling.md (sampler-state instructions beside
the errors of docs/texture-sampling.md's sampler-accuracy block), or with --check
compares both with the checked-in files (exit 1 when stale; the block
between the softcore markers belongs to another script and is kept verbatim
and ignored by the comparison).
"""
import os
import re
import sys

from mdblock import page_head

ARM, RV = "thumbv7em-none-eabihf", "riscv32imac-unknown-none-elf"
ISAS = [("m4", "Cortex-M4"), ("rv", "RV32IMAC"), ("rvzbb", "RV32IMAC+Zbb")]
CALLS = [("lod", "table lod"), ("cone_lod", "cone lod (with n·d)"),
         ("bilinear", "bilinear sample"), ("trilinear", "trilinear sample")]
# FAST paths (issue 10: where a goal and the present accuracy cannot both
# be met, a fast path with its own documented bound beside the accurate one).
FAST_CALLS = [("lod_fast", "table lod FAST"), ("cone_lod_fast", "cone lod FAST (with n·d)"),
              ("trilinear_fast", "trilinear sample FAST")]
# The accurate call each fast path stands in for (its goal applies).
FAST_OF = {"lod_fast": "lod", "cone_lod_fast": "cone_lod", "trilinear_fast": "trilinear"}
# FAST paths with a batch wrapper (`rm_batch_*`) in the budget binary.
FAST_BATCHED = {"lod_fast", "cone_lod_fast"}
ALL_CALLS = CALLS[:2] + FAST_CALLS[:2] + CALLS[2:] + FAST_CALLS[2:]
BEGIN, END = "<!-- softcore:begin -->", "<!-- softcore:end -->"
README_BEGIN, README_END = "<!-- sampler-budgets:begin -->", "<!-- sampler-budgets:end -->"

# Ray differentials (feature `raydiff`, issue 21): (key, label), wrapper
# `rm_bench_<key>`, 64 calls each.
RD_ROWS = [("rd_primary", "primary set-up from the camera"),
           ("rd_transfer", "transfer to a hit"),
           ("rd_reflect", "reflection (shading-normal differentials)"),
           ("rd_refract", "refraction (shading-normal differentials)"),
           ("rd_footprint", "footprint (two texel-space axes)"),
           ("rd_lod", "lod from the footprint (larger axis)"),
           ("rd_gbuffer", "G-buffer first-hit set-up (four neighbours)")]
# The QEMU rows of the ray-differential table: RD_ROWS (also the soft-core
# rows, scripts/softcore.py) and the G-buffer hit's normal differentials
# (for a bounce only), measured here alone.
RD_BUDGET_ROWS = RD_ROWS + [("rd_gbuffer_normals", "G-buffer normal differentials (for a bounce)")]
# Cortex-M4 goals of the ray differentials (issue 33; max instructions):
# per call, and per textured hit as sums of rows.
RD_GOALS = {"rd_primary": 150, "rd_transfer": 150, "rd_reflect": 120, "rd_refract": 300,
            "rd_gbuffer": 150}
RD_SUM_GOALS = [("footprint + lod", ["rd_footprint", "rd_lod"], 150),
                ("ray-traced per textured hit (transfer + footprint + lod)",
                 ["rd_transfer", "rd_footprint", "rd_lod"], 300),
                ("G-buffer per first hit (set-up + footprint + lod)",
                 ["rd_gbuffer", "rd_footprint", "rd_lod"], 180)]
# The sums whose goal is met: CI fails when one rises above its goal again
# (each row has its own ceiling too, but the rows' ceilings, each its
# achieved count + 5 %, add up to more than the goal).
RD_SUMS_AT_GOAL = {label for label, _, _ in RD_SUM_GOALS}
# Environment map (feature `envmap`, issue 21): (key, label), wrapper
# `rm_bench_<key>`, 64 calls each.
ENV_ROWS = [("env_cone", "cone lod, equator texel (no direction)"),
            ("env_cone_lat", "cone lod with the pole term"),
            ("env_raydiff", "ray-differential lod with the pole term"),
            ("env_uv", "direction → (u, v), two 32-bit vectorings (3 CORDIC steps + series)")]

# Sampler-state (ts_*) rows: (key, label, wrapper, its calls of this row, the
# sampler-accuracy cell of the README (format, filter) or None). The order
# of the calls is the one of demo/firmware/src/bin/budget.rs.
SAMPLER_ROWS = [
    ("ts_bilinear", "RGBA8 bilinear (sampler state)", "rm_bench_ts_bilinear", slice(0, 64),
     ("Rgba8", "bilinear")),
    ("ts_trilinear", "RGBA8 trilinear (sampler state)", "rm_bench_ts_trilinear", slice(0, 64),
     ("Rgba8", "trilinear")),
    ("ts_srgb", "RGBA8 sRGB trilinear, re-encoded", "rm_bench_ts_srgb", slice(0, 64),
     ("Rgba8_SRGB (encoded)", "trilinear")),
    ("ts_rgb565", "RGB565 trilinear", "rm_bench_ts_rgb565", slice(0, 64), ("Rgb565", "trilinear")),
    ("ts_bc1_fill", "BC1 trilinear, cache filled (blocks decoded)", "rm_bench_ts_bc1",
     slice(0, 128, 2), ("Bc1", "trilinear")),
    ("ts_bc1_hit", "BC1 trilinear, cache hits", "rm_bench_ts_bc1", slice(1, 128, 2),
     ("Bc1", "trilinear")),
    ("ts_aniso2", "anisotropic 2× sample", "rm_bench_ts_aniso", slice(0, 64), None),
    ("ts_aniso4", "anisotropic 4× sample", "rm_bench_ts_aniso", slice(64, 128), None),
    ("ts_aniso16", "anisotropic 16× sample", "rm_bench_ts_aniso", slice(128, 192),
     ("Rgba8", "anisotropic 16x (trilinear probes)")),
]

# The sampler matrix of issues 20 and 32 (demo/firmware/src/probes.rs
# `sampler_rows`): (key, label, tier, wrapper, its calls of this row, goal).
# A goal is a number per ISA (max instructions per call: issue 32's table,
# RV32IMAC's for Zbb too) or a relative goal (factor, row key of the same
# tier it is relative to, added constant): `factor × that row's max +
# constant`.
def per_isa(m4, rv):
    """A goal of `m4` instructions on the Cortex-M4, `rv` on RV32IMAC with
    or without Zbb."""
    return {"m4": m4, "rv": rv, "rvzbb": rv}


def both_tiers(key, label, wrappers, calls, goals):
    """The ACCURATE row `key` and the FAST row `<key>_f` of one
    configuration: `wrappers` and `goals` are (ACCURATE, FAST) pairs, a
    relative goal given once (FAST's is relative to the FAST row)."""
    if not isinstance(goals, list):
        goals = [goals, goals if goals is None else (goals[0], goals[1] + "_f", goals[2])]
    return [(key, label, "ACCURATE", wrappers[0], calls, goals[0]),
            (key + "_f", label, "FAST", wrappers[1], calls, goals[1])]


ALL_64 = slice(0, 64)
# The BC1 wrappers are called in pairs (cache filled, then hit).
BC1_FILL, BC1_HIT = slice(0, 128, 2), slice(1, 128, 2)
# The anisotropic wrapper: 64 calls of each probe count in turn.
ANISO = [(n, slice(64 * i, 64 * (i + 1))) for i, n in enumerate((2, 4, 16))]
TS = "rm_bench_ts_"
MATRIX_ROWS = [
    *both_tiers("tw_bil", "RGBA8 bilinear, wrap, bias/clamps set",
                ("matrix:rm_bench_bilinear", "rm_bench_bilinear_fast"), ALL_64,
                [per_isa(85, 115), per_isa(80, 110)]),
    *both_tiers("tw_tri", "RGBA8 trilinear, wrap, bias/clamps set",
                ("matrix:rm_bench_trilinear", "matrix:rm_bench_trilinear_fast"), ALL_64,
                [per_isa(170, 230), per_isa(140, 200)]),
    ("tw_tri_n", "RGBA8 trilinear, wrap, bias/clamps set, with fetch statistics", "ACCURATE",
     "rm_bench_trilinear_counted", ALL_64, None),
    *both_tiers("ts_bil", "RGBA8 bilinear, mirror u / border v", (TS + "bilinear", TS + "bilinear_fast"),
                ALL_64, (1.15, "tw_bil", 0)),
    *both_tiers("ts_tri", "RGBA8 trilinear, mirror u / border v", (TS + "trilinear", TS + "trilinear_fast"),
                ALL_64, (1.15, "tw_tri", 0)),
    ("ts_srgb", "sRGB trilinear, re-encoded (mirror/border)", "ACCURATE", TS + "srgb", ALL_64,
     (1.6, "ts_tri", 0)),
    *both_tiers("ts_565", "RGB565 trilinear (mirror/border)", (TS + "rgb565", TS + "rgb565_fast"), ALL_64,
                (1.25, "ts_tri", 0)),
    *both_tiers("ts_bc1_hit", "BC1 trilinear, cache hits (mirror/border)", (TS + "bc1", TS + "bc1_fast"),
                BC1_HIT, (1.3, "ts_tri", 0)),
    *both_tiers("ts_bc1_fill", "BC1 trilinear, cache filled (fill cost, no goal)", (TS + "bc1", TS + "bc1_fast"),
                BC1_FILL, None),
    *[(f"an{n}", f"anisotropic {n}× sample", "ACCURATE", TS + "aniso", calls, (n, "tw_tri", 100))
      for n, calls in ANISO],
    *[(f"an{n}_f", f"anisotropic {n}× sample", "FAST", TS + "aniso_fast", calls, (n, "tw_tri_f", 100))
      for n, calls in ANISO],
]
# Batches of the wrap rows: (label, tier, batch wrapper, single-call row).
MATRIX_BATCHES = [
    ("RGBA8 bilinear, wrap, bias/clamps set", "ACCURATE", "matrix:rm_batch_bilinear", "tw_bil"),
    ("RGBA8 bilinear, wrap, bias/clamps set", "FAST", "rm_batch_bilinear_fast", "tw_bil_f"),
    ("RGBA8 trilinear, wrap, bias/clamps set", "ACCURATE", "matrix:rm_batch_trilinear", "tw_tri"),
    ("RGBA8 trilinear, wrap, bias/clamps set", "FAST", "rm_batch_trilinear_fast", "tw_tri_f"),
]
# The wrap rows have the plain rows' types, so they call the plain rows'
# wrappers a second time (`matrix_rows` runs after the plain rows): the
# calls after the first `n` of these wrappers are the matrix's, under the
# key `matrix:<wrapper>`.
MATRIX_SHARED = {"rm_bench_bilinear": 64, "rm_bench_trilinear": 64, "rm_bench_trilinear_fast": 64,
                 "rm_batch_bilinear": 2, "rm_batch_trilinear": 2}
# Geometric LOD rows: (key, label, single-instance calls, batch calls
# (32 then 64 instances)).
GEOMLOD_ROWS = [
    ("discrete", "discrete", slice(0, 64), slice(0, 2)),
    ("stochastic", "stochastic, t = ½", slice(64, 128), slice(2, 4)),
]



# Goals and CI ceilings, in instructions, one line per (kind, row): the
# Cortex-M4, RV32IMAC and RV32IMAC+Zbb figures, `-` where a kind has none.
# Fixed numbers, so a slower build fails. The kinds:
#   goal                  the goal of a call (max per call over its 64 calls);
#                         a FAST path has the goal of the call it stands in for
#   ceiling               CI ceiling of a call: the goal where it is met, else
#                         the achieved maximum + 10 % (reason in "Goals missed")
#   batch_goal            goal of a batch's steady state per hit
#   batch_ceiling         CI ceiling of a batch's steady state per hit: the goal
#                         where it is met, else the achieved value + 10 %
#   rd_ceiling            ray differentials (max per call): the goal where it
#                         is met, else the measured maximum + 5 %, rounded down
#   matrix_ceiling        the sampler matrix (max per call): the goal where it
#                         is met, else the achieved value + 5 % (reasons in
#                         docs/budget-analysis.md and the per-class breakdown)
#   matrix_batch_ceiling  batches of the matrix's wrap rows (steady per hit),
#                         the same rule
#   geomlod_ceiling       geometric LOD per instance (steady state): the first
#                         measurement's maximum + 10 %, rounded up
LIMITS = """
kind                  row                           m4    rv rvzbb
goal                  lod                           20    30    20
goal                  cone_lod                      40    60    45
goal                  bilinear                      90   110   100
goal                  trilinear                    150   200   180
ceiling               lod                           31    52    33
ceiling               cone_lod                      65   105    68
ceiling               bilinear                      97   137   135
ceiling               trilinear                    221   283   283
ceiling               lod_fast                      20    42    26
ceiling               cone_lod_fast                 40    92    54
ceiling               trilinear_fast               209   276   254
batch_goal            lod                           12     -     -
batch_goal            lod_fast                      12    20     -
batch_goal            trilinear                    120     -     -
batch_ceiling         lod_fast                      12    20    20
rd_ceiling            rd_primary                   150   205   190
rd_ceiling            rd_transfer                  190   340   253
rd_ceiling            rd_reflect                   151   261   235
rd_ceiling            rd_refract                   300   502   362
rd_ceiling            rd_footprint                  37    64    63
rd_ceiling            rd_lod                        51    89    73
rd_ceiling            rd_gbuffer                   150   110    95
rd_ceiling            rd_gbuffer_normals            56   119    90
matrix_ceiling        tw_bil                        97   134   132
matrix_ceiling        tw_bil_f                      97   145   129
matrix_ceiling        tw_tri                       216   280   278
matrix_ceiling        tw_tri_f                     200   269   247
matrix_ceiling        tw_tri_n                     220   290   288
matrix_ceiling        ts_bil                       131   168   166
matrix_ceiling        ts_bil_f                     130   172   159
matrix_ceiling        ts_tri                       272   342   340
matrix_ceiling        ts_tri_f                     250   327   308
matrix_ceiling        ts_srgb                      416   516   512
matrix_ceiling        ts_565                       323   406   403
matrix_ceiling        ts_565_f                     297   388   387
matrix_ceiling        ts_bc1_hit                   469   602   585
matrix_ceiling        ts_bc1_hit_f                 448   588   554
matrix_ceiling        ts_bc1_fill                 3333  3535  3445
matrix_ceiling        ts_bc1_fill_f               3287  3517  3410
matrix_ceiling        an2                          692   903   879
matrix_ceiling        an4                         1091  1414  1399
matrix_ceiling        an16                        3460  4404  4404
matrix_ceiling        an2_f                        658   860   795
matrix_ceiling        an4_f                       1019  1328  1228
matrix_ceiling        an16_f                      3284  4292  3956
matrix_batch_ceiling  matrix:rm_batch_bilinear     104   131   126
matrix_batch_ceiling  rm_batch_bilinear_fast        96   124   116
matrix_batch_ceiling  matrix:rm_batch_trilinear    200   237   232
matrix_batch_ceiling  rm_batch_trilinear_fast      191   223   194
geomlod_ceiling       discrete                      97    78    73
geomlod_ceiling       stochastic                   117    92    86
"""


def limits(kind):
    """{row: {isa: instructions}} of one kind of the LIMITS table."""
    table = {}
    for line in LIMITS.strip().splitlines()[1:]:
        k, row, *figures = line.split()
        if k == kind:
            table[row] = {isa: int(n) for (isa, _), n in zip(ISAS, figures) if n != "-"}
    return table


GOALS = limits("goal")
GOALS.update({f: GOALS[a] for f, a in FAST_OF.items()})
CEILINGS = limits("ceiling")
BATCH_GOALS = limits("batch_goal")
BATCH_CEILINGS = limits("batch_ceiling")
RD_CEILINGS = limits("rd_ceiling")
MATRIX_CEILINGS = limits("matrix_ceiling")
MATRIX_BATCH_CEILINGS = limits("matrix_batch_ceiling")
GEOMLOD_CEILINGS = limits("geomlod_ceiling")

SIZE_CEILING = 6144  # minimal .text, bytes
STATIC_TRILINEAR_CEILING = 512  # bytes


def ceiling_cell(table, key, value, bad, what):
    """The ceiling column of row `key` of a LIMITS kind (M4 / RV32 / Zbb, "—"
    for a row without ceilings). Appends a FAIL line to `bad` for each ISA
    whose `value(isa)` is above its ceiling, `what(isa, value)` naming it."""
    ceil = table.get(key)
    if not ceil:
        return "—"
    for k, _ in ISAS:
        if value(k) > ceil[k]:
            bad.append(f"{what(k, value(k))} > ceiling {ceil[k]}")
    return " / ".join(str(ceil[k]) for k, _ in ISAS)


def symbols(work, name):
    syms = {}
    with open(os.path.join(work, name + ".nm")) as f:
        for line in f:
            p = line.split()
            if len(p) == 4:
                syms[p[3]] = (int(p[0], 16) & ~1, int(p[1], 16))
    return syms


PC = re.compile(r"\[[0-9a-f]+/([0-9a-f]+)/")


def count(work, name, first=None, every=None):
    """Instructions per call of every wrapper: {symbol: [count, ...]}; the
    program counters of each wrapper's first call go into `first` (a dict),
    those of every call into `every` ({symbol: [[pc, ...], ...]})."""
    syms = symbols(work, name)
    entry = {a: s for s, (a, _) in syms.items() if s.startswith(("rm_bench_", "rm_batch_"))}
    d0, dsz = syms["rm_budget_driver"]
    counts = {s: [] for s in entry.values()}
    cur, n, pcs = None, 0, []
    with open(os.path.join(work, name + ".trace"), errors="replace") as f:
        for line in f:
            m = PC.search(line)
            if not m:
                continue
            pc = int(m.group(1), 16)
            if cur is None:
                if pc in entry:
                    cur, n, pcs = entry[pc], 1, [pc]
            elif d0 <= pc < d0 + dsz:
                if first is not None and cur not in first:
                    first[cur] = pcs
                if every is not None:
                    every.setdefault(cur, []).append(pcs)
                counts[cur].append(n)
                cur = None
            else:
                n += 1
                pcs.append(pc)
    return counts


DIS = re.compile(r"^\s*([0-9a-f]+):\s+(\S+)")


def mnemonics(work, name):
    """{address: mnemonic} from the disassembly."""
    out = {}
    with open(os.path.join(work, name + ".dis")) as f:
        for line in f:
            m = DIS.match(line)
            if m:
                out[int(m.group(1), 16)] = m.group(2).lower()
    return out


CLASSES = ["load/store", "multiply", "shift/extract", "add/logic/move", "compare/select", "branch"]


def classify(op):
    """Instruction class of a Thumb-2 or RISC-V mnemonic."""
    op = op.split(".")[0]
    if re.match(r"^(ldr|str|ldm|stm|push|pop|lw|lh|lb|sw|sh|sb|ld|sd|c\.lw|c\.sw)", op):
        return "load/store"
    if re.match(r"^(mul|mla|mls|umull|umlal|smull|smlal|smla|smul|mulh)", op):
        return "multiply"
    if re.match(r"^(lsl|lsr|asr|ror|ubfx|sbfx|bfc|bfi|uxt|sxt|clz|rev|sll|srl|sra|zext|sext|ctz|cpop|rol)", op):
        return "shift/extract"
    if re.match(r"^(cmp|cmn|tst|teq|it|slt|seqz|snez|sgt|sltz|sgtz|min|max|csel|ssat|usat)", op):
        return "compare/select"
    if re.match(r"^(b|bl|bx|blx|cbz|cbnz|beq|bne|blt|bge|bltu|bgeu|beqz|bnez|blez|bgez|bltz|bgtz|bgt|ble|bgtu|bleu|j|jal|jalr|jr|ret|call|tail)$", op):
        return "branch"
    return "add/logic/move"


DIS_TEXT = re.compile(r"^\s*([0-9a-f]+):\s+(.*?)\s*(?:@.*)?$")


def disassembly(work, name):
    """{address: instruction text} (mnemonic and operands) from the
    disassembly."""
    out = {}
    with open(os.path.join(work, name + ".dis")) as f:
        for line in f:
            m = DIS_TEXT.match(line)
            if m and not line.rstrip().endswith(">:"):
                out[int(m.group(1), 16)] = " ".join(m.group(2).split())
    return out


def load_classes(root):
    """The cost classes of scripts/budget-classes.txt: [(class,
    instruction regex, inline-stack regex)], in order."""
    rules = []
    with open(os.path.join(root, "scripts", "budget-classes.txt")) as f:
        for line in f:
            if not line.strip() or line.startswith("#"):
                continue
            name, insn, stack = (x.strip() for x in line.rstrip("\n").split(" ;", 2))
            rules.append((name, re.compile(insn) if insn else None,
                          re.compile(stack) if stack else None))
    return rules


def load_analysis(root):
    """The paragraphs of docs/budget-analysis.md: {section: {heading:
    paragraph}}, the `## ` sections and their `### ` headings in order,
    each paragraph's lines joined by spaces."""
    out, section, heading = {}, None, None
    with open(os.path.join(root, "docs", "budget-analysis.md")) as f:
        for line in f:
            line = line.strip()
            if line.startswith("### "):
                heading = line[4:]
                out[section][heading] = ""
            elif line.startswith("## "):
                section, heading = line[3:], None
                out[section] = {}
            elif line and heading is not None:
                text = out[section][heading]
                out[section][heading] = f"{text} {line}" if text else line
    return out


def load_rows(root):
    """The measured wrappers of scripts/budget-rows.txt: {symbol: calls}."""
    rows = {}
    with open(os.path.join(root, "scripts", "budget-rows.txt")) as f:
        for line in f:
            if line.strip() and not line.startswith("#"):
                sym, calls = (x.strip() for x in line.split(";"))
                rows[sym] = int(calls)
    return rows


HASH = re.compile(r"::h[0-9a-f]{16}$")
GENERICS = re.compile(r"<.*>$")


def symbolize(work, name, pcs):
    """{address: inline stack} of `pcs` in NAME.elf: the function names
    llvm-symbolizer gives (innermost first), each by its last path segment
    without generic arguments (line tables name an inlined frame `f<T>`,
    full DWARF `path::f::h…`), joined by " < "."""
    import subprocess
    pcs = sorted(set(pcs))
    tool = os.environ.get("SYMBOLIZER") or "llvm-symbolizer"
    text = subprocess.run([tool, "--obj=" + os.path.join(work, name + ".elf"), "--inlines"],
                          input="\n".join(hex(p) for p in pcs), capture_output=True, text=True,
                          check=True).stdout
    out = {}
    for pc, block in zip(pcs, text.strip().split("\n\n")):
        names = [GENERICS.sub("", HASH.sub("", n)).split("::")[-1] for n in block.split("\n")[0::2]]
        out[pc] = " < ".join(names)
    return out


def by_class(pcs, texts, stacks, rules):
    """Counts of the executed instructions `pcs` per class of `rules`
    (first match; "other" when none)."""
    counts = {name: 0 for name, _, _ in rules}
    counts["other"] = 0
    for pc in pcs:
        insn, stack = texts.get(pc, "?"), stacks.get(pc, "")
        for name, ri, rs in rules:
            if (ri is None or ri.search(insn)) and (rs is None or rs.search(stack)):
                counts[name] += 1
                break
        else:
            counts["other"] += 1
    return counts


def mix(pcs, ops):
    c = {k: 0 for k in CLASSES}
    for pc in pcs:
        c[classify(ops.get(pc, "?"))] += 1
    return c


def stat(v):
    return (min(v), sum(v) / len(v), max(v))


def fmt(s):
    return f"{s[0]} / {s[1]:.1f} / {s[2]}"


def kv(work, name, prefix):
    d = {}
    with open(os.path.join(work, name + ".out")) as f:
        for line in f:
            m = re.match(prefix + r" (\w+): (.*)", line.strip())
            if m:
                d[m.group(1)] = m.group(2)
    return d


def sections(work, t, b):
    d = {}
    with open(os.path.join(work, f"size-{t}-{b}.txt")) as f:
        for line in f:
            p = line.split()
            if len(p) == 3 and p[0].startswith("."):
                d[p[0]] = int(p[1])
    return d


def demo_stack(work, t):
    with open(os.path.join(work, f"demo-{t}.out")) as f:
        for line in f:
            if line.startswith("stack:"):
                return int(line.split()[1])
    return None


def static_stack(work, t):
    d = {}
    with open(os.path.join(work, f"static-{t}.txt")) as f:
        for line in f:
            p = line.split()
            if len(p) == 2:
                d[p[0]] = int(p[1]) if p[1].isdigit() else None
    return d


BLOCK = re.compile(r"<!-- (\w[\w-]*):begin -->.*?<!-- \1:end -->", re.S)


def blocks(text):
    """Blocks other scripts own, `<!-- NAME:begin -->` … `<!-- NAME:end -->`
    (e.g. softcore, features), markers included: {name: block}, in order."""
    return {m.group(1): m.group(0) for m in BLOCK.finditer(text)}


def softcore_block(text):
    """The softcore block (markers included) of `text`, or None."""
    return blocks(text).get("softcore")


def without_softcore(text):
    """`text` with the content of every owned block removed (what the
    staleness check compares)."""
    return BLOCK.sub(lambda m: f"<!-- {m.group(1)}:begin --><!-- {m.group(1)}:end -->", text)


ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
ANALYSIS = load_analysis(ROOT)


def render(work, old_text, readme):
    firsts = {k: {} for k, _ in ISAS}
    every = {k: {} for k, _ in ISAS}
    res = {k: count(work, k, firsts[k], every[k]) for k, _ in ISAS}
    rows = load_rows(ROOT)
    for k, _ in ISAS:
        for sym in sorted(set(rows) | set(res[k])):
            got, want = len(res[k].get(sym, [])), rows.get(sym)
            if got != want:
                sys.exit(f"budgets: {k} {sym}: {got} calls traced, want {want}"
                         + ("" if want else " (not a row of scripts/budget-rows.txt)"))
    for k, _ in ISAS:
        for sym, n in MATRIX_SHARED.items():
            for d in (res[k], every[k]):
                calls = d.get(sym, [])
                d[sym], d["matrix:" + sym] = calls[:n], calls[n:]
    ops = {k: mnemonics(work, k) for k, _ in ISAS}
    bad = []
    L = page_head("raymip firmware budgets", "README.md", [
        "engineers sizing a controller's firmware: every budget measured on the",
        "targets (instructions, cycles, code, stack, FPGA logic), each table against its ceiling.",
        "Written by `scripts/budgets` (`scripts/budgets.py`; checked by `scripts/test-all`, a stale",
        "file fails); do not edit. Toolchain: see `rustc --version` in CI logs; release profile",
        "(opt-level 3, codegen-units 1), Cortex-M4 code scheduled for that core",
        "(`-C target-cpu=cortex-m4`, as in `.cargo/config.toml`); QEMU 10.0 (`mps2-an386` Cortex-M4,",
        "`virt` RV32).\n"])
    w = L.append
    w("## Instructions per call\n")
    w("Counted from QEMU execution traces (`-accel tcg,one-insn-per-tb=on -d exec,nochain`): every")
    w("instruction from the entry of the `#[inline(never)]` wrapper to its return (callees included,")
    w("the caller's call instruction excluded), 64 calls with the pseudo-random inputs of")
    w("`demo/firmware/src/lib.rs` (`inputs`), called from `demo/firmware/src/bin/budget.rs`.")
    w("min / mean / max; the goal and the CI ceiling apply to the max. ACCURATE paths (bit-identical")
    w("on every target) beside the FAST paths `table_lod::<Fast>` / `cone_lod::<Fast>` (1024-entry log2")
    w("table without interpolation: log2 error ≤ 2⁻¹⁰, lod error ≤ 2⁻⁸ level as for the accurate")
    w("paths) and the FAST tier's trilinear sample (`Cfg<Wrap, Wrap, Linear, Fast>`: D3D11's 8-bit")
    w("positions, exact corner weights, two channels per multiply-accumulate, bound 1.5 LSB against")
    w("0.5625 for the accurate path); a goal counts as met when either path of the call meets it.\n")
    w("| call | Cortex-M4 | RV32IMAC | RV32IMAC+Zbb | goal M4 / RV32 / Zbb | ceiling M4 / RV32 / Zbb |")
    w("|---|---|---|---|---|---|")
    for c, label in ALL_CALLS:
        row = [label] + [fmt(stat(res[k]["rm_bench_" + c])) for k, _ in ISAS]
        row.append(" / ".join(f"≤ {GOALS[c][k]}" for k, _ in ISAS))
        row.append(" / ".join(str(CEILINGS[c][k]) for k, _ in ISAS))
        w("| " + " | ".join(row) + " |")
        for k, _ in ISAS:
            mx = stat(res[k]["rm_bench_" + c])[2]
            if mx > CEILINGS[c][k]:
                bad.append(f"{k} {c}: max {mx} instructions > ceiling {CEILINGS[c][k]}")
    ok = {(c, k) for c, _ in ALL_CALLS for k, _ in ISAS
          if stat(res[k]["rm_bench_" + c])[2] <= GOALS[c][k]}
    by = {}
    for c, _ in CALLS:
        for k, _ in ISAS:
            f = [f for f, a in FAST_OF.items() if a == c and (f, k) in ok]
            if (c, k) in ok:
                by[(c, k)] = "accurate"
            elif f:
                by[(c, k)] = "FAST"
    met = list(by)
    n_acc = sum(v == "accurate" for v in by.values())
    how = "; ".join(f"{dict(CALLS)[c]} {dict(ISAS)[k]} by the {v} path" for (c, k), v in by.items())
    w(f"\nGoals met: {len(met)} of {len(CALLS) * len(ISAS)} (call × ISA; {n_acc} by an accurate path"
      + (f": {how}" if how else "") + ").")

    w("\n## Fixed point beside f32\n")
    w("The same four stages in f32 (`raymip::baseline_f32`, feature `f32`, `libm`), on the same 64 inputs")
    w("converted to f32 outside the counted call, counted by the same trace script: on the")
    w("Cortex-M4F with its single-precision FPU (`thumbv7em-none-eabihf`), on RV32IMAC with soft")
    w("float (`__addsf3`, `__mulsf3`, … from compiler-builtins). Mean instructions per call;")
    w("ratio = f32 / fixed (above 1: fixed point executes fewer instructions). The FAST rows")
    w("compare with the same f32 call as the accurate rows.\n")
    w("| call | M4 fixed | M4 f32 | ratio | RV32 fixed | RV32 f32 | ratio | Zbb fixed | Zbb f32 | ratio |")
    w("|---|---|---|---|---|---|---|---|---|---|")
    for c, label in ALL_CALLS:
        row = [label]
        for k, _ in ISAS:
            a = stat(res[k]["rm_bench_" + c])[1]
            b = stat(res[k]["rm_bench_f32_" + FAST_OF.get(c, c)])[1]
            row += [f"{a:.1f}", f"{b:.1f}", f"{b / a:.2f}"]
        w("| " + " | ".join(row) + " |")

    w("\n## Batch entry points\n")
    w("`table_lod_batch`, `cone_lod_batch`, their FAST forms `table_lod_norm_batch`,")
    w("`cone_lod_batch::<Fast>`, `Sampler::sample_batch` (slice of hits in, slice of")
    w("results out, caller memory), each called once with the first 32 and once with all 64 inputs")
    w("above. Steady state per hit = (count for 64 − count for 32) / 32; amortised = count for")
    w("64 / 64 (call and loop set-up included).\n")
    w("The FAST table batch reads the normalised `Pl` that every ray-stack entry keeps")
    w("(`PathState::pl_norm`, made by `PathState::advance` with the segment's one leading-zero")
    w("count; converted outside the counted call here), so its loop has no leading-zero count,")
    w("and writes one `LodWord` per hit (untextured in the niche outside the `Lod` range).\n")
    w("| batch call | M4 steady | M4 amortised | RV32 steady | RV32 amortised | Zbb steady | Zbb amortised "
      "| goal steady M4 / RV32 | ceiling steady M4 / RV32 / Zbb |")
    w("|---|---|---|---|---|---|---|---|---|")
    for c, label in ALL_CALLS:
        if c in FAST_OF and c not in FAST_BATCHED:
            continue
        row = [label]
        for k, _ in ISAS:
            c32, c64 = res[k]["rm_batch_" + c]
            row += [f"{(c64 - c32) / 32:.1f}", f"{c64 / 64:.1f}"]
            ceil = BATCH_CEILINGS.get(c, {}).get(k)
            if ceil is not None and (c64 - c32) / 32 > ceil:
                bad.append(f"{k} batch {c}: {(c64 - c32) / 32:.1f} per hit > ceiling {ceil}")
        g = BATCH_GOALS.get(c, {})
        row.append(" / ".join(f"≤ {g[k]}" if k in g else "—" for k in ("m4", "rv")) if g else "—")
        ceil = BATCH_CEILINGS.get(c)
        row.append(" / ".join(str(ceil[k]) for k, _ in ISAS) if ceil else "—")
        w("| " + " | ".join(row) + " |")
    for heading, text in ANALYSIS["Batches"].items():
        c = {label + " batch": c for c, label in ALL_CALLS}[heading]
        steady = {k: (res[k]["rm_batch_" + c][1] - res[k]["rm_batch_" + c][0]) / 32 for k, _ in ISAS}
        g = BATCH_GOALS[c]
        met = all(steady[k] <= goal for k, goal in g.items())
        w(f"\n**{heading}, goal {'met' if met else 'missed'}.** Cortex-M4 {steady['m4']:.1f} per hit "
          f"against the goal of {g['m4']}, RV32IMAC {steady['rv']:.1f} and Zbb {steady['rvzbb']:.1f} "
          f"against {g['rv']}. {text}")

    mi, mz = kv(work, "rv", "minstret"), kv(work, "rvzbb", "minstret")
    w("\nCross-check on RV32 with `minstret` under `-icount shift=0`, read before and after each call:")
    w("call-inclusive (argument moves, the call, the return), minus the baseline of an empty call,")
    w("which is 1 (the counter read itself: the optimiser removes a call to a function without")
    w("effects). The trace counts above exclude the caller's side, hence a few more here.\n")
    w("| call | RV32IMAC | RV32IMAC+Zbb |")
    w("|---|---|---|")
    for c, _ in ALL_CALLS:
        w(f"| {c} | {mi.get(c, '?')} | {mz.get(c, '?')} |")

    matrix_section(res, w, bad, every, work)

    w("\n## Ray differentials (feature `raydiff`)\n")
    w("`raymip::path::raydiff` (Igehy's ray differentials in 32-bit block floating point), each stage")
    w("its own wrapper, 64 calls on `inputs::raydiff` (a primary-like state, directions near")
    w("`(±½, ±½, −0.7)`, normals near `+z` with small differentials), the footprint and lod on one")
    w("4 × 3 triangle of the demo texture size; counted like the calls above. min / mean / max; the")
    w("Cortex-M4 goal (issue 33) and the CI ceiling apply to the max.\n")
    mean = lambda k, c: stat(res[k]["rm_bench_" + c])[1]
    rd_max = lambda k, c: stat(res[k]["rm_bench_" + c])[2]

    def call_table(rows):
        """min / mean / max of each (key, label) wrapper `rm_bench_<key>`."""
        w("| call | Cortex-M4 | RV32IMAC | RV32IMAC+Zbb |")
        w("|---|---|---|---|")
        for key, label in rows:
            w(f"| {label} | " + " | ".join(fmt(stat(res[k]["rm_bench_" + key])) for k, _ in ISAS) + " |")

    def ratio_table(head, per):
        """Each {label: count(isa)} beside its ratio to the accurate cone lod."""
        w(f"| {head} | " + " | ".join(f"{isa} | ratio to cone" for _, isa in ISAS) + " |")
        w("|---|" + "---|---|" * len(ISAS))
        for label, f in per.items():
            w(f"| {label} | " + " | ".join(f"{f(k):.1f} | {f(k) / mean(k, 'cone_lod'):.2f}" for k, _ in ISAS) + " |")

    w("| call | Cortex-M4 | RV32IMAC | RV32IMAC+Zbb | goal M4 | ceiling M4 / RV32 / Zbb |")
    w("|---|---|---|---|---|---|")
    for key, label in RD_BUDGET_ROWS:
        goal = RD_GOALS.get(key)
        w(f"| {label} | " + " | ".join(fmt(stat(res[k]["rm_bench_" + key])) for k, _ in ISAS)
          + f" | {'≤ ' + str(goal) if goal else '—'} | "
          + " / ".join(str(RD_CEILINGS[key][k]) for k, _ in ISAS) + " |")
        for k, _ in ISAS:
            if rd_max(k, key) > RD_CEILINGS[key][k]:
                bad.append(f"{k} {key}: max {rd_max(k, key)} instructions > ceiling {RD_CEILINGS[key][k]}")
    met = [label for key, label in RD_BUDGET_ROWS if key in RD_GOALS and rd_max("m4", key) <= RD_GOALS[key]]
    missed = [f"{label} ({rd_max('m4', key)} > {RD_GOALS[key]})" for key, label in RD_BUDGET_ROWS
              if key in RD_GOALS and rd_max("m4", key) > RD_GOALS[key]]
    for label, keys, goal in RD_SUM_GOALS:
        total = sum(rd_max("m4", key) for key in keys)
        (met if total <= goal else missed).append(
            label if total <= goal else f"{label} ({total} > {goal})")
        # A sum whose goal is met keeps it as a ceiling, as a row does.
        if label in RD_SUMS_AT_GOAL and total > goal:
            bad.append(f"m4 {label}: {total} instructions > goal {goal} (met before: a ceiling)")
    w(f"\nGoals met on the Cortex-M4 (max): {', '.join(met) if met else 'none'}. Missed: "
      f"{'; '.join(missed) if missed else 'none'}. Where a goal is missed the ceiling is this")
    w("measurement + 5 %. The x and y differentials of a quantity share one exponent: each")
    w("operation aligns its terms to one exponent for both axes (a shift per component and term) and")
    w("normalises its result pair once (one leading-zero count, a shift per component); a transfer")
    w("also normalises `D·n`, `t` and both axes' `q·n` and takes one reciprocal, and the two axes'")
    w("temporaries exceed the Cortex-M4's registers (spills). The ray-stack state is read and written")
    w("in place (`&mut RayDiff`).\n")
    w("Per textured hit beside the other methods (means): ray-traced differentials = transfer +")
    w("footprint + lod; G-buffer differentials (first hit) = G-buffer set-up + footprint + lod; the")
    w("ratio is to the cone lod with the normal term (accurate; the talk measured about 3× and 2×")
    w("on a GPU). A bounce adds a reflection or refraction to the ray-traced path; at a G-buffer")
    w("first hit also the normal differentials of the chosen sides (the set-up makes only `∂P`,")
    w("all a textured hit's footprint needs).\n")
    ratio_table("method per hit", {
        "table lod FAST (batch, steady)": lambda k: (res[k]["rm_batch_lod_fast"][1] - res[k]["rm_batch_lod_fast"][0]) / 32,
        "table lod": lambda k: mean(k, "lod"),
        "cone lod (with n·d)": lambda k: mean(k, "cone_lod"),
        "ray differentials, ray-traced": lambda k: mean(k, "rd_transfer") + mean(k, "rd_footprint") + mean(k, "rd_lod"),
        "ray differentials, G-buffer": lambda k: mean(k, "rd_gbuffer") + mean(k, "rd_footprint") + mean(k, "rd_lod"),
    })
    ps = {k: kv(work, k, "path state") for k, _ in ISAS}
    w(f"\nRay-stack entry (`PathState`) with the feature (and `cone`): {ps['m4'].get('raydiff', '?')} on")
    w(f"the Cortex-M4, {ps['rv'].get('raydiff', '?')} on RV32IMAC (printed by the budget binary); without it")
    w("the sizes of the \"Feature sets\" section (`raystack::PATH_STATE_BYTES`, checked at")
    w("compile time on every target).")

    w("\n## Environment map (feature `envmap`)\n")
    w("`raymip::lod::envmap` (Ray Tracing Gems ch. 21): the lod of a ray that leaves the scene on a")
    w("2048 × 1024 latitude-longitude map and the map coordinates of its direction, each its own")
    w("wrapper, 64 calls on `inputs::envmap` (cone spreads in [2⁻¹², 2⁻⁸) rad, directions of every")
    w("latitude, direction differentials up to 2⁻⁸); counted like the calls above. min / mean / max.")
    w("`(u, v)` is two `atan2` in 32-bit words, each three CORDIC steps, one division (`udiv` /")
    w("`divu`), a Newton step and a short series of multiply-highs (within `ENVMAP_UV_MAX_ERROR` =")
    w("2⁻²⁸); the lods are one or two table logarithms.\n")
    call_table(ENV_ROWS)
    w("\nPer ray that leaves the scene (means): the lod and the lookup coordinates, beside the cone")
    w("lod of a surface hit (with n·d) and its ratio to it.\n")
    ratio_table("method per miss", {
        "cone lod (pole term) + (u, v)": lambda k: mean(k, "env_cone_lat") + mean(k, "env_uv"),
        "ray-differential lod (pole term) + (u, v)": lambda k: mean(k, "env_raydiff") + mean(k, "env_uv"),
    })

    gl = geomlod_stats(res)
    recs = {k: kv(work, k, "geomlod") for k, _ in ISAS}
    w("\n## Geometric LOD per instance (`geomlod::Selector::fill`)\n")
    w("The instance records (id, LOD, 8-bit mask) of instances at pseudo-random camera-space depths")
    w("over [−2, 70) (`inputs::instances`), 8 LODs from z_near = 2 to z_far = 66, bias −¼")
    w("(`inputs::selector`), written into the caller's array. One instance: 64 calls of one")
    w("instance each, min / mean / max. Per instance: one call with the first 32 and one with all")
    w("64 instances, (count for 64 − count for 32) / 32. A stochastic instance in a transition")
    w("writes two records.\n")
    w("| mode | M4 one instance | M4 per instance | RV32 one instance | RV32 per instance "
      "| Zbb one instance | Zbb per instance | records for 64 instances | ceiling per instance M4 / RV32 / Zbb |")
    w("|---|---|---|---|---|---|---|---|---|")
    for key, label, _, _ in GEOMLOD_ROWS:
        row = [label]
        for k, _ in ISAS:
            one, per = gl[k][key]
            row += [fmt(one), f"{per:.1f}"]
        row.append(recs["m4"].get(key, "?"))
        row.append(ceiling_cell(GEOMLOD_CEILINGS, key, lambda k: gl[k][key][1], bad,
                                lambda k, v: f"{k} geomlod {key}: {v:.1f} per instance"))
        w("| " + " | ".join(row) + " |")
        if len({recs[k].get(key) for k, _ in ISAS}) != 1:
            bad.append(f"geomlod {key}: record counts differ between targets: {recs}")

    w("\n## Executed instruction mix\n")
    w("Where the instructions of one call go: the first of the 64 calls of each fixed-point wrapper,")
    w("every executed instruction classified by its mnemonic (from `llvm-objdump`; the wrapper's")
    w("own frame included). Classes: load/store (incl. push/pop), multiply, shift/extract (shifts,")
    w("bit-field extracts, `clz`), add/logic/move, compare/select (incl. `it`, `slt*`), branch")
    w("(incl. call and return).\n")
    w("| call | ISA | total | " + " | ".join(CLASSES) + " |")
    w("|---|---|---|" + "---|" * len(CLASSES))
    for c, label in ALL_CALLS:
        for k, isa in ISAS:
            m = mix(firsts[k]["rm_bench_" + c], ops[k])
            w(f"| {label} | {isa} | {sum(m.values())} | " + " | ".join(str(m[x]) for x in CLASSES) + " |")

    missed = [(c, k) for c, _ in ALL_CALLS for k, _ in ISAS if (c, k) not in ok]
    if missed:
        w("\n## Goals missed, and why\n")
        w("Per path: an accurate path listed here may have its goal met by its FAST path (above).")
        w("The analysis of each call is docs/budget-analysis.md, copied here.\n")
        w("Missed (call, ISA, max instructions / goal): " + "; ".join(
            f"{dict(ALL_CALLS)[c]} {dict(ISAS)[k]} {stat(res[k]['rm_bench_' + c])[2]} / {GOALS[c][k]}"
            for c, k in missed) + ".\n")
        for label, text in ANALYSIS["Per-hit calls"].items():
            if any(dict(ALL_CALLS)[c] == label for c, _ in missed):
                w(f"**{label}.** {text}\n")

    w("")
    w(softcore_block(old_text) or BEGIN + "\n" + END)

    w("\n## Code size\n")
    w("Bytes linked into a firmware image by each feature set: `.text` / `.rodata` of a probe binary")
    w("minus the probe skeleton (`demo/size-probe`: same runtime and texture data, no raymip call).")
    w("Minimal = Pb table lookup + `table_lod_clamped` + one bilinear sample from a pyramid in memory.")
    w("Full = the float-free API: table build/update (fixed-point set-up), table and cone lod, ray")
    w("stack, MIP generation, all four filter modes from memory and through the block cache.\n")
    w("| set | thumbv7em .text | thumbv7em .rodata | riscv32imac .text | riscv32imac .rodata | goal |")
    w("|---|---|---|---|---|---|")
    for setname, b in [("minimal", "size-min"), ("full", "size-full")]:
        row = [setname]
        for t in (ARM, RV):
            base, s = sections(work, t, "size-base"), sections(work, t, b)
            tx = s.get(".text", 0) - base.get(".text", 0)
            ro = s.get(".rodata", 0) - base.get(".rodata", 0)
            if setname == "minimal" and tx > SIZE_CEILING:
                bad.append(f"{t} minimal .text {tx} > ceiling {SIZE_CEILING}")
            row += [str(tx), str(ro)]
        row.append("minimal .text ≤ 4096" if setname == "minimal" else "—")
        w("| " + " | ".join(row) + " |")

    w("\n## Stack\n")
    w("Stack painting (`demo/firmware/src/lib.rs`): the free stack below the caller is filled with a")
    w("pattern, the code runs, the lowest changed word gives the depth (exact to 4 bytes; no interrupts).\n")
    w("| measured | Cortex-M4 | RV32IMAC | RV32IMAC+Zbb |")
    w("|---|---|---|---|")
    st = {k: kv(work, k, "stack") for k, _ in ISAS}
    for c, _ in ALL_CALLS:
        w(f"| one {c} call | {st['m4'].get(c)} | {st['rv'].get(c)} | {st['rvzbb'].get(c)} |")
    ds = {"m4": demo_stack(work, ARM), "rv": demo_stack(work, RV)}
    w(f"| whole demo render (64×48, ray stack of 10) | {ds['m4']} bytes | {ds['rv']} bytes | — |")
    w("\n### Worst-case stack (static, -Z emit-stack-sizes, LTO off)\n")
    w("`scripts/stack-sizes` builds the same binaries with nightly rustc and `-Z emit-stack-sizes`")
    w("(LLVM records each function's frame in `.stack_sizes`), LTO off, one codegen unit, and")
    w("`scripts/stack_graph.py` adds up frames along the call graph taken from the disassembly")
    w("(own frame + deepest callee; tail calls counted like calls, an upper bound). Recursion,")
    w("unresolved indirect calls and functions without a frame size fail it; compiler builtins")
    w("(precompiled without `.stack_sizes`: 64-bit division on the render path) are bounded from")
    w("their bodies (sum of stack-pointer decrements). Painting measures the stable-toolchain")
    w("release build as shipped (its profile sets no `lto`: LTO off as well, but another compiler")
    w("version, so frames can differ); it must not exceed the static worst case (checked).\n")
    w("| entry | Cortex-M4 static | Cortex-M4 painted | RV32IMAC static | RV32IMAC painted |")
    w("|---|---|---|---|---|")
    stat_ = {"m4": static_stack(work, ARM), "rv": static_stack(work, RV)}

    def painted(s):
        return int(s.split()[0]) if s and s.split()[0].isdigit() else None
    pt = {m: {c: painted(st[m].get(c)) for c, _ in CALLS} for m in ("m4", "rv")}
    for m in ("m4", "rv"):
        pt[m]["render"] = ds[m]
    for k, label in [("lod", "table lod"), ("cone_lod", "cone lod"), ("bilinear", "bilinear sample"),
                     ("trilinear", "trilinear sample"), ("render", "demo render")]:
        row = [label]
        for m in ("m4", "rv"):
            s, p = stat_[m].get(k), pt[m].get(k)
            row += [f"{s} bytes" if s is not None else "unbounded", f"{p} bytes" if p is not None else "?"]
            if s is None or p is None or p > s:
                bad.append(f"{m} {k}: painted {p} bytes > static worst case {s} bytes")
        w("| " + " | ".join(row) + " |")
    for m in ("m4", "rv"):
        s = stat_[m].get("trilinear")
        if s is None or s > STATIC_TRILINEAR_CEILING:
            bad.append(f"static trilinear stack on {m} {s} > ceiling {STATIC_TRILINEAR_CEILING}")

    w("\n## `size -A` of the demo firmware\n")
    w("Debug-info sections (not loaded) left out; `.stack` on RISC-V is the rest of the RAM region.\n")
    for t in (ARM, RV):
        w("```text")
        with open(os.path.join(work, f"size-{t}-demo.txt")) as f:
            for line in f:
                line = line.rstrip()
                if not line or line.startswith((".debug", ".comment", ".ARM.attributes",
                                                ".riscv.attributes", "Total")):
                    continue
                if ":" in line and "/" in line:
                    line = f"demo ({t}) :"
                w(line)
        w("```")
    # Other scripts' blocks (scripts/features, …) follow, unchanged.
    for name, block in blocks(old_text).items():
        if name != "softcore":
            w("\n" + block)
    return "\n".join(L) + "\n", bad, replace_block(readme, readme_block(res, readme))


def matrix_goal(goal, st, k):
    """The max-instruction goal of a matrix row on ISA `k` (None: no goal)."""
    if goal is None:
        return None
    if isinstance(goal, dict):
        return goal[k]
    factor, rel, const = goal
    return int(factor * st[k][rel][2] + const)


def matrix_section(res, w, bad, every, work):
    """The sampler matrix of issue 20 (section text through `w`, ceiling
    failures appended to `bad`; `every`: the program counters of every call,
    for the breakdown of the rows whose goal is missed)."""
    st = {k: {key: stat(res[k][sym][sl]) for key, _, _, sym, sl, _ in MATRIX_ROWS} for k, _ in ISAS}
    w("\n## Sampler matrix: every configuration, ACCURATE and FAST\n")
    w("One `texture::Sampler` per key (address mode per axis, colour space, tier and fetch statistics")
    w("as types), on the demo texture (32×32, 6 levels) and the 64 bilinear / trilinear inputs above.")
    w("RGBA8 rows read a `Pow2Pyramid` (the pyramid with its validated level views: texel addresses")
    w("computed by the sampler, no check per sample); RGB565 a `Pow2Rgb565` (an RGB565 `Image` with")
    w("its 16-bit level views, read the same way, each texel expanded once); BC1 an `Image` through")
    w("an 8×2-block `TexelCache`. Every key but one counts no fetch statistics (`NoStats`: a")
    w("firmware that reads none); the row \"with fetch statistics\" is the wrap trilinear key with the")
    w("default `FetchStats`, for the counters' cost. Wrap rows: the state `inputs::wrap_state` (wrap on")
    w("both axes, lod bias +¼, lod clamp [½, 4], set at run time); mirror/border rows:")
    w("`inputs::sampler_state` (mirror on u, clamp-to-border on v, the same bias and clamp);")
    w("anisotropic rows: wrap, no bias, 64 footprints at the probe cap. The FAST tier is")
    w("`Cfg<_, _, Linear, Fast, _>` (8-bit positions, exact corner weights, two channels per 64-bit")
    w("multiply-accumulate, ≤ 1.5 LSB); sRGB has no FAST row because its kernel is the ACCURATE one at")
    w("both tiers (`texture::kernel`). min / mean / max instructions per call; a relative goal is the")
    w("issue's factor times the achieved max of the row named (same tier): mirror/border ≤ 1.15 ×")
    w("wrap, RGB565 ≤ 1.25 ×, sRGB ≤ 1.6 ×, BC1 hits ≤ 1.3 × RGBA8 trilinear of the same key,")
    w("anisotropic N× ≤ N × wrap trilinear + 100.\n")
    w("| call | tier | Cortex-M4 | RV32IMAC | RV32IMAC+Zbb | goal M4 / RV32 / Zbb | met | ceiling M4 / RV32 / Zbb |")
    w("|---|---|---|---|---|---|---|---|")
    met = total = 0
    for key, label, tier, _, _, goal in MATRIX_ROWS:
        row = [label, tier] + [fmt(st[k][key]) for k, _ in ISAS]
        g = {k: matrix_goal(goal, st, k) for k, _ in ISAS}
        if goal is None:
            row += ["—", "—"]
        else:
            ok = [st[k][key][2] <= g[k] for k, _ in ISAS]
            met += sum(ok)
            total += len(ok)
            row.append(" / ".join(f"≤ {g[k]}" for k, _ in ISAS))
            row.append(" / ".join("yes" if o else "no" for o in ok))
        row.append(ceiling_cell(MATRIX_CEILINGS, key, lambda k: st[k][key][2], bad,
                                lambda k, v: f"{k} matrix {key}: max {v} instructions"))
        w("| " + " | ".join(row) + " |")
    w(f"\nGoals met: {met} of {total} (row × ISA).\n")
    w("Batches of the wrap rows (`Sampler::sample_batch`, called with 32 and then 64 hits): steady")
    w("per hit = (count for 64 − count for 32) / 32, against the goal single call − 10 % (of the")
    w("single call's mean above).\n")
    w("| batch | tier | " + " | ".join(f"{isa} steady / goal" for _, isa in ISAS)
      + " | met | ceiling M4 / RV32 / Zbb |")
    w("|---|---|" + "---|" * len(ISAS) + "---|---|")
    for label, tier, sym, single in MATRIX_BATCHES:
        row = [label, tier]
        ok = []
        for k, _ in ISAS:
            c32, c64 = res[k][sym]
            steady = (c64 - c32) / 32
            goal = 0.9 * st[k][single][1]
            ok.append(steady <= goal)
            row.append(f"{steady:.1f} / ≤ {goal:.1f}")
            ceil = MATRIX_BATCH_CEILINGS.get(sym, {}).get(k)
            if ceil is not None and steady > ceil:
                bad.append(f"{k} {sym}: {steady:.1f} per hit > ceiling {ceil}")
        row.append(" / ".join("yes" if o else "no" for o in ok))
        ceil = MATRIX_BATCH_CEILINGS.get(sym)
        row.append(" / ".join(str(ceil[k]) for k, _ in ISAS) if ceil else "—")
        w("| " + " | ".join(row) + " |")
    w("\nWhere the instructions go (docs/budget-analysis.md, copied here):")
    for key, text in ANALYSIS["Sampler matrix"].items():
        w(f"\n**{key}.** {text}")
    breakdown_section(st, every, work, w)


def breakdown_section(st, every, work, w):
    """Per-class counts of the executed path of every matrix row whose goal
    is missed on some ISA: the call with the most instructions of each ISA,
    classified by scripts/budget-classes.txt."""
    rules = load_classes(ROOT)
    missed = [(key, label, tier, sym, sl) for key, label, tier, sym, sl, goal in MATRIX_ROWS
              if goal is not None and any(st[k][key][2] > matrix_goal(goal, st, k) for k, _ in ISAS)]
    if not missed:
        return
    names = [name for name, _, _ in rules] + ["other"]
    rows = {}
    for k, _ in ISAS:
        texts = disassembly(work, k)
        picks = {}
        for key, _, _, sym, sl in missed:
            calls = every[k][sym][sl]
            picks[key] = max(calls, key=len)
        stacks = symbolize(work, k, [pc for pcs in picks.values() for pc in pcs])
        for key, pcs in picks.items():
            rows.setdefault(key, {})[k] = by_class(pcs, texts, stacks, rules)
    used = [n for n in names if any(rows[key][k][n] for key in rows for k, _ in ISAS)]
    w("\n### Executed path by class (rows whose goal is missed)\n")
    w("The call with the most instructions of each row, classified instruction by instruction: its")
    w("disassembly and the functions `llvm-symbolizer` gives for its address (inlined frames from the")
    w("debug information) against the rules of `scripts/budget-classes.txt` (first match). Cells:")
    w("Cortex-M4 / RV32IMAC / RV32IMAC+Zbb. The staleness check requires the totals exactly and")
    w(f"lets the class cells of a target move by at most {CLASS_SLACK_PERCENT} % of its total")
    w("(summed over the row): the debug information may attribute the same instruction to a")
    w("different inlined frame from one build to another (seen between machines, identical totals).\n")
    w("| call | tier | total | " + " | ".join(used) + " |")
    w("|---|---|---|" + "---|" * len(used))
    for key, label, tier, _, _ in missed:
        cells = [" / ".join(str(st[k][key][2]) for k, _ in ISAS)]
        cells += [" / ".join(str(rows[key][k][n]) for k, _ in ISAS) for n in used]
        w(f"| {label} | {tier} | " + " | ".join(cells) + " |")


# How far the class cells of one row and target may move between the
# checked-in and the measured BUDGETS.md before the check calls it stale:
# percent of that target's total, summed over the row's class cells.
CLASS_SLACK_PERCENT = 1
CLASS_HEADING = "### Executed path by class"


def class_row(line):
    """((call, tier), cells) of one row of the "Executed path by class"
    table, each cell a list of ints (one per target); None for any other
    line."""
    m = TABLE_ROW.match(line.strip())
    if not m:
        return None
    cells = [c.strip() for c in m.group(1).split("|")]
    try:
        return (cells[0], cells[1]), [[int(x) for x in c.split(" / ")] for c in cells[2:]]
    except (ValueError, IndexError):
        return None


def class_lines(text):
    """The lines of the "Executed path by class" section of a BUDGETS.md
    text (empty when it has none)."""
    i = text.find(CLASS_HEADING)
    return [] if i < 0 else text[i:].split("\n## ")[0].splitlines()


def within_class_slack(old_cells, new_cells):
    """True when two rows of the class table have the same totals (first
    cell) and, per target, class cells whose absolute differences sum to at
    most CLASS_SLACK_PERCENT of that target's total."""
    if len(old_cells) != len(new_cells) or old_cells[0] != new_cells[0]:
        return False
    for t, total in enumerate(new_cells[0]):
        moved = sum(abs(o[t] - n[t]) for o, n in zip(old_cells[1:], new_cells[1:]))
        if moved * 100 > total * CLASS_SLACK_PERCENT:
            return False
    return True


def keep_class_cells(old, new):
    """`new` with each class-table row replaced by the checked-in row of
    `old` when the two are within_class_slack (what the check compares)."""
    rows = {r[0]: (line, r[1]) for line in class_lines(old) if (r := class_row(line))}
    kept = {}
    for line in class_lines(new):
        r = class_row(line)
        if r and r[0] in rows and within_class_slack(rows[r[0]][1], r[1]):
            kept[line] = rows[r[0]][0]
    i = new.find(CLASS_HEADING)
    if i < 0:
        return new
    return new[:i] + "\n".join(kept.get(line, line) for line in new[i:].split("\n"))


def sampler_stats(res):
    """{isa: {row key: (min, mean, max)}} of the sampler-state rows."""
    return {k: {key: stat(res[k][sym][sl]) for key, _, sym, sl, _ in SAMPLER_ROWS} for k, _ in ISAS}


def geomlod_stats(res):
    """{isa: {mode: ((min, mean, max) of one instance, steady per instance)}}."""
    out = {}
    for k, _ in ISAS:
        out[k] = {}
        for key, _, one, batch in GEOMLOD_ROWS:
            c32, c64 = res[k]["rm_batch_geomlod"][batch]
            out[k][key] = (stat(res[k]["rm_bench_geomlod"][one]), (c64 - c32) / 32)
    return out


TABLE_ROW = re.compile(r"^\|(.*)\|\s*$")


def accuracy_cells(readme):
    """{(format, filter): cell} of the sampler-accuracy block of the README
    (written by the sampler_accuracy example): `measured / bound`."""
    block = blocks(readme).get("sampler-accuracy", "")
    header, out = None, {}
    for line in block.splitlines():
        m = TABLE_ROW.match(line.strip())
        if not m:
            continue
        cells = [c.strip() for c in m.group(1).split("|")]
        if all(set(c) <= set("-:") for c in cells):
            continue
        if header is None:
            header = cells
            continue
        for h, c in zip(header[1:], cells[1:]):
            out[(cells[0], h)] = c
    return out


def readme_block(res, readme):
    """The README block (markers included): the sampler-state rows' mean
    instructions per target and their measured error."""
    ts = sampler_stats(res)
    acc = accuracy_cells(readme)
    L = [README_BEGIN]
    L.append("Instructions per `TextureSampler` call (mean, max in parentheses; `bash scripts/budgets`, "
             "QEMU traces, BUDGETS.md \"Sampler matrix\" for the inputs) and the largest error per "
             "channel of that format and filter measured against the f64 reference over random states "
             "(8-bit LSB, measured / bound; the table above):\n")
    L.append("| call | Cortex-M4 | RV32IMAC | RV32IMAC+Zbb | max error vs f64 (LSB) |")
    L.append("|---|---|---|---|---|")
    for key, label, _, _, cell in SAMPLER_ROWS:
        row = [label] + [f"{ts[k][key][1]:.1f} ({ts[k][key][2]})" for k, _ in ISAS]
        row.append(acc.get(cell, "?") if cell else "—")
        L.append("| " + " | ".join(row) + " |")
    L.append(README_END)
    return "\n".join(L)


def replace_block(text, new):
    """`text` with its sampler-budgets block replaced by `new` (the block
    must exist)."""
    i, j = text.find(README_BEGIN), text.find(README_END)
    if i < 0 or j < i:
        sys.exit(f"budgets: docs/texture-sampling.md has no {README_BEGIN} … {README_END} block")
    return text[:i] + new + text[j + len(README_END):]


def self_test():
    t = f"a\n{BEGIN}\nx 1\n{END}\nb\n"
    assert softcore_block(t) == f"{BEGIN}\nx 1\n{END}"
    assert without_softcore(t) == without_softcore(f"a\n{BEGIN}\ny 2\n{END}\nb\n")
    assert without_softcore(t) != without_softcore(f"a\n{BEGIN}\nx 1\n{END}\nc\n")
    assert softcore_block("no markers") is None
    f = "<!-- features:begin -->\nF\n<!-- features:end -->"
    assert blocks(t + f) == {"softcore": softcore_block(t), "features": f}
    assert without_softcore(t + f) == without_softcore(t + f.replace("F", "G"))
    head = f"{CLASS_HEADING} x\n\n| call | tier | total | a | b |\n|---|---|---|---|---|\n"
    row = "| s | ACCURATE | 1000 / 2000 | 500 / 1000 | 500 / 1000 |\n\n## next\n"
    near = row.replace("500 / 1000 | 500 / 1000", "505 / 1010 | 495 / 990")
    far = row.replace("500 / 1000 | 500 / 1000", "506 / 1000 | 494 / 1000")
    other = row.replace("1000 / 2000", "1000 / 2001")
    assert keep_class_cells(head + row, head + near) == head + row
    assert keep_class_cells(head + row, head + far) == head + far
    assert keep_class_cells(head + row, head + other) == head + other


def main():
    self_test()
    work, root = sys.argv[1], sys.argv[2]
    check = len(sys.argv) > 3 and sys.argv[3] == "--check"
    path = os.path.join(root, "BUDGETS.md")
    old = open(path).read() if os.path.exists(path) else ""
    readme_path = os.path.join(root, "docs", "texture-sampling.md")
    readme = open(readme_path).read()
    new, bad, new_readme = render(work, old, readme)
    status = 0
    if check:
        import difflib
        if without_softcore(keep_class_cells(old, new)) != without_softcore(old):
            sys.stdout.writelines(difflib.unified_diff(
                old.splitlines(True), new.splitlines(True), "BUDGETS.md (checked in)", "BUDGETS.md (measured)"))
            print("budgets: FAIL: BUDGETS.md is stale (run scripts/budgets and commit it)")
            status = 1
        else:
            print("budgets: BUDGETS.md is up to date")
        if new_readme != readme:
            sys.stdout.writelines(difflib.unified_diff(
                readme.splitlines(True), new_readme.splitlines(True), "docs/texture-sampling.md (checked in)",
                "docs/texture-sampling.md (measured)"))
            print("budgets: FAIL: the sampler-budgets block of docs/texture-sampling.md is stale (run scripts/budgets)")
            status = 1
        else:
            print("budgets: docs/texture-sampling.md sampler-budgets block is up to date")
    else:
        with open(path, "w") as f:
            f.write(new)
        with open(readme_path, "w") as f:
            f.write(new_readme)
        print("budgets: wrote BUDGETS.md and the sampler-budgets block of docs/texture-sampling.md")
    if bad:
        print("budgets: FAIL\n  " + "\n  ".join(bad))
        status = 1
    sys.exit(status)


if __name__ == "__main__":
    main()
