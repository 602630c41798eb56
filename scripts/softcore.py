#!/usr/bin/env python3
"""Formats the soft-core measurement of scripts/softcore into BUDGETS.md (the
block between <!-- softcore:begin --> and <!-- softcore:end -->) and docs/bare-metal.md
(the throughput comparison between <!-- softcore-throughput:begin --> and
<!-- softcore-throughput:end -->). Every number comes from the files in
--work: demo.out (the demo tile on the model: counters, render cycles,
soc-sim's summary line), cycles.out (per-call cycles), matrix.out and
raydiff.out (per-call cycles of the sampler matrix and the ray differentials:
the `cycles-matrix` and `cycles-raydiff` binaries, rows named by the keys of
scripts/budgets.py `MATRIX_ROWS` / `RD_ROWS`, whose labels they get here),
size-*.txt (`size -A`) and table1/table1.json (textured hits per frame of the
BART scenes).

With the texture co-processor (issue 23) the same files prefixed `pcpi-`
(the SoC with ENABLE_TEX = 1, firmware feature `pcpi`) and tb.out (the
co-processor's bit-level testbench) give the co-processor rows of the
block, and --docs names docs/softcore.md, whose comparison with the
hardware paper (between <!-- softcore-paper:begin --> and
<!-- softcore-paper:end -->) also uses the FPGA figures scripts/fpga keeps
in BUDGETS.md (the `fpga-data` comment of its block).

--check writes nothing and reports differences (exit 1 on them only with
RAYMIP_BUDGETS_STRICT=1). A matrix or ray-differential row above its ceiling
(SOFTCORE_CEILINGS) fails in both modes. --self-test checks the parsers on
fixed text.
"""
import hashlib
import json
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from budgets import MATRIX_BATCHES, MATRIX_ROWS, RD_ROWS  # noqa: E402  (row keys and labels: one home)
from mdblock import markers, parse_args, read_data, replace_block, update  # noqa: E402

B_BEGIN, B_END = markers("softcore")
R_BEGIN, R_END = markers("softcore-throughput")
D_BEGIN, D_END = markers("softcore-paper")
FILTER_TB_RE = re.compile(r"filter (\d+) tex.bw, (\d+) tex.bt, (\d+) tex.bb, (\d+) tex.blend, latency (\d+) (\d+) (\d+) (\d+) cycles")
TB_RE = re.compile(r"tb-pcpi-tex: (\d+) vectors \((\d+) tex.log2pl, (\d+) tex.lod\), (\d+) mismatches, latency (\d+) cycles")

# The hardware paper's logic: 88 % of a Virtex-5 LX330 (51 840 slices of
# four 6-input LUTs and four flip-flops: 207 360 LUT6).
PAPER_LOGIC_PCT = 88
LX330_LUT6 = 207360

# The hardware paper's FPGA prototype: clock and frame rate range at 800×480.
PAPER_MHZ = 84
PAPER_FPS = (3.4, 6.4)
PAPER_SIZE = (800, 480)

CALLS = [("lod", "table lod"), ("cone_lod", "cone lod (with n·d)"),
         ("lod_fast", "table lod FAST"), ("cone_lod_fast", "cone lod FAST (with n·d)"),
         ("bilinear", "bilinear sample"), ("trilinear", "trilinear sample")]

# CI ceilings of the matrix and ray-differential rows on the soft core: max
# cycles per call (batches: steady cycles per hit), the achieved value of
# the measurement that wrote BUDGETS.md + 10 %. Fixed numbers, so a slower
# build fails; a row without a ceiling fails too.
SOFTCORE_CEILINGS = {
    "tw_bil": 925, "tw_bil_f": 949, "tw_tri": 1857, "tw_tri_f": 1734, "tw_tri_n": 1648, "ts_bil": 1254,
    "ts_bil_f": 1243, "ts_tri": 2417, "ts_tri_f": 2401, "ts_srgb": 3998, "ts_565": 4076,
    "ts_565_f": 3995, "ts_bc1_hit": 9262, "ts_bc1_hit_f": 9178, "ts_bc1_fill": 21640,
    "ts_bc1_fill_f": 21555, "an2": 7102, "an4": 10299, "an16": 29322, "an2_f": 6906, "an4_f": 9804,
    "an16_f": 27330, "rd_primary": 10742, "rd_transfer": 14466, "rd_reflect": 13881,
    "rd_refract": 36757, "rd_footprint": 5465, "rd_lod": 2996, "rd_gbuffer": 8054,
}
SOFTCORE_BATCH_CEILINGS = {"tw_bil": 775, "tw_bil_f": 700, "tw_tri": 1436, "tw_tri_f": 1324}
# The same on VexRiscv in the LiteX SoC: max cycles per call
# (batches: steady cycles per hit), achieved + 10 %.
# VexRiscv's direct-mapped caches make some rows move with the code and
# data layout of the whole binary (tw_tri, tw_bil_f, ts_565, an2_f, both
# trilinear batches, ts_srgb rose with unrelated changes elsewhere in it: the
# same instructions, more cycles; ts_bil (every call +160 cycles, min 168 ->
# 328), ts_bc1_fill and the FAST bilinear batch with the 64-byte level
# records, which moved the sampler data): their ceilings are the measurement
# after such a move + 10 %. tw_bil, an4_f and the ACCURATE bilinear batch:
# the measurement with the timed loops of counters::series + 10 %.
VEX_CEILINGS = {
    "tw_bil": 322, "tw_bil_f": 279, "tw_tri": 762, "tw_tri_f": 720, "tw_tri_n": 711, "ts_bil": 445,
    "ts_bil_f": 307, "ts_tri": 767, "ts_tri_f": 776, "ts_srgb": 1265, "ts_565": 1879, "ts_565_f": 2431,
    "ts_bc1_hit": 3255, "ts_bc1_hit_f": 3089, "ts_bc1_fill": 11520, "ts_bc1_fill_f": 10313, "an2": 3972,
    "an4": 4719, "an16": 10095, "an2_f": 2994, "an4_f": 3612, "an16_f": 8549, "rd_primary": 7220,
    "rd_transfer": 10567, "rd_reflect": 10199, "rd_refract": 19717, "rd_footprint": 2059, "rd_lod": 1039,
    "rd_gbuffer": 3154,
}
VEX_BATCH_CEILINGS = {"tw_bil": 183, "tw_bil_f": 173, "tw_tri": 318, "tw_tri_f": 308}
# The goals on VexRiscv: LOD + trilinear per textured hit (table lod +
# trilinear sample, RGBA8, wrap), the max of the 64 inputs, cycles; alone
# and with the co-processor on the CFU port.
VEX_GOAL = 350
CFU_GOAL = 60
CFU_TB_RE = re.compile(r"tb-cfu-tex: (\d+) vectors \((.*?)\), (\d+) mismatches, latency ([\d ]+) cycles")

CALL_RE = re.compile(r"^call (\w+): n (\d+) cycles min (\d+) sum (\d+) max (\d+) "
                     r"instret min (\d+) sum (\d+) max (\d+)$")
BATCH_RE = re.compile(r"^batch (\w+): n32 cycles (\d+) instret (\d+) n64 cycles (\d+) instret (\d+)$")
BASE_RE = re.compile(r"^baseline: cycles min (\d+) max (\d+) instret min (\d+) max (\d+)$")
RENDER_RE = re.compile(r"^\s*render: (\d+) cycles, (\d+) instructions")
SIM_RE = re.compile(r"(?:soc|litex)-sim: exit code (\d+) after (\d+) cycles \(RAM (\d+) KiB\)")


def parse_batches(text):
    """{batch call: (cycles for 32 hits, instret for 32, cycles for 64, instret for 64)}."""
    out = {}
    for line in text.splitlines():
        m = BATCH_RE.match(line.strip())
        if m:
            out[m.group(1)] = tuple(int(x) for x in m.group(2, 3, 4, 5))
    return out


def parse_cycles(text):
    """{call: dict(n, cycles=(min, mean, max), instret=(min, mean, max))}, baseline."""
    calls, base = {}, None
    for line in text.splitlines():
        m = CALL_RE.match(line.strip())
        if m:
            n = int(m.group(2))
            c = [int(x) for x in m.group(3, 4, 5)]
            i = [int(x) for x in m.group(6, 7, 8)]
            calls[m.group(1)] = {"n": n, "cycles": (c[0], c[1] / n, c[2]),
                                 "instret": (i[0], i[1] / n, i[2])}
        m = BASE_RE.match(line.strip())
        if m:
            base = tuple(int(x) for x in m.groups())
    return calls, base


def parse_demo(text):
    """Counters (dict), render (cycles, instructions), RAM KiB of the demo run."""
    counters, render, ram = {}, None, None
    for line in text.splitlines():
        s = line.strip()
        if s.startswith("counters:"):
            counters = {k: int(v) for k, v in re.findall(r"(\w+)=(\d+)", s)}
        m = RENDER_RE.match(s)
        if m:
            render = (int(m.group(1)), int(m.group(2)))
        m = SIM_RE.search(s)
        if m:
            ram = int(m.group(3))
    return counters, render, ram


def parse_variant(rd, name):
    """The demo and `cycles` outputs of SoC variant `name` (files
    NAME-cycles.out, NAME-demo.out) as a dict: calls, batches, base,
    counters, render, ram. Exits when a call or line is missing."""
    calls, base = parse_cycles(rd(f"{name}-cycles.out"))
    batches = parse_batches(rd(f"{name}-cycles.out"))
    counters, render, ram = parse_demo(rd(f"{name}-demo.out"))
    missing = [k for k, _ in CALLS if k not in calls or calls[k]["n"] != 64 or k not in batches]
    if missing or base is None or render is None or ram is None:
        sys.exit(f"softcore.py: {name}-cycles.out / {name}-demo.out lack {missing or 'a line'}")
    return {"calls": calls, "batches": batches, "base": base, "counters": counters, "render": render, "ram": ram}


def loaded_bytes(size_text):
    """Bytes of RAM the image occupies: every allocated section of `size -A`
    except the stack/heap reservations and non-loaded metadata."""
    total = 0
    for line in size_text.splitlines():
        p = line.split()
        if len(p) == 3 and p[0].startswith(".") and p[1].isdigit():
            if p[0] in (".stack", ".heap", ".comment", ".riscv.attributes") or p[0].startswith(".debug"):
                continue
            total += int(p[1])
    return total


def rtl_id(rtl):
    h = hashlib.sha256(open(rtl, "rb").read()).hexdigest()[:16]
    commit = None
    readme = os.path.join(os.path.dirname(rtl), "README.md")
    if os.path.exists(readme):
        m = re.search(r"commit ([0-9a-f]{40})", open(readme).read())
        commit = m.group(1) if m else None
    return h, commit


def fmt3(t, digits=1):
    return f"{t[0]} / {t[1]:.{digits}f} / {t[2]}"


def si(x):
    for div, unit in ((1e6, " M"), (1e3, " k")):
        if x >= div:
            return f"{x / div:.3g}{unit}"
    return f"{x:.3g} "


def ceiling_cell(key, value, table, bad, what):
    """The ceiling of row `key` as a table cell; a value above it (or a row
    without one) goes into `bad` with the achieved + 10 % figure."""
    ceil = table.get(key)
    if ceil is None or value > ceil:
        bad.append(f"{what} {key}: {value:g} cycles > ceiling {ceil} "
                   f"(achieved + 10 % = {math.ceil(value * 1.1)})")
    return str(ceil) if ceil is not None else "—"


def matrix_lines(calls, batches, mx, bad, vx=None):
    """The soft-core block's sampler-matrix and ray-differential sections
    (lines); ceiling failures appended to `bad`. `mx`: (matrix calls,
    matrix baseline, matrix batches, raydiff calls, raydiff baseline);
    `vx`: the same measured on VexRiscv (the LiteX SoC), its columns after
    PicoRV32's, or None."""
    mcalls, mbase, mbatches, rcalls, rbase = mx
    vhead = " VexRiscv cycles | VexRiscv ceiling |" if vx else ""
    vsep = "---|---|" if vx else ""

    def vcells(key, table, ceilings, what, steady=False):
        if not vx:
            return ""
        if steady:
            c32, _, c64, _ = table[key]
            v = (c64 - c32) / 32
            return f" {v:.1f} | {ceiling_cell(key, v, ceilings, bad, what)} |"
        c = table[key]
        return f" {fmt3(c['cycles'])} | {ceiling_cell(key, c['cycles'][2], ceilings, bad, what)} |"
    cpi = lambda c: c["cycles"][1] / c["instret"][1]
    L = ["\n### Sampler matrix (issue 20)\n"]
    L.append("The rows of the \"Sampler matrix\" section above: the same wrappers, subjects, inputs and")
    L.append("order (`demo/firmware/src/probes.rs`, driven by `demo/firmware/src/bin/cycles_matrix.rs` here and")
    L.append("`budget.rs` under QEMU), counted like the calls above minus the counter reads (baseline")
    L.append(f"{mbase[0]} cycles, {mbase[2]} instruction). A BC1 row counts the first call of each pair (cache")
    L.append("emptied, blocks decoded) or the second (hits). min / mean / max over the 64 inputs; the CI")
    L.append("ceiling applies to the max cycles (achieved + 10 %, `SOFTCORE_CEILINGS` in `scripts/softcore.py`).\n")
    if vx:
        L.append("VexRiscv columns: the same binary built for the LiteX SoC (below), warm caches, its own")
        L.append("ceilings (`VEX_CEILINGS`).\n")
    L.append("| call | tier | cycles | instructions | CPI | ceiling (max cycles) |" + vhead)
    L.append("|---|---|---|---|---|---|" + vsep)
    for key, label, tier, *_ in MATRIX_ROWS:
        c = mcalls[key]
        ceil = ceiling_cell(key, c["cycles"][2], SOFTCORE_CEILINGS, bad, "matrix")
        L.append(f"| {label} | {tier} | {fmt3(c['cycles'])} | {fmt3(c['instret'])} | {cpi(c):.2f} | {ceil} |" +
                 vcells(key, vx and vx[0], VEX_CEILINGS, "VexRiscv matrix"))
    L.append("\nBatches of the wrap rows (`Sampler::sample_batch`, 32 then 64 hits per call): steady per hit =")
    L.append("(count for 64 − count for 32) / 32, amortised = count for 64 / 64.\n")
    L.append("| batch | tier | cycles steady | cycles amortised | instructions steady | CPI steady | ceiling (steady cycles) |" +
             vhead.replace("cycles", "cycles steady"))
    L.append("|---|---|---|---|---|---|---|" + vsep)
    for label, tier, _, key in MATRIX_BATCHES:
        c32, i32, c64, i64 = mbatches[key]
        cs, is_ = (c64 - c32) / 32, (i64 - i32) / 32
        ceil = ceiling_cell(key, cs, SOFTCORE_BATCH_CEILINGS, bad, "matrix batch")
        L.append(f"| {label} | {tier} | {cs:.1f} | {c64 / 64:.1f} | {is_:.1f} | {cs / is_:.2f} | {ceil} |" +
                 vcells(key, vx and vx[1], VEX_BATCH_CEILINGS, "VexRiscv matrix batch", steady=True))
    L.append("\n### Ray differentials (issue 21)\n")
    L.append("The rows of the \"Ray differentials\" section above (`probes::raydiff_rows`, the same inputs), by")
    L.append("`demo/firmware/src/bin/cycles_raydiff.rs` (feature `raydiff`; a binary of its own, as the matrix and")
    L.append(f"the ray differentials together exceed the RAM), minus the counter reads ({rbase[0]} cycles, {rbase[2]}")
    L.append("instruction). min / mean / max; ceiling on the max cycles as above.\n")
    L.append("| call | cycles | instructions | CPI | ceiling (max cycles) |" + vhead)
    L.append("|---|---|---|---|---|" + vsep)
    for key, label in RD_ROWS:
        c = rcalls[key]
        ceil = ceiling_cell(key, c["cycles"][2], SOFTCORE_CEILINGS, bad, "raydiff")
        L.append(f"| {label} | {fmt3(c['cycles'])} | {fmt3(c['instret'])} | {cpi(c):.2f} | {ceil} |" +
                 vcells(key, vx and vx[2], VEX_CEILINGS, "VexRiscv raydiff"))
    mean = lambda d, k: d[k]["cycles"][1]
    c32, _, c64, _ = batches["lod_fast"]
    per = {
        "table lod FAST (batch, steady)": (c64 - c32) / 32,
        "table lod": mean(calls, "lod"),
        "cone lod (with n·d)": mean(calls, "cone_lod"),
        "ray differentials, ray-traced": sum(mean(rcalls, k) for k in ("rd_transfer", "rd_footprint", "rd_lod")),
        "ray differentials, G-buffer": sum(mean(rcalls, k) for k in ("rd_gbuffer", "rd_footprint", "rd_lod")),
    }
    L.append("\nPer textured hit (mean cycles), as in the instruction table above: ray-traced differentials =")
    L.append("transfer + footprint + lod, G-buffer (first hit) = G-buffer set-up + footprint + lod; ratio to the")
    L.append("cone lod with the normal term (the talk measured about 3× and 2× on a GPU).\n")
    L.append("| method per hit | cycles | ratio to cone |")
    L.append("|---|---|---|")
    cone = per["cone lod (with n·d)"]
    for label, c in per.items():
        L.append(f"| {label} | {c:.1f} | {c / cone:.2f} |")
    return L


def vex_lines(a, calls, vex):
    """The soft-core block's VexRiscv section (lines): the per-call and batch
    tables beside PicoRV32's, the demo tile. `vex`: dict with the parsed
    `calls`, `batches`, `base`, `counters`, `render`, `ram` of the LiteX SoC,
    and `cfu`: the same with the co-processor (or None) and `cfu_tb`: the
    CFU testbench's summary match (or None)."""
    vc, vb = vex["calls"], vex["batches"]
    cfu = vex.get("cfu")
    L = ["\n### VexRiscv in a LiteX SoC (issue 34)\n"]
    L.append(f"The same binaries built for `riscv32im-unknown-none-elf` with feature `litex`, on the SoC of")
    L.append(f"`demo/softcore/litex_soc.py` generated by LiteX's SoC builder for its simulation platform ({a.litex}):")
    L.append(f"VexRiscv `full` (`{a.vex_file}` sha256 {a.vex_sha}… from the installed pythondata-cpu-vexriscv:")
    L.append("RV32IM, 5-stage pipeline, 4 KiB direct-mapped instruction and data caches with 32-byte lines, static")
    L.append("branch prediction, barrel shifter, pipelined multiplier (`MulPlugin`), iterative divider")
    L.append("(`MulDivIterativePlugin`, one bit a cycle), machine-mode CSRs with the 64-bit counters),")
    L.append(f"{vex['ram']} KiB integrated main RAM (code and data) on LiteX's Wishbone bus, LiteX's UART; simulated cycle by")
    L.append(f"cycle by {a.verilator} with the driver `demo/softcore/litex_sim.cpp`. With caches, each series runs")
    L.append("once untimed before the timed pass (`WARM_UP` in `demo/firmware/src/counters.rs`): warm caches, as in")
    L.append("a per-hit loop. The timed loop runs from two places half a KiB apart modulo 1 KiB and the one with")
    L.append("fewer cycles is kept (`series`), so the harness's own code lines do not evict the callee's; the")
    L.append("direct-mapped caches still make every count depend on the image's layout (a change elsewhere in the")
    L.append(f"code can move a row by tens of cycles). Empty measurement {vex['base'][0]} cycles.\n")
    if cfu:
        L.append("With the co-processor: VexRiscv `full+cfu` (`VexRiscv_FullCfu.v`) with `demo/softcore/cfu_tex.v` on its")
        L.append("CFU port, the firmware with feature `cfu` (the instructions of the PCPI unit plus the addressing")
        L.append("instructions; `src/coproc/`).")
        tb = vex.get("cfu_tb")
        if tb:
            L.append(f"The CFU alone (`tb_cfu_tex.cpp`): {tb.group(1)} reference vectors from the software paths")
            L.append(f"({tb.group(2)}), {tb.group(3)} mismatching bits; answers {tb.group(4)} cycles after the command")
            L.append("(in that order).")
        L.append("")
    ch = " VexRiscv + CFU cycles | VexRiscv + CFU instructions | VexRiscv + CFU batch steady |" if cfu else ""
    L.append("| call | PicoRV32 cycles (mean) | VexRiscv cycles | VexRiscv instructions | VexRiscv CPI | VexRiscv batch steady |" + ch)
    L.append("|---|---|---|---|---|---|" + ("---|---|---|" if cfu else ""))
    steady = lambda b, k: (b[k][2] - b[k][0]) / 32
    for k, name in CALLS:
        c, v = calls[k], vc[k]
        row = (f"| {name} | {c['cycles'][1]:.1f} | {fmt3(v['cycles'])} | {fmt3(v['instret'])} | "
               f"{v['cycles'][1] / v['instret'][1]:.2f} | {steady(vb, k):.1f} |")
        if cfu:
            q = cfu["calls"][k]
            row += f" {fmt3(q['cycles'])} | {fmt3(q['instret'])} | {steady(cfu['batches'], k):.1f} |"
        L.append(row)
    for label, d, goal in (("VexRiscv", vex, VEX_GOAL), ("VexRiscv + CFU", cfu, CFU_GOAL)):
        if not d:
            continue
        c = d["calls"]
        lt = [c["lod"]["cycles"][i] + c["trilinear"]["cycles"][i] for i in (0, 1, 2)]
        ok = "met" if lt[2] <= goal else "missed"
        L.append(f"\n{label}, LOD + trilinear per textured hit (table lod + trilinear sample, RGBA8, wrap): "
                 f"{lt[0]} / {lt[1]:.1f} / {lt[2]} cycles (min / mean / sum of the maxima); issue 34's goal "
                 f"≤ {goal} cycles at the max: {ok}.")
    for label, d in (("VexRiscv", vex), ("VexRiscv + CFU", cfu)):
        if not d:
            continue
        cyc, ins = d["render"]
        px = d["counters"].get("pixels", 1)
        L.append(f"Whole demo tile on {label} (checksum and counters equal to the host's): {cyc} cycles, "
                 f"{ins} instructions, CPI {cyc / ins:.2f}; {cyc / px:.0f} cycles per pixel.")
    return L


def budgets_block(a, calls, base, counters, render, ram, image, stack, rtl_sha, commit, batches, pc=None,
                  mx=None, bad=None, vex=None):
    L = [B_BEGIN, "## Cycles on the PicoRV32 soft core (RTL under Verilator)\n"]
    L.append("Written by `scripts/softcore` (run by `scripts/test-all`); do not edit. Machine: the")
    src = f"YosysHQ PicoRV32 RTL (commit {commit[:12]}, " if commit else "PicoRV32 RTL ("
    L.append(f"{src}`picorv32.v` sha256 {rtl_sha}…) in the SoC `demo/softcore/soc.v`,")
    L.append(f"simulated cycle by cycle by {a.verilator}. Core: RV32IMC with `ENABLE_FAST_MUL`,")
    L.append("`ENABLE_DIV`, `BARREL_SHIFTER`, `COMPRESSED_ISA`, `ENABLE_COUNTERS`, no interrupts;")
    L.append(f"{ram} KiB single-port on-chip RAM holding code and data, one block-RAM read cycle per")
    L.append("access (request in cycle t, data in t+1), no caches. Firmware: `riscv32imc-unknown-none-elf`,")
    L.append(f"release profile, {a.rustc}.\n")
    L.append("Cycles and instructions per call from `rdcycle`/`rdinstret` read around each call")
    L.append("(`demo/firmware/src/bin/cycles.rs`), call-inclusive (argument moves, call, return) minus an")
    L.append(f"empty measurement ({base[0]} cycles, {base[2]} instruction: the counter reads), over the same")
    L.append("64 inputs as the QEMU budgets above. min / mean / max; CPI = mean cycles / mean instructions.\n")
    L.append("| call | cycles | instructions | CPI |")
    L.append("|---|---|---|---|")
    for k, name in CALLS:
        c = calls[k]
        L.append(f"| {name} | {fmt3(c['cycles'])} | {fmt3(c['instret'])} | "
                 f"{c['cycles'][1] / c['instret'][1]:.2f} |")
    L.append("\nBatch entry points (`table_lod_batch`, `cone_lod_batch`, their FAST twins, `Sampler::sample_batch`), each")
    L.append("called once on the first 32 and once on all 64 inputs above, counters read around the call")
    L.append("(minus the empty measurement): steady state per hit = (count for 64 − count for 32) / 32,")
    L.append("amortised = count for 64 / 64 (call and loop set-up included).\n")
    L.append("| batch call | cycles steady | cycles amortised | instructions steady | instructions amortised | CPI steady |")
    L.append("|---|---|---|---|---|---|")
    for k, name in CALLS:
        c32, i32, c64, i64 = batches[k]
        cs, is_ = (c64 - c32) / 32, (i64 - i32) / 32
        L.append(f"| {name} | {cs:.1f} | {c64 / 64:.1f} | {is_:.1f} | {i64 / 64:.1f} | {cs / is_:.2f} |")
    cyc, ins = render
    px = counters.get("pixels", 0)
    tex = counters.get("samples", 0)
    L.append(f"\nWhole demo tile (64×48 = {px} pixels, {counters.get('hits', 0)} hits, {tex} textured")
    L.append(f"samples; checksum equal to the host's): {cyc} cycles, {ins} instructions, CPI {cyc / ins:.2f};")
    L.append(f"{cyc / px:.0f} cycles per pixel. Image {image} bytes (`size -A`, loaded sections) + {stack}")
    L.append(f"bytes of stack painted under the render, of the {ram} KiB RAM.")
    if pc is not None:
        pcalls, pbatches, pcounters, prender, tb = pc
        L.append("\n### With the texture co-processor\n")
        L.append("The same measurement on the SoC with `ENABLE_TEX = 1` (`demo/softcore/pcpi_tex.v` on the")
        L.append("core's PCPI port: `tex.log2pl`, `tex.lod`, and the ACCURATE filter's `tex.bw`, `tex.bt`, `tex.bb`,")
        L.append("`tex.blend`) and the firmware built with feature `pcpi` (`src/coproc/pcpi.rs`: table lod = the two lod")
        L.append("instructions, cone lod's two log2 = `tex.log2pl`, each bilinear level = `tex.bw` + `tex.bt` + `tex.bb`,")
        L.append("the trilinear level blend = `tex.blend`; the FAST lods and the FAST, nearest and sRGB kernels are")
        L.append("unchanged). Demo tile: checksum and counters equal to the host's.")
        if tb:
            ftb = tb[5:]
            L.append(f"Co-processor alone (`tb_pcpi_tex.cpp`): {tb[0]} reference vectors from the software paths")
            L.append(f"({tb[1]} `tex.log2pl`, {tb[2]} `tex.lod`" +
                     (f", {ftb[0]} `tex.bw`, {ftb[1]} `tex.bt`, {ftb[2]} `tex.bb`, {ftb[3]} `tex.blend`" if ftb else "") +
                     f"), {tb[3]} mismatching bits; lod results {tb[4]} cycles after `pcpi_valid`" +
                     (f", filter results {ftb[4]} / {ftb[5]} / {ftb[6]} / {ftb[7]} (`tex.bw` / `bt` / `bb` / `blend`)" if ftb else "") +
                     ".\n")
        L.append("| call | cycles without | cycles with co-processor | instructions with | CPI with | batch steady without | batch steady with |")
        L.append("|---|---|---|---|---|---|---|")
        for k, name in CALLS:
            c, q = calls[k], pcalls[k]
            b0 = (batches[k][2] - batches[k][0]) / 32
            b1 = (pbatches[k][2] - pbatches[k][0]) / 32
            L.append(f"| {name} | {c['cycles'][1]:.1f} | {fmt3(q['cycles'])} | {fmt3(q['instret'])} | "
                     f"{q['cycles'][1] / q['instret'][1]:.2f} | {b0:.1f} | {b1:.1f} |")
        lod0 = calls["lod"]["cycles"][1] + calls["trilinear"]["cycles"][1]
        lod1 = pcalls["lod"]["cycles"][1] + pcalls["trilinear"]["cycles"][1]
        L.append(f"\nLOD + trilinear per textured hit: {lod0:.1f} → {lod1:.1f} cycles. Demo tile: "
                 f"{render[0]} → {prender[0]} cycles ({prender[0] / pcounters.get('pixels', 1):.0f} per pixel).")
        L.append("\nThe filter (issue 23's goal: LOD + trilinear ≤ 500 cycles per textured hit), mean cycles per call")
        L.append("and batch steady state per hit:\n")
        L.append("| filter work | call without | call with co-processor | batch steady without | batch steady with |")
        L.append("|---|---|---|---|---|")
        steady = lambda b, k: (b[k][2] - b[k][0]) / 32
        for label, ks in (("bilinear sample", ("bilinear",)), ("trilinear sample", ("trilinear",)),
                          ("LOD + trilinear per textured hit (table lod + trilinear)", ("lod", "trilinear"))):
            c0 = sum(calls[k]["cycles"][1] for k in ks)
            c1 = sum(pcalls[k]["cycles"][1] for k in ks)
            s0 = sum(steady(batches, k) for k in ks)
            s1 = sum(steady(pbatches, k) for k in ks)
            L.append(f"| {label} | {c0:.1f} | {c1:.1f} | {s0:.1f} | {s1:.1f} |")
    if vex is not None:
        L += vex_lines(a, calls, vex)
    if mx is not None:
        L += matrix_lines(calls, batches, mx, bad, vex and vex["mx"])
    L.append(B_END)
    return "\n".join(L)


def readme_block(calls, counters, render, rows):
    hz = PAPER_MHZ * 1e6
    lod = calls["lod"]["cycles"][1]
    tri = calls["trilinear"]["cycles"][1]
    fast = calls["lod_fast"]["cycles"][1]
    per = {"LOD alone (table lod)": lod, "LOD alone (table lod FAST)": fast, "LOD + trilinear": lod + tri}
    L = [R_BEGIN]
    L.append("Written by `scripts/softcore` from its measurement (cycles: BUDGETS.md, soft-core block;")
    L.append("hits: `table1` at 800×480, animation time 0, up to 10 bounces); do not edit.\n")
    L.append(f"| work per textured hit | cycles (mean) | textured hits/s, one PicoRV32 at {PAPER_MHZ} MHz |")
    L.append("|---|---|---|")
    for name, c in per.items():
        L.append(f"| {name} | {c:.1f} | {si(hz / c)} |")
    if rows:
        lo, hi = PAPER_FPS
        L.append(f"\n| scene ({PAPER_SIZE[0]}×{PAPER_SIZE[1]}) | textured hits / frame | "
                 f"frames/s, LOD alone | frames/s, LOD + trilinear | "
                 f"PicoRV32s for {lo}–{hi} fps, LOD alone | PicoRV32s for {lo}–{hi} fps, LOD + trilinear |")
        L.append("|---|---|---|---|---|---|")
        for r in rows:
            h = r["textured_hits"]
            fps = [hz / (c * h) for c in (lod, lod + tri)]
            cores = [f"{math.ceil(lo / f)}–{math.ceil(hi / f)}" for f in fps]
            L.append(f"| {r['scene']} | {h} | {fps[0]:.2f} | {fps[1]:.3f} | {cores[0]} | {cores[1]} |")
    else:
        L.append("\n(BART scenes not found when this was written: no per-scene rows.)")
    cyc, _ = render
    px = counters.get("pixels", 1)
    frame = PAPER_SIZE[0] * PAPER_SIZE[1] * cyc / px
    L.append(f"\nFor scale, the whole firmware path of the demo tile (tile tracer, ray stack, table lod,")
    L.append(f"trilinear through the texel cache) takes {cyc / px:.0f} cycles per pixel on the soft core:")
    L.append(f"{hz / frame:.3f} frames/s at {PAPER_SIZE[0]}×{PAPER_SIZE[1]} and {PAPER_MHZ} MHz for a scene as simple as the demo's.")
    L.append(R_END)
    return "\n".join(L)


def paper_block(calls, pcalls, rows, fpga, vex=None, ecp5=None):
    """docs/softcore.md: the hardware paper's comparison redone at the clock
    and with the logic that scripts/fpga measured, for every SoC side by
    side: PicoRV32 without and with the PCPI co-processor on the iCE40 UP5K
    (fpga: the `fpga-data` dict of BUDGETS.md, or None), VexRiscv without
    and with the CFU co-processor on the ECP5 (`vex`: the VexRiscv
    measurement as in vex_lines, `ecp5`: the `ecp5-data` dict, or None)."""
    L = [D_BEGIN]
    L.append("Written by `scripts/softcore` from its cycle counts and the FPGA figures of `scripts/fpga`")
    L.append("(BUDGETS.md); do not edit.\n")
    if not fpga:
        L.append("(No FPGA figures in BUDGETS.md yet: run `scripts/fpga`.)")
        L.append(D_END)
        return "\n".join(L)
    socs = [("PicoRV32", calls, fpga, "plain"), ("PicoRV32 + PCPI co-processor", pcalls, fpga, "pcpi")]
    if vex and ecp5:
        socs.append(("VexRiscv", vex["calls"], ecp5, "vex"))
        if vex.get("cfu"):
            socs.append(("VexRiscv + CFU co-processor", vex["cfu"]["calls"], ecp5, "cfu"))
    L.append(f"Clock: the maximum frequency nextpnr reports for each SoC on its FPGA (PicoRV32: {fpga['device']}, "
             f"seed {fpga['seed']}" + (f"; VexRiscv in LiteX: ECP5 {ecp5['device']}, seed {ecp5['seed']}" if ecp5 else "") +
             f"); the paper's prototype ran at {PAPER_MHZ} MHz on a Virtex-5 LX330. Cycles: LOD + trilinear per")
    L.append("textured hit (table lod + trilinear sample, RGBA8, wrap; mean of the 64 inputs, BUDGETS.md's soft-core block).\n")
    L.append("| SoC | FPGA | MHz | LUT4 | flip-flops | DSPs | cycles, LOD + trilinear | "
             "textured hits/s per core | at the paper's 84 MHz |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    per = []
    for name, c, f, key in socs:
        v = f["variants"][key]
        cyc = c["lod"]["cycles"][1] + c["trilinear"]["cycles"][1]
        hz = v["mhz"] * 1e6 if v.get("mhz") else None
        per.append((name, cyc, hz, v))
        L.append(f"| {name} | {f['device'].split(' (')[0]} | {v['mhz'] if v.get('mhz') else 'not placed'} | {v['lut']} | "
                 f"{v['ff']} | {v['dsp']} | {cyc:.1f} | {si(hz / cyc) if hz else '—'} | {si(PAPER_MHZ * 1e6 / cyc)} |")
    if rows:
        lo, hi = PAPER_FPS
        L.append(f"\nCores for the paper's {lo}–{hi} frames/s at {PAPER_SIZE[0]}×{PAPER_SIZE[1]} (textured hits "
                 "per frame from `table1`; LOD + trilinear per hit, nothing else of the frame):\n")
        L.append("| scene | textured hits / frame | SoC | cores at its clock | LUT4 for those cores | "
                 "share of the paper's logic (88 % of the LX330's 207 360 LUT6) |")
        L.append("|---|---|---|---|---|---|")
        budget = PAPER_LOGIC_PCT / 100 * LX330_LUT6
        for r in rows:
            h = r["textured_hits"]
            for name, cyc, hz, v in per:
                if not hz:
                    continue
                fps = hz / (cyc * h)
                n = (math.ceil(lo / fps), math.ceil(hi / fps))
                luts = (n[0] * v["lut"], n[1] * v["lut"])
                L.append(f"| {r['scene']} | {h} | {name} | {n[0]}–{n[1]} | {luts[0]}–{luts[1]} | "
                         f"{100 * luts[0] / budget:.0f}–{100 * luts[1] / budget:.0f} % |")
        L.append("\nA Virtex-5 LUT6 holds more logic than an iCE40 or ECP5 LUT4, so the last column understates")
        L.append("the soft cores' share; it counts only the LOD and filter work the paper's logic does.")
        kitchen = [r for r in rows if r["scene"] == "kitchen"]
        if kitchen and len(per) == 4 and per[3][2]:
            name, cyc, hz, _ = per[3]
            need = PAPER_FPS[0] * kitchen[0]["textured_hits"] * cyc / 1e6
            n = math.ceil(PAPER_FPS[0] * kitchen[0]["textured_hits"] * cyc / hz)
            L.append(f"\nIssue 34's goal, one {name} for the kitchen at {PAPER_FPS[0]} frames/s: {n} cores at "
                     f"{hz / 1e6:.1f} MHz ({'met' if n <= 1 else 'missed'}); one core would need {need:.0f} MHz at "
                     f"{cyc:.1f} cycles per hit, or {hz / (PAPER_FPS[0] * kitchen[0]['textured_hits']):.1f} cycles "
                     f"per hit at {hz / 1e6:.1f} MHz.")
    else:
        L.append("\n(BART scenes not found when this was written: no per-scene rows.)")
    L.append(D_END)
    return "\n".join(L)


def self_test():
    calls, base = parse_cycles("baseline: cycles min 18 max 18 instret min 1 max 1\n"
                               "call lod: n 4 cycles min 10 sum 44 max 12 instret min 2 sum 10 max 3\n")
    assert base == (18, 18, 1, 1), base
    assert calls["lod"]["cycles"] == (10, 11.0, 12) and calls["lod"]["instret"] == (2, 2.5, 3)
    assert parse_batches("batch lod: n32 cycles 100 instret 40 n64 cycles 196 instret 76\n") == \
        {"lod": (100, 40, 196, 76)}
    c, r, ram = parse_demo("counters: pixels=3 hits=2 samples=1\n"
                           "render: 100 cycles, 20 instructions (rdcycle/rdinstret)\n"
                           "soc-sim: exit code 0 after 123 cycles (RAM 128 KiB)\n")
    assert c == {"pixels": 3, "hits": 2, "samples": 1} and r == (100, 20) and ram == 128
    assert loaded_bytes("x :\nsection size addr\n.text 10 0\n.rodata 5 10\n.stack 99 15\n"
                        ".debug_info 7 0\nTotal 121\n") == 15
    t = f"a\n{B_BEGIN}\nold\n{B_END}\nb\n"
    assert replace_block(t, B_BEGIN, B_END, "X") == "a\nXb\n".replace("Xb", "X\nb")
    assert replace_block("a\n## Code size\n", B_BEGIN, B_END, "X", before="## Code size") == "a\nX\n\n## Code size\n"
    assert si(322000) == "322 k" and si(3.2e6) == "3.2 M"
    bad = []
    assert ceiling_cell("x", 10, {"x": 11}, bad, "m") == "11" and not bad
    assert ceiling_cell("x", 12, {"x": 11}, bad, "m") == "11" and len(bad) == 1
    assert ceiling_cell("y", 1, {}, bad, "m") == "—" and len(bad) == 2
    assert all(k in SOFTCORE_CEILINGS for k, *_ in MATRIX_ROWS + RD_ROWS)
    assert all(k in SOFTCORE_BATCH_CEILINGS for *_, k in MATRIX_BATCHES)
    assert all(k in VEX_CEILINGS for k, *_ in MATRIX_ROWS + RD_ROWS)
    assert all(k in VEX_BATCH_CEILINGS for *_, k in MATRIX_BATCHES)
    assert CFU_TB_RE.search("tb-cfu-tex: 9 vectors (1 tex.log2pl, 8 tex.lod), 0 mismatches, latency 3 1 cycles"
                            ).groups() == ("9", "1 tex.log2pl, 8 tex.lod", "0", "3 1")
    tb = ("tb-pcpi-tex: 9 vectors (2 tex.log2pl, 3 tex.lod), 0 mismatches, latency 4 cycles after valid; "
          "filter 1 tex.bw, 1 tex.bt, 1 tex.bb, 1 tex.blend, latency 2 5 9 5 cycles")
    assert TB_RE.search(tb).groups() == ("9", "2", "3", "0", "4")
    assert FILTER_TB_RE.search(tb).groups() == ("1", "1", "1", "1", "2", "5", "9", "5")
    print("softcore.py: self-test passed")


def main():
    # --litex: the LiteX and pythondata-cpu-vexriscv versions (the VexRiscv
    # runs); --vex-rtl: the VexRiscv Verilog file the LiteX SoC used.
    a = parse_args(self_test, ("work", "rtl", "verilator", "rustc", "budgets", "readme", "docs", "litex", "vex-rtl"))
    rd = lambda name: open(os.path.join(a.work, name)).read()
    calls, base = parse_cycles(rd("cycles.out"))
    missing = [k for k, _ in CALLS if k not in calls or calls[k]["n"] != 64]
    if missing or base is None:
        sys.exit(f"softcore.py: cycles.out lacks {missing or 'the baseline'}")
    batches = parse_batches(rd("cycles.out"))
    missing = [k for k, _ in CALLS if k not in batches]
    if missing:
        sys.exit(f"softcore.py: cycles.out lacks the batch lines of {missing}")
    counters, render, ram = parse_demo(rd("demo.out"))
    if not counters or render is None or ram is None:
        sys.exit("softcore.py: demo.out lacks the counters, render or soc-sim lines")
    stack = int(re.search(r"stack: (\d+) bytes", rd("demo.out")).group(1))
    image = loaded_bytes(rd("size-demo.txt"))
    rtl_sha, commit = rtl_id(a.rtl)
    rows = []
    t1 = os.path.join(a.work, "table1", "table1.json")
    if os.path.exists(t1):
        rows = [r for r in json.load(open(t1))["rows"] if r["scene"] in ("kitchen", "robots")]
        for r in rows:
            if (r["width"], r["height"]) != PAPER_SIZE:
                sys.exit(f"softcore.py: table1 row {r['scene']} is {r['width']}×{r['height']}")
    pc = None
    if os.path.exists(os.path.join(a.work, "pcpi-cycles.out")):
        pcalls, _ = parse_cycles(rd("pcpi-cycles.out"))
        pbatches = parse_batches(rd("pcpi-cycles.out"))
        pcounters, prender, _ = parse_demo(rd("pcpi-demo.out"))
        missing = [k for k, _ in CALLS if k not in pcalls or k not in pbatches]
        if missing or prender is None:
            sys.exit(f"softcore.py: pcpi-cycles.out / pcpi-demo.out lack {missing or 'the render line'}")
        tb = None
        if os.path.exists(os.path.join(a.work, "tb.out")):
            m = TB_RE.search(rd("tb.out"))
            tb = tuple(int(x) for x in m.groups()) if m else None
            f = FILTER_TB_RE.search(rd("tb.out"))
            if tb and f:
                tb += tuple(int(x) for x in f.groups())
        pc = (pcalls, pbatches, pcounters, prender, tb)
    mcalls, mbase = parse_cycles(rd("matrix.out"))
    mbatches = parse_batches(rd("matrix.out"))
    rcalls, rbase = parse_cycles(rd("raydiff.out"))
    missing = [k for k, *_ in MATRIX_ROWS if k not in mcalls or mcalls[k]["n"] != 64]
    missing += [k for *_, k in MATRIX_BATCHES if k not in mbatches]
    missing += [k for k, _ in RD_ROWS if k not in rcalls or rcalls[k]["n"] != 64]
    if missing or mbase is None or rbase is None:
        sys.exit(f"softcore.py: matrix.out / raydiff.out lack {missing or 'the baseline'}")
    vex = None
    if os.path.exists(os.path.join(a.work, "vex-cycles.out")):
        vex = parse_variant(rd, "vex")
        vm, _ = parse_cycles(rd("vex-matrix.out"))
        vmb = parse_batches(rd("vex-matrix.out"))
        vr, _ = parse_cycles(rd("vex-raydiff.out"))
        missing = [k for k, *_ in MATRIX_ROWS if k not in vm] + [k for *_, k in MATRIX_BATCHES if k not in vmb]
        missing += [k for k, _ in RD_ROWS if k not in vr]
        if missing:
            sys.exit(f"softcore.py: vex-matrix.out / vex-raydiff.out lack {missing}")
        vex["mx"] = (vm, vmb, vr)
        if os.path.exists(os.path.join(a.work, "cfu-cycles.out")):
            vex["cfu"] = parse_variant(rd, "cfu")
        if os.path.exists(os.path.join(a.work, "tb-cfu.out")):
            vex["cfu_tb"] = CFU_TB_RE.search(rd("tb-cfu.out"))
        a.vex_file = os.path.basename(a.vex_rtl)
        a.vex_sha = hashlib.sha256(open(a.vex_rtl, "rb").read()).hexdigest()[:16]
    bad = []
    bb = budgets_block(a, calls, base, counters, render, ram, image, stack, rtl_sha, commit, batches, pc,
                       (mcalls, mbase, mbatches, rcalls, rbase), bad, vex)
    rb = readme_block(calls, counters, render, rows)
    targets = [(a.budgets, B_BEGIN, B_END, bb, "## Code size"), (a.readme, R_BEGIN, R_END, rb, None)]
    if a.docs and pc is not None:
        btext = open(a.budgets).read()
        db = paper_block(calls, pc[0], rows, read_data(btext, "fpga"), vex, read_data(btext, "ecp5"))
        targets.append((a.docs, D_BEGIN, D_END, db, None))
    changed = []
    for path, begin, end, block, anchor in targets:
        old = open(path).read()
        if begin in (R_BEGIN, D_BEGIN) and not rows and begin in old:
            print(f"softcore.py: no BART rows: {os.path.basename(path)} left as it is")
            continue
        if update("softcore.py", path, old, replace_block(old, begin, end, block, before=anchor), a.check,
                  "run scripts/softcore"):
            changed.append(path)
    print(bb)
    print(rb)
    if a.docs and pc is not None:
        print(targets[-1][3])
    plus10 = lambda v: math.ceil(v * 1.1)
    print("softcore.py: this measurement + 10 % (SOFTCORE_CEILINGS, SOFTCORE_BATCH_CEILINGS):",
          {k: plus10(d[k]["cycles"][2]) for d, rows in ((mcalls, MATRIX_ROWS), (rcalls, RD_ROWS))
           for k, *_ in rows},
          {k: plus10((mbatches[k][2] - mbatches[k][0]) / 32) for *_, k in MATRIX_BATCHES})
    if vex:
        vm, vmb, vr = vex["mx"]
        print("softcore.py: VexRiscv + 10 % (VEX_CEILINGS, VEX_BATCH_CEILINGS):",
              {k: plus10(d[k]["cycles"][2]) for d, rows in ((vm, MATRIX_ROWS), (vr, RD_ROWS)) for k, *_ in rows},
              {k: plus10((vmb[k][2] - vmb[k][0]) / 32) for *_, k in MATRIX_BATCHES})
    if bad:
        print("softcore.py: FAIL (above the ceiling)\n  " + "\n  ".join(bad))
        return 1
    if a.check and changed and os.environ.get("RAYMIP_BUDGETS_STRICT") == "1":
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
