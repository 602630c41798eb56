// Verilator testbench of the texture co-processor cfu_tex.v (module Cfu)
// alone: drives its CFU port as VexRiscv's CfuPlugin does, serves its RAM
// read port from a RAM of its own (the two word banks, one read per bank
// and cycle, data the cycle after the address, as the LiteX SoC's block
// RAM) and checks every output bit against reference vectors written by
// the firmware's software paths (`raymip-demo pcpi-vectors FILE`,
// host-tests/src/cli/pcpi_vectors.rs; the same file tb_pcpi_tex.cpp reads).
//
// Usage: tb-cfu-tex VECTORS
// Each vector `OP RS1 RS2 RD` (hex), in file order (the filter and
// addressing instructions and the texture unit keep state from one to the
// next): OP is the function id {funct7, funct3}, or 400: RAM word RS1 :=
// RS2 (the RAM at the Cfu's default RAM_BASE, 2^(RAM_AW + 1) words). The
// command is presented with cmd_valid until cmd_ready (the transfer at the
// rising edge where both are high; within 32 cycles); the answer must come
// with rsp_valid within 32 cycles and equal RD in all 32 bits. mem_hold
// (a CPU write on the bus) is high two cycles in every seven, with an
// address outside the RAM: the unit's reads of a tex.sel wait for it to
// fall; every RAM word of the file is written as a CPU write (mem_hold and
// mem_wadr for a cycle), which drops the unit's block cache when it falls
// in the cached block. Every fifth answer is held off with rsp_ready low for a few
// cycles, during which rsp_valid and the data must stay and no command may
// be taken. After every vector a function id the unit does not define is
// sent: it must answer 0 and change no state (the next vector would
// differ). Prints `tb-cfu-tex: N vectors, 0 mismatches, latency ...` and
// exits 0, else lists the first mismatches and exits 1.
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <memory>
#include <vector>

#include "VCfu.h"
#include "tb_vectors.h"
#include "verilated.h"

namespace {

// Words per RAM bank 2^kRamAw: cfu_tex.v's default RAM_AW.
constexpr int kRamAw = 15;
// The pseudo-op of a RAM word.
constexpr unsigned kRamWord = 0x400;
// The RAM's word address on the CPU's bus (cfu_tex.v's default RAM_BASE
// 0x4000_0000 >> 2), and one outside it (the writes of the periodic
// mem_hold, which touch no block).
constexpr uint32_t kRamWordBase = 0x1000'0000;
constexpr uint32_t kOutside = 0;

struct Tb {
    std::unique_ptr<VerilatedContext> ctx = std::make_unique<VerilatedContext>();
    std::unique_ptr<VCfu> top = std::make_unique<VCfu>(ctx.get());
    uint64_t bad = 0;
    uint64_t cycle = 0;
    // The RAM: word 2·i + b is word i of bank b.
    std::vector<uint32_t> ram = std::vector<uint32_t>(size_t(2) << kRamAw);
    void tick() {
        const uint32_t a0 = top->mem_adr_0, a1 = top->mem_adr_1;
        top->clk = 1;
        top->eval();
        top->mem_dat_0 = ram[size_t(a0) << 1];
        top->mem_dat_1 = ram[(size_t(a1) << 1) | 1];
        top->mem_hold = ++cycle % 7 < 2;
        top->mem_wadr = kOutside;
        top->eval();
        top->clk = 0;
        top->eval();
    }
    // One cycle with a CPU write at word address `wadr` on the bus.
    void write(uint32_t wadr) {
        top->mem_hold = 1;
        top->mem_wadr = wadr;
        top->eval();
        tick();
    }
    void fail(const char* what, unsigned op, uint32_t rs1, uint32_t rs2, uint32_t got,
              uint32_t want) {
        if (++bad <= 10)
            std::fprintf(stderr, "mismatch: %s: op %03x rs1 %08x rs2 %08x: rd %08x (want %08x)\n",
                         what, op, rs1, rs2, got, want);
    }
    // One instruction through the handshake; returns the answer and its
    // latency (cycles from the transfer to rsp_valid), -1 on a time-out.
    uint32_t run(unsigned op, uint32_t rs1, uint32_t rs2, bool hold, int* lat) {
        auto& t = *top;
        t.cmd_payload_function_id = op;
        t.cmd_payload_inputs_0 = rs1;
        t.cmd_payload_inputs_1 = rs2;
        t.cmd_valid = 1;
        t.eval();
        int wait = 0;
        while (!t.cmd_ready && wait < 32) {
            tick();
            ++wait;
        }
        if (!t.cmd_ready) {
            *lat = -1;
            return 0;
        }
        tick();  // the transfer
        t.cmd_valid = 0;
        t.eval();
        int l = 1;
        while (!t.rsp_valid && l < 32) {
            tick();
            ++l;
        }
        *lat = t.rsp_valid ? l : -1;
        uint32_t got = t.rsp_payload_outputs_0;
        if (hold && t.rsp_valid) {
            t.rsp_ready = 0;
            t.cmd_valid = 1;  // a command offered meanwhile must wait
            t.cmd_payload_function_id = 0x3ff;
            t.eval();
            for (int k = 0; k < 3; ++k) {
                if (!t.rsp_valid || t.rsp_payload_outputs_0 != got || t.cmd_ready)
                    fail("answer not held while rsp_ready is low", op, rs1, rs2,
                         t.rsp_payload_outputs_0, got);
                tick();
            }
            t.cmd_valid = 0;
            t.rsp_ready = 1;
            t.eval();
        }
        tick();  // the answer is taken (rsp_ready high)
        return got;
    }
};

}  // namespace

int main(int argc, char** argv) {
    FILE* f = tb_shared::open_vectors(argc, argv, "tb-cfu-tex");
    Tb tb;
    auto& t = *tb.top;
    tb_shared::reset(tb, [&](bool on) {
        t.reset = on;
        t.cmd_valid = 0;
        t.rsp_ready = 1;
    });

    // Function ids: funct7 0: 0…5; funct7 1: 8…12 (tex.lvl, tex.addr, tex.tap ×3);
    // funct7 2: 16…19 (tex.ram, tex.sel, tex.tri, tex.bil).
    constexpr int kOps = 15;
    const unsigned ids[kOps] = {0, 1, 2, 3, 4, 5, 8, 9, 10, 11, 12, 16, 17, 18, 19};
    const char* names[kOps] = {"tex.log2pl", "tex.lod",   "tex.bw",    "tex.bt",    "tex.bb",
                               "tex.blend",  "tex.lvl",   "tex.addr",  "tex.tap10", "tex.tap01",
                               "tex.tap11",  "tex.ram",   "tex.sel",   "tex.tri",   "tex.bil"};
    int count[kOps] = {}, lat_max[kOps] = {};
    uint64_t n = 0;
    tb_shared::Vector v;
    while (tb_shared::read_vector(f, &v)) {
        const unsigned op = v.op;
        const uint32_t rs1 = v.rs1, rs2 = v.rs2, want = v.rd;
        if (op == kRamWord) {
            if (rs1 >= tb.ram.size()) {
                std::fprintf(stderr, "tb-cfu-tex: RAM word %" PRIx32 " outside the RAM\n", rs1);
                return 2;
            }
            tb.ram[rs1] = rs2;
            // The write on the CPU's bus, as the unit's snoop sees it.
            tb.write(kRamWordBase + rs1);
            continue;
        }
        int k = -1;
        for (int i = 0; i < kOps; ++i)
            if (ids[i] == op) k = i;
        if (k < 0) {
            std::fprintf(stderr, "tb-cfu-tex: unknown op %x in %s\n", op, argv[1]);
            return 2;
        }
        ++n;
        ++count[k];
        int lat;
        uint32_t got = tb.run(op, rs1, rs2, n % 5 == 0, &lat);
        if (lat < 0 || got != want) tb.fail(names[k], op, rs1, rs2, got, want);
        if (lat > lat_max[k]) lat_max[k] = lat;
        // An undefined function id: answers 0, changes nothing.
        const unsigned other[] = {6, 7, 13, 14, 15, 20, 0x3ff};
        unsigned o = other[n % 7];
        got = tb.run(o, 0xffffffffu, 0xffffffffu, false, &lat);
        if (lat != 1 || got != 0) tb.fail("undefined function id", o, ~0u, ~0u, got, 0);
    }
    std::fclose(f);
    t.final();
    for (int k = 0; k < kOps; ++k) {
        if (count[k] == 0) {
            std::fprintf(stderr, "tb-cfu-tex: %s has no vectors of %s\n", argv[1], names[k]);
            return 1;
        }
    }
    std::printf("tb-cfu-tex: %" PRIu64 " vectors (", n);
    for (int k = 0; k < kOps; ++k) std::printf("%s%d %s", k ? ", " : "", count[k], names[k]);
    std::printf("), %" PRIu64 " mismatches, latency", tb.bad);
    for (int k = 0; k < kOps; ++k) std::printf(" %d", lat_max[k]);
    std::printf(" cycles\n");
    return tb.bad == 0 ? 0 : 1;
}
