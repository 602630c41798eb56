#!/usr/bin/env python3
"""The raymip LiteX SoC: VexRiscv (the `full` variant of pythondata-cpu-vexriscv,
or `full+cfu` with the texture co-processor demo/softcore/cfu_tex.v on its
CFU port), one main RAM holding code and data, LiteX's UART and a
simulation exit register, for LiteX's simulation platform.

--cfu names cfu_tex.v; its tex_log2pl.v beside it is added too, the main
RAM is BankedRAM (even and odd words) instead of LiteX's integrated SRAM,
and the CFU's texture unit gets a read port on each bank
(add_cfu_ram_port).

Generates the SoC's Verilog with LiteX's SoC builder (SoCCore, SimPlatform)
into --out: `sim.v` (top module `sim`), the CPU's and the CFU's Verilog
files listed in `sources.txt` (the installed packages' paths: nothing is
copied), `public.vlt` (the Verilator configuration that lets the driver
demo/softcore/litex_sim.cpp load an ELF image into the main RAM),
`main_ram.h` (for the driver: one main RAM array, or the CFU SoC's two
banks) and `csr.csv`. scripts/softcore then builds the Verilator model
itself: one model per variant serves every firmware image.

The memory map is LiteX's, with the firmware's fixed addresses
(demo/softcore/litex/memory.x and demo/firmware/src/console.rs), which this
script checks against the generated CSR map:
  0x4000_0000  main RAM (--ram-bytes, default 512 KiB): code, data, stack;
               the CPU's reset address.
  0xf000_0000  CSRs: `uart` (rxtx, txfull, ...) and `sim_exit` (a write of
               the exit code ends the simulation), each at a fixed page.

--bursting: LiteX's bus bursting (SoCCore's `bus_bursting`): the main RAM
answers the incrementing bursts of VexRiscv's cache refills one word a
cycle (LiteX's integrated SRAM, or BankedRAM); without it one word every
two cycles. scripts/softcore and scripts/fpga measure the SoC without it.

Usage: litex_soc.py --out DIR [--cfu] [--ram-bytes N] [--bursting]
"""
import argparse
import csv
import os
import re
import sys

from migen import Cat, Memory, Module, Mux, Signal, If
from migen.fhdl.specials import WRITE_FIRST

from litex.build.generic_platform import Pins, Subsignal
from litex.build.sim import SimPlatform
from litex.build.io import CRG
from litex.soc.integration import export
from litex.soc.integration.soc import SoCRegion
from litex.soc.interconnect import wishbone
from litex.soc.integration.soc_core import SoCCore
from litex.soc.interconnect.csr import AutoCSR, CSRStorage

MAIN_RAM = 0x4000_0000
CSR_BASE = 0xF000_0000
# CSR pages (0x800 bytes each) of the two peripherals the firmware uses; the
# firmware's constants (demo/firmware/src/console.rs) must match.
CSR_LOCATIONS = {"uart": 2, "sim_exit": 3}

_io = [
    ("sys_clk", 0, Pins(1)),
    ("sys_rst", 0, Pins(1)),
    # LiteX's simulation UART: a byte stream each way.
    ("serial", 0,
        Subsignal("source_valid", Pins(1)),
        Subsignal("source_ready", Pins(1)),
        Subsignal("source_data", Pins(8)),
        Subsignal("sink_valid", Pins(1)),
        Subsignal("sink_ready", Pins(1)),
        Subsignal("sink_data", Pins(8)),
    ),
    # The exit register, seen by the driver.
    ("sim_exit", 0,
        Subsignal("valid", Pins(1)),
        Subsignal("code", Pins(32)),
    ),
]


class SimExit(Module, AutoCSR):
    """A CSR whose write ends the simulation: `valid` pulses for one cycle
    with the written value on `code`."""

    def __init__(self, pads):
        self.code = CSRStorage(32, description="Exit code; a write ends the simulation.")
        self.sync += pads.valid.eq(self.code.re)
        self.comb += pads.code.eq(self.code.storage)


class BankedRAM(Module):
    """The main RAM of the CFU SoC as two banks of 32-bit words, `even` and
    `odd` (word address bit 0), each a memory of its own with the bus's
    read/write port (byte enables) and one read port `cfu_ports[b]` for the
    texture unit: two ports per memory, so that block RAM holds each bank
    once (one memory with three ports is copied). On the Wishbone bus it
    behaves as LiteX's SRAM: the data and ack one cycle after the request,
    and with `bursting` one word a cycle in an incrementing read burst
    (`cti` 0b010, as VexRiscv's cache refills are): while a burst beat is
    acknowledged the banks already read the next word, and ack stays high
    until the beat that ends the burst."""

    def __init__(self, ram_bytes, bursting=False):
        words = ram_bytes // 4
        aw = words.bit_length() - 1
        assert words == 1 << aw, "the main RAM's size must be a power of two"
        self.bus = wishbone.Interface(data_width=32, address_width=32, addressing="word")
        self.banks = [Memory(32, words // 2, name=f"main_ram_{n}") for n in ("even", "odd")]
        ports = [m.get_port(write_capable=True, we_granularity=8, mode=WRITE_FIRST) for m in self.banks]
        self.cfu_ports = [m.get_port(has_re=False) for m in self.banks]
        self.specials += self.banks + ports + self.cfu_ports
        bus = self.bus
        adr = bus.adr[:aw]
        # The word the banks read: with bursting, the next one of an
        # incrementing read burst whose beat is acknowledged now, else the
        # bus's. (Without, the SoC's Verilog is the one without the option.)
        radr = adr
        if bursting:
            burst = Signal()
            radr = Signal(aw)
            self.comb += [
                burst.eq(bus.cyc & bus.stb & ~bus.we & (bus.cti == wishbone.CTI_BURST_INCREMENTING)),
                radr.eq(Mux(burst & bus.ack, adr + 1, adr)),
            ]
        for b, port in enumerate(ports):
            self.comb += [port.adr.eq(radr[1:]), port.dat_w.eq(bus.dat_w)]
            self.comb += [port.we[i].eq(bus.cyc & bus.stb & bus.we & bus.sel[i] & (adr[0] == b)) for i in range(4)]
        # The bank of the word read in the previous cycle.
        odd = Signal()
        self.sync += odd.eq(radr[0])
        self.comb += bus.dat_r.eq(Mux(odd, ports[1].dat_r, ports[0].dat_r))
        more = (~bus.ack | burst) if bursting else ~bus.ack
        self.sync += [bus.ack.eq(0), If(bus.cyc & bus.stb & more, bus.ack.eq(1))]


class RaymipSoC(SoCCore):
    """VexRiscv + main RAM + UART + exit register on LiteX's simulation
    platform; `cfu` the path of the CFU's Verilog, or None."""

    def __init__(self, cfu=None, ram_bytes=512 * 1024, bursting=False):
        platform = SimPlatform("SIM", _io)
        self.crg = CRG(platform.request("sys_clk"), platform.request("sys_rst"))
        SoCCore.__init__(
            self, platform, clk_freq=int(1e6),
            ident="raymip LiteX SoC",
            cpu_type="vexriscv",
            cpu_variant="full+cfu" if cfu else "full",
            cpu_cfu=cfu,
            cpu_reset_address=MAIN_RAM,
            integrated_rom_size=0,
            integrated_sram_size=0,
            # The CFU SoC's main RAM is BankedRAM, added below.
            integrated_main_ram_size=0 if cfu else ram_bytes,
            uart_name="sim",
            with_timer=False,
            bus_bursting=bursting,
        )
        if cfu:
            # The CFU's logarithm pipeline, shared with the PicoRV32 unit.
            platform.add_source(os.path.join(os.path.dirname(cfu), "tex_log2pl.v"))
            self.main_ram = BankedRAM(ram_bytes, bursting)
            self.bus.add_slave("main_ram", self.main_ram.bus, SoCRegion(origin=MAIN_RAM, size=ram_bytes))
            self.add_cfu_ram_port(ram_bytes)
        self.sim_exit = SimExit(platform.request("sim_exit"))
        # An interrupt-free firmware and a UART without the host's side:
        # the sink (host → SoC) stays idle.
        serial = self.platform.lookup_request("serial")
        self.comb += [serial.sink_valid.eq(0), serial.sink_data.eq(0)]


    def add_cfu_ram_port(self, ram_bytes):
        """The texture unit's read port on the main RAM (cfu_tex.v's
        `mem_*` ports): the second port of each bank of BankedRAM, bank 0
        the even and bank 1 the odd words, `mem_hold` while the CPU's
        data bus has a write in flight (the unit's first read of a tex.sel
        waits for it) and `mem_wadr` its word address (a write into the
        block the unit caches drops that cache)."""
        words = ram_bytes // 4
        aw = words.bit_length() - 2  # words per bank 2^aw
        ports = self.main_ram.cfu_ports
        adr = [Signal(aw, name=f"cfu_mem_adr_{b}") for b in range(2)]
        for port, a in zip(ports, adr):
            self.comb += port.adr.eq(a)
        dbus = self.cpu.dbus
        hold = Signal(name="cfu_mem_hold")
        self.comb += hold.eq(dbus.cyc & dbus.we)
        self.cpu.cfu_params.update(
            p_HAS_RAM=1,
            p_RAM_BASE=MAIN_RAM,
            p_RAM_AW=aw,
            o_mem_adr_0=adr[0],
            o_mem_adr_1=adr[1],
            i_mem_dat_0=ports[0].dat_r,
            i_mem_dat_1=ports[1].dat_r,
            i_mem_hold=hold,
            i_mem_wadr=dbus.adr,
        )


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("--out", required=True, help="output directory")
    ap.add_argument("--cfu", help="Verilog of the CFU (module Cfu); without: the plain `full` variant")
    ap.add_argument("--ram-bytes", type=int, default=512 * 1024)
    ap.add_argument("--bursting", action="store_true",
                    help="LiteX's bus bursting: cache refills one word a cycle")
    a = ap.parse_args()
    out = os.path.abspath(a.out)
    cfu = os.path.abspath(a.cfu) if a.cfu else None
    soc = RaymipSoC(cfu=cfu, ram_bytes=a.ram_bytes, bursting=a.bursting)
    for name, page in CSR_LOCATIONS.items():
        soc.csr.locs[name] = page
    # LiteX's Builder would also generate the BIOS's software tree and
    # LiteX's own simulator files; only the Verilog and the CSR map are
    # needed here.
    os.makedirs(out, exist_ok=True)
    soc.platform.output_dir = out
    soc.finalize()
    with open(os.path.join(out, "csr.csv"), "w") as f:
        f.write(export.get_csr_csv(csr_regions=soc.csr_regions, constants=soc.constants,
                                   mem_regions=soc.mem_regions))
    # The memories' initial contents go to `$readmemh` files, which the
    # Verilog names relative to the working directory: write them into
    # --out and name them by absolute path, so that the model runs from any
    # directory.
    v = soc.platform.get_verilog(soc, name="sim")
    for name, content in v.data_files.items():
        with open(os.path.join(out, name), "w") as f:
            f.write(content)
    text = re.sub(r'\$readmemh\("([^"/]+)"', lambda m: f'$readmemh("{os.path.join(out, m.group(1))}"',
                  v.main_source)
    with open(os.path.join(out, "sim.v"), "w") as f:
        f.write(text)
    sources = [os.path.join(out, "sim.v")]
    sources += [os.path.abspath(f) for f, *_ in soc.platform.sources if f.endswith(".v")]
    with open(os.path.join(out, "sources.txt"), "w") as f:
        f.write("\n".join(sources) + "\n")
    # The main RAM's memory array, writable from the driver.
    # The main RAM's memory arrays (one, or BankedRAM's two), writable from
    # the driver, and how many there are (`main_ram.h`).
    arrays = ["main_ram_even", "main_ram_odd"] if cfu else ["main_ram"]
    with open(os.path.join(out, "public.vlt"), "w") as f:
        f.write("`verilator_config\n")
        for name in arrays:
            f.write(f"public_flat_rw -module \"sim\" -var \"{name}\"\n")
        # The CPU's buses, read by the driver's per-call profile.
        for bus in ("ibus", "dbus"):
            for sig in ("adr", "cyc", "stb", "we", "ack"):
                f.write(f"public_flat_rd -module \"sim\" -var \"{bus}_{sig}\"\n")
    with open(os.path.join(out, "main_ram.h"), "w") as f:
        f.write("// Written by demo/softcore/litex_soc.py: the main RAM's memory arrays.\n"
                f"#define RAYMIP_RAM_BANKS {len(arrays)}\n")
    with open(os.path.join(out, "sim.v")) as f:
        verilog = f.read()
    missing = [n for n in arrays if not re.search(rf"reg \[31:0\] {n}\[", verilog)]
    if missing:
        sys.exit(f"litex_soc.py: the generated Verilog lacks the main RAM arrays {missing}")
    # The firmware's constants against the generated map.
    regions = {}
    with open(os.path.join(out, "csr.csv")) as f:
        for row in csv.reader(f):
            if row and row[0] in ("csr_base", "memory_region"):
                regions[row[1]] = int(row[2], 0)
    want = {name: CSR_BASE + 0x800 * page for name, page in CSR_LOCATIONS.items()}
    want["main_ram"] = MAIN_RAM
    bad = {k: (hex(v), hex(regions.get(k, -1))) for k, v in want.items() if regions.get(k) != v}
    if bad:
        sys.exit(f"litex_soc.py: the generated map differs from the firmware's (want, got): {bad}")
    print(f"litex_soc.py: {sources[0]} + {', '.join(sources[1:])}")


if __name__ == "__main__":
    main()
