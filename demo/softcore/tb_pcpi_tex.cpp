// Verilator testbench of the texture co-processor pcpi_tex.v alone (issue
// 23): drives its PCPI port as PicoRV32 does and checks every output bit
// against reference vectors written by the firmware's software paths
// (`raymip-demo pcpi-vectors FILE`, host-tests/src/cli/pcpi_vectors.rs).
//
// Usage: tb-pcpi-tex VECTORS
// Each vector `OP RS1 RS2 RD` (hex), in file order (the filter
// instructions, OP 2…5, keep state from one to the next) up to the first
// with OP ≥ 8 (the CFU unit's addressing section, which this unit does not
// implement, comes last): the instruction
// tex.* with funct3 OP is presented with pcpi_valid held high (pcpi_insn, pcpi_rs1, pcpi_rs2
// stable) until pcpi_ready; then pcpi_wr must be 1 and pcpi_rd equal RD in
// all 32 bits, pcpi_ready must have come within 16 cycles (PicoRV32's PCPI
// time-out) with pcpi_wait high until then, and valid drops the next cycle
// as the core drops it. Unclaimed encodings (other funct3, funct7 or
// opcode) must never raise pcpi_ready, pcpi_wr or pcpi_wait.
// Prints `tb-pcpi-tex: N vectors, 0 mismatches` and exits 0, else lists
// the first mismatches and exits 1.
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <memory>

#include "Vpcpi_tex.h"
#include "tb_vectors.h"
#include "verilated.h"

namespace {

uint32_t insn(uint32_t funct3, uint32_t funct7, uint32_t opcode) {
    // rd = x10, rs1 = x11, rs2 = x12 (the co-processor ignores the numbers).
    return funct7 << 25 | 12u << 20 | 11u << 15 | funct3 << 12 | 10u << 7 | opcode;
}

struct Tb {
    std::unique_ptr<VerilatedContext> ctx = std::make_unique<VerilatedContext>();
    std::unique_ptr<Vpcpi_tex> top = std::make_unique<Vpcpi_tex>(ctx.get());
    void tick() {
        top->clk = 1;
        top->eval();
        top->clk = 0;
        top->eval();
    }
};

}  // namespace

int main(int argc, char** argv) {
    FILE* f = tb_shared::open_vectors(argc, argv, "tb-pcpi-tex");
    Tb tb;
    auto& t = *tb.top;
    tb_shared::reset(tb, [&](bool on) {
        t.resetn = !on;
        t.pcpi_valid = 0;
    });

    uint64_t n = 0, bad = 0, max_lat = 0;
    int lat_op[6] = {0, 0, 0, 0, 0, 0};  // the longest latency of each instruction
    int ops[6] = {0, 0, 0, 0, 0, 0};
    tb_shared::Vector v;
    while (tb_shared::read_vector(f, &v)) {
        const unsigned op = v.op;
        const uint32_t rs1 = v.rs1, rs2 = v.rs2, want = v.rd;
        if (op >= 8) break;
        ++n;
        if (op < 6) ++ops[op];
        t.pcpi_insn = insn(op, 0, 0x0b);
        t.pcpi_rs1 = rs1;
        t.pcpi_rs2 = rs2;
        t.pcpi_valid = 1;
        t.eval();
        int lat = 0;
        bool ok = true;
        while (!t.pcpi_ready && lat < 16) {
            if (!t.pcpi_wait) ok = false;  // must hold wait while busy
            tb.tick();
            ++lat;
        }
        uint32_t got = t.pcpi_rd;
        if (!t.pcpi_ready || !t.pcpi_wr || got != want || !ok) {
            if (++bad <= 10)
                std::fprintf(stderr,
                             "mismatch: op %u rs1 %08x rs2 %08x: rd %08x (want %08x) ready %d "
                             "wr %d after %d cycles, wait held %d\n",
                             op, rs1, rs2, got, want, int(t.pcpi_ready), int(t.pcpi_wr), lat,
                             int(ok));
        }
        if (op < 2 && uint64_t(lat) > max_lat) max_lat = lat;
        if (op < 6 && lat > lat_op[op]) lat_op[op] = lat;
        // The core takes the result at this edge and drops valid after it.
        tb.tick();
        t.pcpi_valid = 0;
        t.eval();
        if (t.pcpi_ready) {
            if (++bad <= 10) std::fprintf(stderr, "ready held longer than one cycle\n");
        }
        tb.tick();
    }
    std::fclose(f);

    // Encodings the co-processor must leave alone.
    const uint32_t other[] = {insn(6, 0, 0x0b), insn(7, 0, 0x0b), insn(0, 1, 0x0b),
                              insn(1, 0x40, 0x0b), insn(4, 1, 0x0b), insn(0, 0, 0x2b),
                              insn(0, 1, 0x33)};
    for (uint32_t w : other) {
        t.pcpi_insn = w;
        t.pcpi_rs1 = 0x1234;
        t.pcpi_rs2 = 0x5678;
        t.pcpi_valid = 1;
        for (int c = 0; c < 20; ++c) {
            t.eval();
            if (t.pcpi_ready || t.pcpi_wr || t.pcpi_wait) {
                if (++bad <= 10) std::fprintf(stderr, "encoding %08x claimed\n", w);
                break;
            }
            tb.tick();
        }
        t.pcpi_valid = 0;
        tb.tick();
        tb.tick();
    }
    t.final();
    for (int k = 0; k < 6; ++k) {
        if (ops[k] == 0) {
            std::fprintf(stderr, "tb-pcpi-tex: %s has no vectors of instruction %d\n", argv[1], k);
            return 1;
        }
    }
    std::printf("tb-pcpi-tex: %" PRIu64 " vectors (%d tex.log2pl, %d tex.lod), %" PRIu64
                " mismatches, latency %" PRIu64 " cycles after valid; filter %d tex.bw, %d tex.bt, "
                "%d tex.bb, %d tex.blend, latency %d %d %d %d cycles\n",
                n, ops[0], ops[1], bad, max_lat, ops[2], ops[3], ops[4], ops[5], lat_op[2],
                lat_op[3], lat_op[4], lat_op[5]);
    return bad == 0 ? 0 : 1;
}
