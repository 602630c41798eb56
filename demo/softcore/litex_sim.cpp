// Verilator driver of the raymip LiteX SoC (litex_soc.py: VexRiscv, main
// RAM, LiteX's simulation UART, the exit register): loads a firmware ELF
// into the main RAM, runs the SoC from reset until the firmware writes the
// exit register, copies the UART's bytes to stdout, and exits with the
// firmware's exit code. One model serves every firmware image.
//
// Usage: litex-sim FIRMWARE.elf [MAX_CYCLES]
// With LITEX_SIM_PROFILE=FILE and LITEX_SIM_PROFILE_ROOT=ADDR in the
// environment: the cycle profile of every call of the function at ADDR
// (from the retirement of its first instruction to that of the
// instruction at its return address, callees included) into FILE: a line
// `calls N` (the calls), then one line `pc retired cycles` (hex pc,
// decimal counts) per instruction address that retired inside those
// calls. Every cycle is charged to the next instruction that leaves
// VexRiscv's last stage (the cycle it leaves and the cycles since the one
// before), so a stall shows on the instruction that waited: a data-cache
// miss on its load, a co-processor's latency on its custom instruction,
// an instruction-cache refill or a taken branch's bubbles on the
// instruction after them.
// With LITEX_SIM_PROFILE_CALLS=FILE as well: every call of the root
// function one by one into FILE, in the order of the run: a line
// `i pc cycles` per retired instruction (the cycles charged to it, as
// above), `d r|w addr` per data-bus and `f addr` per instruction-bus
// beat the SoC acknowledged (byte addresses; a cache refill is eight
// beats of one 32-byte line), then `call N cycles C` (C the call's
// cycles): one slow call among fast ones (one input of a series) shows
// which instruction waited and on which line.
// Exit status: the firmware's exit code (3 when it trapped: its trap
// handler prints the cause); 2 usage or ELF errors; 124 MAX_CYCLES reached
// (default 2e9). A summary line goes to stderr.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <map>
#include <memory>
#include <utility>

#include "Vsim.h"
#include "Vsim___024root.h"
#include "Vsim_VexRiscv.h"
#include "Vsim_sim.h"
#include "main_ram.h"
#include "sim_driver.h"
#include "verilated.h"

namespace {

// LiteX's `main_ram` region (litex_soc.py MAIN_RAM).
constexpr uint32_t kRamBase = 0x4000'0000;
// The main RAM's arrays (main_ram.h, written by litex_soc.py beside the
// model's Verilog): LiteX's SRAM `main_ram`, or the CFU SoC's BankedRAM,
// words 2i in `main_ram_even`[i] and 2i + 1 in `main_ram_odd`[i].
#if RAYMIP_RAM_BANKS == 2
constexpr uint32_t kRamBytes = 2 * sizeof(Vsim_sim::main_ram_even);
#else
constexpr uint32_t kRamBytes = sizeof(Vsim_sim::main_ram);
#endif

}  // namespace

int main(int argc, char** argv) {
    sim::Args args;
    if (!sim::parse(argc, argv, "litex-sim", args)) return 2;
    // Line by line, so that a log shows how far a run got.
    std::setvbuf(stdout, nullptr, _IOLBF, 0);
    auto ctx = std::make_unique<VerilatedContext>();
    auto top = std::make_unique<Vsim>(ctx.get());

    const auto words = sim::ram_words(args.elf, kRamBytes, kRamBase);
    if (words.empty()) return 2;
#if RAYMIP_RAM_BANKS == 2
    auto& even = top->rootp->sim->main_ram_even;
    auto& odd = top->rootp->sim->main_ram_odd;
    for (uint32_t w = 0; w < kRamBytes / 4; ++w) (w % 2 ? odd : even)[w / 2] = words[w];
#else
    auto& ram = top->rootp->sim->main_ram;
    for (uint32_t w = 0; w < kRamBytes / 4; ++w) ram[w] = words[w];
#endif

    top->sys_clk = 0;
    top->sys_rst = 1;
    top->sim_trace = 0;
    top->serial_source_ready = 1;
    uint64_t cycle = 0;
    int status = sim::kTimeout;
    // The profile: pc -> (retired, cycles) inside the calls of `root`;
    // `idle` the cycles since the last instruction left the last stage,
    // `ret` the return address of the call in progress (`inside`).
    const char* profile = std::getenv("LITEX_SIM_PROFILE");
    const char* root_env = std::getenv("LITEX_SIM_PROFILE_ROOT");
    if (profile && !root_env) {
        std::fprintf(stderr, "litex-sim: LITEX_SIM_PROFILE needs LITEX_SIM_PROFILE_ROOT\n");
        return 2;
    }
    const uint32_t root = root_env ? uint32_t(std::strtoul(root_env, nullptr, 0)) : 0;
    // LITEX_SIM_PROFILE_END=ADDR: a call ends when the instruction at ADDR
    // retires instead of at the return address (a window of straight-line
    // code, e.g. from one counter read to the next around a timed call).
    const char* end_env = std::getenv("LITEX_SIM_PROFILE_END");
    const uint32_t end = end_env ? uint32_t(std::strtoul(end_env, nullptr, 0)) : 0;
    std::map<uint32_t, std::pair<uint64_t, uint64_t>> prof;
    const char* per_call = std::getenv("LITEX_SIM_PROFILE_CALLS");
    FILE* pc_file = nullptr;
    if (per_call && profile) {
        pc_file = std::fopen(per_call, "w");
        if (!pc_file) {
            std::perror(per_call);
            return 2;
        }
    }
    uint64_t call_cycles = 0;
    const auto* soc = top->rootp->sim;
    uint64_t idle = 0, calls = 0;
    uint32_t ret = 0;
    bool inside = false;
    const auto* cpu = top->rootp->sim->VexRiscv;
    for (; cycle < args.max_cycles; ++cycle) {
        if (profile && cycle >= 8) {
            ++idle;
            if (cpu->lastStageIsFiring) {
                const uint32_t pc = cpu->lastStagePc;
                if (!inside && pc == root) {
                    // The call's return address: `ra` as the call left it.
                    inside = true;
                    ret = end_env ? end : cpu->RegFilePlugin_regFile[1];
                    ++calls;
                    call_cycles = 0;
                } else if (inside && pc == ret) {
                    inside = false;
                    if (pc_file)
                        std::fprintf(pc_file, "call %llu cycles %llu\n", (unsigned long long)calls - 1,
                                     (unsigned long long)call_cycles);
                }
                if (inside) {
                    auto& e = prof[pc];
                    e.first += 1;
                    e.second += idle;
                    call_cycles += idle;
                    if (pc_file) std::fprintf(pc_file, "i %08x %llu\n", pc, (unsigned long long)idle);
                }
                idle = 0;
            }
            // The beats acknowledged in this cycle (sampled before the edge).
            if (pc_file && inside) {
                if (soc->dbus_cyc && soc->dbus_stb && soc->dbus_ack)
                    std::fprintf(pc_file, "d %c %08x\n", soc->dbus_we ? 'w' : 'r', soc->dbus_adr << 2);
                if (soc->ibus_cyc && soc->ibus_stb && soc->ibus_ack)
                    std::fprintf(pc_file, "f %08x\n", soc->ibus_adr << 2);
            }
        }
        if (cycle == 8) top->sys_rst = 0;
        // The UART's stream: a byte is taken at the rising edge where
        // valid and ready are both high (ready always is).
        const bool byte = top->serial_source_valid;
        const uint8_t data = top->serial_source_data;
        top->sys_clk = 1;
        top->eval();
        top->sys_clk = 0;
        top->eval();
        if (byte) std::putchar(data);
        if (top->sim_exit_valid) {
            status = int(top->sim_exit_code & 0xff);
            break;
        }
    }
    // Bytes the firmware queued in the UART before exiting (they reach the
    // stream a few cycles after the CSR write; the FIFO holds at most 16).
    for (int i = 0; status != sim::kTimeout && i < 256; ++i) {
        if (top->serial_source_valid) std::putchar(top->serial_source_data);
        top->sys_clk = 1;
        top->eval();
        top->sys_clk = 0;
        top->eval();
    }
    top->final();
    if (pc_file) std::fclose(pc_file);
    if (profile) {
        FILE* f = std::fopen(profile, "w");
        if (!f) {
            std::perror(profile);
            return 2;
        }
        std::fprintf(f, "calls %llu\n", (unsigned long long)calls);
        for (const auto& [pc, e] : prof)
            std::fprintf(f, "%08x %llu %llu\n", pc, (unsigned long long)e.first,
                         (unsigned long long)e.second);
        std::fclose(f);
    }
    return sim::summary("litex-sim", status, cycle, args, kRamBytes);
}
