// What the co-processor testbenches tb_pcpi_tex.cpp and tb_cfu_tex.cpp
// share: the reference vector file (`raymip-demo pcpi-vectors FILE`,
// host-tests/src/cli/pcpi_vectors.rs), one vector `OP RS1 RS2 RD` (hex) a
// line, and the reset of the unit under test.
#pragma once

#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

namespace tb_shared {

// One vector: the instruction (or pseudo-op) OP on RS1 and RS2 must answer RD.
struct Vector {
    unsigned op;
    uint32_t rs1, rs2, rd;
};

// The vector file named by a testbench's one argument; on any other
// command line, or a file that does not open, it says why and exits 2.
// `name`: the testbench's command.
inline FILE* open_vectors(int argc, char** argv, const char* name) {
    if (argc != 2) {
        std::fprintf(stderr, "usage: %s VECTORS\n", name);
        std::exit(2);
    }
    FILE* f = std::fopen(argv[1], "r");
    if (!f) {
        std::perror(argv[1]);
        std::exit(2);
    }
    return f;
}

// Reads the next vector of `f` into `v`; false at the end of the file.
inline bool read_vector(FILE* f, Vector* v) {
    return std::fscanf(f, "%x %" SCNx32 " %" SCNx32 " %" SCNx32, &v->op, &v->rs1, &v->rs2, &v->rd) == 4;
}

// Holds the unit of testbench `b` in reset for four clock cycles, then
// runs one cycle out of it; `set_reset(true)` asserts the unit's reset
// input (whatever its polarity) and sets its other inputs idle,
// `set_reset(false)` releases the reset.
template <class Bench, class SetReset>
void reset(Bench& b, SetReset set_reset) {
    b.top->clk = 0;
    set_reset(true);
    for (int i = 0; i < 4; ++i) b.tick();
    set_reset(false);
    b.tick();
}

}  // namespace tb_shared
