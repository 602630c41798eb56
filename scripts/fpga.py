#!/usr/bin/env python3
"""Formats the FPGA measurement of scripts/fpga into BUDGETS.md (the block
between <!-- fpga:begin --> and <!-- fpga:end -->, which carries the figures
as a `<!-- fpga-data: {...} -->` comment for scripts/softcore.py) and
docs/softcore.md (<!-- fpga-docs:begin --> … <!-- fpga-docs:end -->), and the
ECP5 figures of the LiteX SoC into their own blocks
(<!-- fpga-ecp5:begin --> … and <!-- fpga-ecp5-docs:begin --> …, data as an
`ecp5-data` comment) from ecp5-stat-vex/cfu.txt and ecp5-pnr-*.log. Every
number comes from the files in --work: stat-0/1.txt (Yosys `stat` of the
SoC without / with the co-processor) and, with --pnr, pnr-0/1.log
(nextpnr-ice40: logic cells, maximum frequency) and pnr-*.seconds.

Without --pnr the place-and-route figures are kept from BUDGETS.md for a
variant whose synthesis figures are unchanged, and dropped otherwise.
--check writes nothing and reports differences (exit 1 on them only with
RAYMIP_BUDGETS_STRICT=1). --self-test checks the parsers on fixed text.
"""
import os
import re
import sys

from mdblock import data_comment, markers, parse_args, read_data, replace_block, update

B_BEGIN, B_END = markers("fpga")
E_BEGIN, E_END = markers("fpga-ecp5")
ED_BEGIN, ED_END = markers("fpga-ecp5-docs")
ECP5_CELL_RE = re.compile(r"^\s+(LUT4|TRELLIS_FF|CCU2C|MULT18X18D|DP16KD|TRELLIS_DPR16X4|PFUMX|L6MUX21)\s+(\d+)\s*$")
ECP5_COMB_RE = re.compile(r"TRELLIS_COMB:\s+(\d+)/\s*(\d+)")
ECP5_VARIANTS = (("vex", "VexRiscv `full`"), ("cfu", "VexRiscv `full+cfu` + co-processor (`cfu_tex.v`)"))
ECP5_SYNTH_KEYS = ("lut", "ff", "carry", "dsp", "bram", "dram")
D_BEGIN, D_END = markers("fpga-docs")
CELL_RE = re.compile(r"^\s+(SB_\w+)\s+(\d+)\s*$")
LC_RE = re.compile(r"ICESTORM_LC:\s+(\d+)/\s*(\d+)")
MHZ_RE = re.compile(r"Max frequency for clock '[^']*': ([\d.]+) MHz")
VARIANTS = (("plain", "0", "without co-processor"), ("pcpi", "1", "with co-processor (`ENABLE_TEX = 1`)"))
SYNTH_KEYS = ("lut", "ff", "carry", "dsp", "bram")


def parse_stat(text):
    """Yosys `stat` of an iCE40 netlist: LUT4s, flip-flops (every SB_DFF*),
    carry cells, DSPs (SB_MAC16), block RAMs (SB_RAM40_4K)."""
    cells = {}
    for line in text.splitlines():
        m = CELL_RE.match(line)
        if m:
            cells[m.group(1)] = cells.get(m.group(1), 0) + int(m.group(2))
    return {"lut": cells.get("SB_LUT4", 0),
            "ff": sum(v for k, v in cells.items() if k.startswith("SB_DFF")),
            "carry": cells.get("SB_CARRY", 0),
            "dsp": cells.get("SB_MAC16", 0),
            "bram": cells.get("SB_RAM40_4K", 0)}


def parse_ecp5_stat(text):
    """Yosys `stat` of an ECP5 netlist: LUT4s, flip-flops (TRELLIS_FF),
    carry cells (CCU2C), DSPs (MULT18X18D), block RAMs (DP16KD),
    distributed RAM (TRELLIS_DPR16X4)."""
    cells = {}
    for line in text.splitlines():
        m = ECP5_CELL_RE.match(line)
        if m:
            cells[m.group(1)] = cells.get(m.group(1), 0) + int(m.group(2))
    return {"lut": cells.get("LUT4", 0), "ff": cells.get("TRELLIS_FF", 0), "carry": cells.get("CCU2C", 0),
            "dsp": cells.get("MULT18X18D", 0), "bram": cells.get("DP16KD", 0),
            "dram": cells.get("TRELLIS_DPR16X4", 0)}


def parse_ecp5_pnr(text):
    """(logic cells TRELLIS_COMB used, of total, max MHz), the last report."""
    comb = ECP5_COMB_RE.findall(text)
    mhz = MHZ_RE.findall(text)
    if not comb or not mhz:
        return None
    return int(comb[-1][0]), int(comb[-1][1]), float(mhz[-1])


def synth_table(data, variants, cells, lc_heading, cost_intro, cost_cells):
    """The Markdown table of a pair of SoCs, `variants` ((key, name): without,
    then with the co-processor): the synthesis `cells` ((heading, key)), the
    placed logic cells (`lc_heading`) and the clock; then the co-processor's
    cost after `cost_intro`, per synthesis figure in `cost_cells` ((key,
    unit)) and in logic cells when both are placed."""
    L = [f"| SoC | {' | '.join(h for h, _ in cells)} | {lc_heading} | max clock |",
         "|---" * (len(cells) + 3) + "|"]
    for key, name in variants:
        v = data["variants"][key]
        lc = f"{v['lc']} / {data['lc_total']} ({100 * v['lc'] / data['lc_total']:.0f} %)" if v.get("lc") else "not placed"
        mhz = f"{v['mhz']:.2f} MHz" if v.get("mhz") else "—"
        L.append(f"| {name} | {' | '.join(str(v[k]) for _, k in cells)} | {lc} | {mhz} |")
    p, q = (data["variants"][key] for key, _ in variants)
    L.append(f"\n{cost_intro}: {', '.join(f'+{q[k] - p[k]} {unit}' for k, unit in cost_cells)}"
             + (f", +{q['lc'] - p['lc']} logic cells." if p.get("lc") and q.get("lc") else "."))
    return L


def keep_pnr(old, key, v, synth_keys):
    """Copies variant `key`'s place-and-route figures from the previous data
    `old` into `v` when its synthesis figures `synth_keys` are unchanged;
    whether it did."""
    ov = old["variants"].get(key) if old else None
    if ov is None or any(ov.get(k) != v[k] for k in synth_keys):
        return False
    for k in ("lc", "mhz", "pnr_s"):
        if ov.get(k) is not None:
            v[k] = ov[k]
    return True


def variant_figures(a, data, old, key, stat, pnr, parsers, lut_cell):
    """The figures of variant `key`: its synthesis from `stat`.txt and, with
    --pnr and a `pnr`.seconds file, its placement from `pnr`.log (the
    device's total logic cells into `data`), else the previous run's
    placement when its synthesis is unchanged (keep_pnr). `parsers`: the
    family's (stat parser, place-and-route parser, synthesis keys).
    Returns (figures, "placed" | "kept" | "changed")."""
    parse_syn, parse_pnr_log, synth_keys = parsers
    v = parse_syn(open(os.path.join(a.work, stat + ".txt")).read())
    if v["lut"] == 0:
        sys.exit(f"fpga.py: {stat}.txt has no {lut_cell} count")
    seconds = os.path.join(a.work, pnr + ".seconds")
    if a.pnr and os.path.exists(seconds):
        p = parse_pnr_log(open(os.path.join(a.work, pnr + ".log")).read())
        if p is None:
            sys.exit(f"fpga.py: {pnr}.log has no utilisation / frequency")
        v["lc"], data["lc_total"], v["mhz"] = p
        v["pnr_s"] = int(open(seconds).read())
        return v, "placed"
    return v, "kept" if keep_pnr(old, key, v, synth_keys) else "changed"


def ecp5_table(data):
    return synth_table(data, ECP5_VARIANTS,
                       (("LUT4", "lut"), ("flip-flops", "ff"), ("carry (CCU2C)", "carry"), ("DSPs (MULT18X18D)", "dsp"),
                        ("block RAMs (DP16KD)", "bram"), ("distributed RAM (DPR16X4)", "dram")),
                       "logic cells (TRELLIS_COMB)", "The co-processor on the CFU port",
                       (("lut", "LUT4"), ("ff", "flip-flops"), ("carry", "carry cells"), ("dsp", "DSPs"),
                        ("bram", "block RAMs")))


def ecp5_blocks(a, data):
    intro = (f"ECP5 {data['device']}, the LiteX SoC of `demo/softcore/litex_soc.py` with a {data['ram_bytes'] // 1024} KiB "
             f"main RAM in block RAM (the simulated 512 KiB exceeds the part), {a.yosys} `synth_ecp5`; "
             f"{data.get('nextpnr') or 'nextpnr-ecp5 (not run)'}, `--45k --package CABGA381 --speed 6 "
             f"--seed {data['seed']}` (yowasp, WebAssembly).")
    B = [E_BEGIN, "## The LiteX SoC on an ECP5 (Yosys + nextpnr-ecp5)\n",
         "Written by `scripts/fpga` (synthesis run by `scripts/test-all`; place and route with `--full`); do not edit.",
         intro + "\n"]
    B += ecp5_table(data)
    secs = [data["variants"][k].get("pnr_s") for k, _ in ECP5_VARIANTS]
    if all(secs):
        B.append(f"Place and route took {secs[0]} s and {secs[1]} s on this machine (not run in CI).")
    B.append(data_comment("ecp5", data))
    B.append(E_END)
    D = [ED_BEGIN, "Written by `scripts/fpga` (figures also in BUDGETS.md); do not edit.\n", intro + "\n"]
    D += ecp5_table(data)
    D.append(ED_END)
    return "\n".join(B), "\n".join(D)


def ecp5_data(a, old_text):
    """The ECP5 figures of this run (place and route kept from BUDGETS.md,
    as for the iCE40, when not run and the synthesis is unchanged)."""
    old = read_data(old_text, "ecp5")
    data = {"device": "LFE5U-45F (CABGA381, speed 6)", "seed": 1, "lc_total": 43848, "ram_bytes": a.ecp5_ram,
            "variants": {}}
    for key, _ in ECP5_VARIANTS:
        v, how = variant_figures(a, data, old, key, f"ecp5-stat-{key}", f"ecp5-pnr-{key}",
                                 (parse_ecp5_stat, parse_ecp5_pnr, ECP5_SYNTH_KEYS), "LUT4")
        if how == "placed":
            data["nextpnr"] = a.ecp5_nextpnr
        elif how == "kept":
            data["nextpnr"] = old.get("nextpnr")
            data["lc_total"] = old.get("lc_total", data["lc_total"])
        else:
            print(f"fpga.py: ECP5 {key}: synthesis figures changed: run scripts/fpga --full for its clock")
        data["variants"][key] = v
    return data


def parse_pnr(text):
    """(logic cells used, of total, max MHz: the last report, after routing)."""
    lc = LC_RE.findall(text)
    mhz = MHZ_RE.findall(text)
    if not lc or not mhz:
        return None
    return int(lc[-1][0]), int(lc[-1][1]), float(mhz[-1])


def table(data):
    return synth_table(data, [(key, name) for key, _, name in VARIANTS],
                       (("LUT4", "lut"), ("flip-flops", "ff"), ("carry", "carry"), ("DSPs (SB_MAC16)", "dsp"),
                        ("block RAMs", "bram")),
                       "logic cells", "The co-processor",
                       (("lut", "LUT4"), ("ff", "flip-flops"), ("carry", "carry cells"), ("dsp", "DSP")))


def budgets_block(a, data):
    L = [B_BEGIN, "## Soft core on an FPGA (Yosys + nextpnr-ice40)\n"]
    L.append("Written by `scripts/fpga` (synthesis run by `scripts/test-all`; place and route with `--pnr`);")
    L.append(f"do not edit. The SoC of the soft-core block above in `demo/softcore/fpga_top.v`, {a.yosys},")
    L.append(f"`synth_ice40 -dsp`; {a.nextpnr}, `--up5k --package sg48 --seed {data['seed']}`. RAM {data['ram_bytes']} bytes")
    L.append("of block RAM instead of the simulated 128 KiB (the UP5K's SPRAM, not inferred by this Yosys);")
    L.append("core and co-processor logic as simulated.\n")
    L += table(data)
    secs = [data["variants"][k].get("pnr_s") for k, _, _ in VARIANTS]
    if all(secs):
        L.append(f"Place and route took {secs[0]} s and {secs[1]} s on this machine (not run in CI).")
    L.append(data_comment("fpga", data))
    L.append(B_END)
    return "\n".join(L)


def docs_block(data):
    L = [D_BEGIN, "Written by `scripts/fpga` (figures also in BUDGETS.md); do not edit.\n"]
    L.append(f"iCE40 UP5K, Yosys `synth_ice40 -dsp`, nextpnr-ice40 seed {data['seed']}; RAM "
             f"{data['ram_bytes']} bytes of block RAM (see `scripts/fpga`).\n")
    L += table(data)
    L.append(D_END)
    return "\n".join(L)


def self_test():
    s = parse_stat("   Number of cells: 9\n     SB_CARRY  7\n     SB_DFF 2\n     SB_DFFE   3\n"
                   "     SB_LUT4 10\n     SB_MAC16 1\n     SB_RAM40_4K 4\n")
    assert s == {"lut": 10, "ff": 5, "carry": 7, "dsp": 1, "bram": 4}, s
    p = parse_pnr("Info: \t ICESTORM_LC:  3738/ 5280    70%\n"
                  "Info: Max frequency for clock 'clk$glb': 22.46 MHz (PASS at 12.00 MHz)\n"
                  "Info: Max frequency for clock 'clk$glb': 22.39 MHz (PASS at 12.00 MHz)\n")
    assert p == (3738, 5280, 22.39), p
    t = f"a\n{B_BEGIN}\nx\n{B_END}\nb"
    assert replace_block(t, B_BEGIN, B_END, "Y") == "a\nY\nb"
    assert replace_block("a\nEND\nb", B_BEGIN, B_END, "Y", after="END") == "a\nEND\n\nY\nb"
    e = parse_ecp5_stat("     CCU2C  279\n     DP16KD  26\n     LUT4 3849\n     MULT18X18D 4\n"
                        "     TRELLIS_DPR16X4 2\n     TRELLIS_FF 2225\n")
    assert e == {"lut": 3849, "ff": 2225, "carry": 279, "dsp": 4, "bram": 26, "dram": 2}, e
    q = parse_ecp5_pnr("Info: \t    TRELLIS_COMB:  5000/43848    11%\n"
                       "Info: Max frequency for clock '$glbnet$sys_clk': 61.20 MHz (PASS at 50.00 MHz)\n")
    assert q == (5000, 43848, 61.2), q
    print("fpga.py: self-test passed")


def main():
    a = parse_args(self_test, ("work", "rtl", "yosys", "nextpnr", "budgets", "docs", "ecp5-nextpnr"),
                   ("ram", "ecp5-ram"), ("pnr",))
    old_text = open(a.budgets).read()
    old = read_data(old_text, "fpga")
    data = {"device": "iCE40 UP5K (sg48)", "seed": 1, "lc_total": 5280, "ram_bytes": a.ram, "variants": {}}
    for key, n, _ in VARIANTS:
        v, how = variant_figures(a, data, old, key, f"stat-{n}", f"pnr-{n}",
                                 (parse_stat, parse_pnr, SYNTH_KEYS), "SB_LUT4")
        if how == "changed":
            print(f"fpga.py: {key}: synthesis figures changed: run scripts/fpga --pnr for its clock")
        data["variants"][key] = v
    e_data = ecp5_data(a, old_text)
    e_budgets, e_docs = ecp5_blocks(a, e_data)
    changed = []
    for path, begin, end, block, after in [(a.budgets, B_BEGIN, B_END, budgets_block(a, data), markers("softcore")[1]),
                                           (a.budgets, E_BEGIN, E_END, e_budgets, B_END),
                                           (a.docs, D_BEGIN, D_END, docs_block(data), None),
                                           (a.docs, ED_BEGIN, ED_END, e_docs, D_END)]:
        text = open(path).read()
        if update("fpga.py", path, text, replace_block(text, begin, end, block, after=after), a.check,
                  "run scripts/fpga --pnr"):
            changed.append(path)
    print(budgets_block(a, data))
    print(e_budgets)
    if a.check and changed and os.environ.get("RAYMIP_BUDGETS_STRICT") == "1":
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())
