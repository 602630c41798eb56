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
import argparse
import hashlib
import json
import math
import os
import re
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from budgets import MATRIX_BATCHES, MATRIX_ROWS, RD_ROWS  # noqa: E402  (row keys and labels: one home)

B_BEGIN, B_END = "<!-- softcore:begin -->", "<!-- softcore:end -->"
R_BEGIN, R_END = "<!-- softcore-throughput:begin -->", "<!-- softcore-throughput:end -->"
D_BEGIN, D_END = "<!-- softcore-paper:begin -->", "<!-- softcore-paper:end -->"
FPGA_DATA_RE = re.compile(r"<!-- fpga-data: (\{.*?\}) -->")
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

CALL_RE = re.compile(r"^call (\w+): n (\d+) cycles min (\d+) sum (\d+) max (\d+) "
                     r"instret min (\d+) sum (\d+) max (\d+)$")
BATCH_RE = re.compile(r"^batch (\w+): n32 cycles (\d+) instret (\d+) n64 cycles (\d+) instret (\d+)$")
BASE_RE = re.compile(r"^baseline: cycles min (\d+) max (\d+) instret min (\d+) max (\d+)$")
RENDER_RE = re.compile(r"^\s*render: (\d+) cycles, (\d+) instructions")
SIM_RE = re.compile(r"soc-sim: exit code (\d+) after (\d+) cycles \(RAM (\d+) KiB\)")


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


def matrix_lines(calls, batches, mx, bad):
    """The soft-core block's sampler-matrix and ray-differential sections
    (lines); ceiling failures appended to `bad`. `mx`: (matrix calls,
    matrix baseline, matrix batches, raydiff calls, raydiff baseline)."""
    mcalls, mbase, mbatches, rcalls, rbase = mx
    cpi = lambda c: c["cycles"][1] / c["instret"][1]
    L = ["\n### Sampler matrix (issue 20)\n"]
    L.append("The rows of the \"Sampler matrix\" section above: the same wrappers, subjects, inputs and")
    L.append("order (`demo/firmware/src/probes.rs`, driven by `demo/firmware/src/bin/cycles_matrix.rs` here and")
    L.append("`budget.rs` under QEMU), counted like the calls above minus the counter reads (baseline")
    L.append(f"{mbase[0]} cycles, {mbase[2]} instruction). A BC1 row counts the first call of each pair (cache")
    L.append("emptied, blocks decoded) or the second (hits). min / mean / max over the 64 inputs; the CI")
    L.append("ceiling applies to the max cycles (achieved + 10 %, `SOFTCORE_CEILINGS` in `scripts/softcore.py`).\n")
    L.append("| call | tier | cycles | instructions | CPI | ceiling (max cycles) |")
    L.append("|---|---|---|---|---|---|")
    for key, label, tier, *_ in MATRIX_ROWS:
        c = mcalls[key]
        ceil = ceiling_cell(key, c["cycles"][2], SOFTCORE_CEILINGS, bad, "matrix")
        L.append(f"| {label} | {tier} | {fmt3(c['cycles'])} | {fmt3(c['instret'])} | {cpi(c):.2f} | {ceil} |")
    L.append("\nBatches of the wrap rows (`Sampler::sample_batch`, 32 then 64 hits per call): steady per hit =")
    L.append("(count for 64 − count for 32) / 32, amortised = count for 64 / 64.\n")
    L.append("| batch | tier | cycles steady | cycles amortised | instructions steady | CPI steady | ceiling (steady cycles) |")
    L.append("|---|---|---|---|---|---|---|")
    for label, tier, _, key in MATRIX_BATCHES:
        c32, i32, c64, i64 = mbatches[key]
        cs, is_ = (c64 - c32) / 32, (i64 - i32) / 32
        ceil = ceiling_cell(key, cs, SOFTCORE_BATCH_CEILINGS, bad, "matrix batch")
        L.append(f"| {label} | {tier} | {cs:.1f} | {c64 / 64:.1f} | {is_:.1f} | {cs / is_:.2f} | {ceil} |")
    L.append("\n### Ray differentials (issue 21)\n")
    L.append("The rows of the \"Ray differentials\" section above (`probes::raydiff_rows`, the same inputs), by")
    L.append("`demo/firmware/src/bin/cycles_raydiff.rs` (feature `raydiff`; a binary of its own, as the matrix and")
    L.append(f"the ray differentials together exceed the RAM), minus the counter reads ({rbase[0]} cycles, {rbase[2]}")
    L.append("instruction). min / mean / max; ceiling on the max cycles as above.\n")
    L.append("| call | cycles | instructions | CPI | ceiling (max cycles) |")
    L.append("|---|---|---|---|---|")
    for key, label in RD_ROWS:
        c = rcalls[key]
        ceil = ceiling_cell(key, c["cycles"][2], SOFTCORE_CEILINGS, bad, "raydiff")
        L.append(f"| {label} | {fmt3(c['cycles'])} | {fmt3(c['instret'])} | {cpi(c):.2f} | {ceil} |")
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


def budgets_block(a, calls, base, counters, render, ram, image, stack, rtl_sha, commit, batches, pc=None,
                  mx=None, bad=None):
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
    if mx is not None:
        L += matrix_lines(calls, batches, mx, bad)
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


def paper_block(calls, pcalls, rows, fpga):
    """docs/softcore.md: the hardware paper's comparison redone at the clock
    and with the logic that scripts/fpga measured (fpga: the `fpga-data`
    dict of BUDGETS.md, or None)."""
    L = [D_BEGIN]
    L.append("Written by `scripts/softcore` from its cycle counts and the FPGA figures of `scripts/fpga`")
    L.append("(BUDGETS.md); do not edit.\n")
    if not fpga:
        L.append("(No FPGA figures in BUDGETS.md yet: run `scripts/fpga`.)")
        L.append(D_END)
        return "\n".join(L)
    work = {"without co-processor": calls, "with co-processor": pcalls}
    L.append(f"Clock: the maximum frequency nextpnr-ice40 reports for the SoC on the {fpga['device']} "
             f"(seed {fpga['seed']}); the paper's prototype ran at {PAPER_MHZ} MHz on a Virtex-5 LX330.\n")
    L.append("| SoC | MHz | logic cells | LUT4 | flip-flops | DSPs | cycles, LOD + trilinear | "
             "textured hits/s per core | at the paper's 84 MHz |")
    L.append("|---|---|---|---|---|---|---|---|---|")
    per = {}
    for (name, c), key in zip(work.items(), ("plain", "pcpi")):
        v = fpga["variants"][key]
        cyc = c["lod"]["cycles"][1] + c["trilinear"]["cycles"][1]
        hz = v["mhz"] * 1e6 if v.get("mhz") else None
        per[key] = (cyc, hz, v)
        L.append(f"| {name} | {v['mhz'] if v.get('mhz') else '—'} | {v.get('lc', 'not placed')} / {fpga['lc_total']} | {v['lut']} | "
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
            for key, label in (("plain", "without"), ("pcpi", "with co-processor")):
                cyc, hz, v = per[key]
                if not hz:
                    continue
                fps = hz / (cyc * h)
                n = (math.ceil(lo / fps), math.ceil(hi / fps))
                luts = (n[0] * v["lut"], n[1] * v["lut"])
                L.append(f"| {r['scene']} | {h} | {label} | {n[0]}–{n[1]} | {luts[0]}–{luts[1]} | "
                         f"{100 * luts[0] / budget:.0f}–{100 * luts[1] / budget:.0f} % |")
        L.append("\nA Virtex-5 LUT6 holds more logic than an iCE40 LUT4, so the last column understates")
        L.append("the soft cores' share; it counts only the LOD and filter work the paper's logic does.")
    else:
        L.append("\n(BART scenes not found when this was written: no per-scene rows.)")
    L.append(D_END)
    return "\n".join(L)


def replace_block(text, begin, end, block, anchor=None):
    i, j = text.find(begin), text.find(end)
    if i >= 0 and j > i:
        return text[:i] + block + text[j + len(end):]
    if anchor and anchor in text:
        k = text.index(anchor)
        return text[:k] + block + "\n\n" + text[k:]
    return text.rstrip("\n") + "\n\n" + block + "\n"


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
    assert replace_block("a\n## Code size\n", B_BEGIN, B_END, "X", "## Code size") == "a\nX\n\n## Code size\n"
    assert si(322000) == "322 k" and si(3.2e6) == "3.2 M"
    bad = []
    assert ceiling_cell("x", 10, {"x": 11}, bad, "m") == "11" and not bad
    assert ceiling_cell("x", 12, {"x": 11}, bad, "m") == "11" and len(bad) == 1
    assert ceiling_cell("y", 1, {}, bad, "m") == "—" and len(bad) == 2
    assert all(k in SOFTCORE_CEILINGS for k, *_ in MATRIX_ROWS + RD_ROWS)
    assert all(k in SOFTCORE_BATCH_CEILINGS for *_, k in MATRIX_BATCHES)
    tb = ("tb-pcpi-tex: 9 vectors (2 tex.log2pl, 3 tex.lod), 0 mismatches, latency 4 cycles after valid; "
          "filter 1 tex.bw, 1 tex.bt, 1 tex.bb, 1 tex.blend, latency 2 5 9 5 cycles")
    assert TB_RE.search(tb).groups() == ("9", "2", "3", "0", "4")
    assert FILTER_TB_RE.search(tb).groups() == ("1", "1", "1", "1", "2", "5", "9", "5")
    print("softcore.py: self-test passed")


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--self-test", action="store_true")
    ap.add_argument("--work")
    ap.add_argument("--rtl")
    ap.add_argument("--verilator")
    ap.add_argument("--rustc")
    ap.add_argument("--budgets")
    ap.add_argument("--readme")
    ap.add_argument("--docs")
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args()
    if a.self_test:
        self_test()
        return 0
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
    bad = []
    bb = budgets_block(a, calls, base, counters, render, ram, image, stack, rtl_sha, commit, batches, pc,
                       (mcalls, mbase, mbatches, rcalls, rbase), bad)
    rb = readme_block(calls, counters, render, rows)
    targets = [(a.budgets, B_BEGIN, B_END, bb, "## Code size"), (a.readme, R_BEGIN, R_END, rb, None)]
    if a.docs and pc is not None:
        m = FPGA_DATA_RE.search(open(a.budgets).read())
        fpga = json.loads(m.group(1)) if m else None
        db = paper_block(calls, pc[0], rows, fpga)
        targets.append((a.docs, D_BEGIN, D_END, db, None))
    changed = []
    for path, begin, end, block, anchor in targets:
        old = open(path).read()
        if begin in (R_BEGIN, D_BEGIN) and not rows and begin in old:
            print(f"softcore.py: no BART rows: {os.path.basename(path)} left as it is")
            continue
        new = replace_block(old, begin, end, block, anchor)
        if new == old:
            print(f"softcore.py: {os.path.basename(path)} is up to date")
            continue
        changed.append(path)
        if a.check:
            import difflib
            print(f"softcore.py: {os.path.basename(path)} differs from this measurement "
                  "(run scripts/softcore and commit it):")
            sys.stdout.writelines(difflib.unified_diff(old.splitlines(True), new.splitlines(True),
                                                       path, path + " (measured)"))
        else:
            open(path, "w").write(new)
            print(f"softcore.py: wrote {os.path.basename(path)}")
    print(bb)
    print(rb)
    if a.docs and pc is not None:
        print(targets[-1][3])
    plus10 = lambda v: math.ceil(v * 1.1)
    print("softcore.py: this measurement + 10 % (SOFTCORE_CEILINGS, SOFTCORE_BATCH_CEILINGS):",
          {k: plus10(d[k]["cycles"][2]) for d, rows in ((mcalls, MATRIX_ROWS), (rcalls, RD_ROWS))
           for k, *_ in rows},
          {k: plus10((mbatches[k][2] - mbatches[k][0]) / 32) for *_, k in MATRIX_BATCHES})
    if bad:
        print("softcore.py: FAIL (above the ceiling)\n  " + "\n  ".join(bad))
        return 1
    if a.check and changed and os.environ.get("RAYMIP_BUDGETS_STRICT") == "1":
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
