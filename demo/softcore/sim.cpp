// Verilator driver of the raymip soft-core SoC (soc.v): loads a firmware
// ELF into the SoC's RAM, runs the PicoRV32 core until the firmware writes
// the exit register, copies console bytes to stdout, and exits with the
// firmware's exit code.
//
// Usage: soc-sim FIRMWARE.elf [MAX_CYCLES]
// Exit status: the firmware's exit code; 2 usage or ELF errors; 3 the core
// trapped (illegal instruction, misaligned access, ebreak); 4 bus fault
// (access outside RAM and the two registers); 124 MAX_CYCLES reached
// (default 2e9). A summary line goes to stderr.
#include <cstdint>
#include <cstdio>
#include <memory>

#include "Vsoc.h"
#include "Vsoc___024root.h"
#include "Vsoc_soc.h"
#include "sim_driver.h"
#include "verilated.h"

namespace {

constexpr uint32_t kRamBytes = sizeof(Vsoc_soc::ram);

}  // namespace

int main(int argc, char** argv) {
    sim::Args args;
    if (!sim::parse(argc, argv, "soc-sim", args)) return 2;
    auto ctx = std::make_unique<VerilatedContext>();
    auto top = std::make_unique<Vsoc>(ctx.get());

    const auto words = sim::ram_words(args.elf, kRamBytes, 0);
    if (words.empty()) return 2;
    auto& ram = top->rootp->soc->ram;
    for (uint32_t w = 0; w < kRamBytes / 4; ++w) ram[w] = words[w];

    top->clk = 0;
    top->resetn = 0;
    uint64_t cycle = 0;
    int status = sim::kTimeout;
    for (; cycle < args.max_cycles; ++cycle) {
        if (cycle == 8) top->resetn = 1;
        top->clk = 1;
        top->eval();
        top->clk = 0;
        top->eval();
        if (top->con_valid) std::putchar(top->con_byte);
        if (top->exit_valid) {
            status = int(top->exit_code & 0xff);
            break;
        }
        if (top->trap) {
            std::fprintf(stderr, "soc-sim: the core trapped (illegal instruction, misaligned "
                                 "access or ebreak)\n");
            status = 3;
            break;
        }
        if (top->fault) {
            std::fprintf(stderr, "soc-sim: bus fault at address %#010x\n", top->fault_addr);
            status = 4;
            break;
        }
    }
    top->final();
    return sim::summary("soc-sim", status, cycle, args, kRamBytes);
}
