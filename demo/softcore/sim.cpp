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
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <memory>
#include <vector>

#include "Vsoc.h"
#include "Vsoc___024root.h"
#include "Vsoc_soc.h"
#include "verilated.h"

namespace {

constexpr uint32_t kRamBytes = sizeof(Vsoc_soc::ram);

uint32_t rd32(const std::vector<uint8_t>& f, size_t o) {
    return uint32_t(f[o]) | uint32_t(f[o + 1]) << 8 | uint32_t(f[o + 2]) << 16 |
           uint32_t(f[o + 3]) << 24;
}
uint16_t rd16(const std::vector<uint8_t>& f, size_t o) {
    return uint16_t(f[o] | f[o + 1] << 8);
}

// Copies the PT_LOAD segments of a little-endian ELF32 RISC-V image into
// `ram` (bytes, zero-filled beyond the file size). Returns false with a
// message on anything unexpected.
bool load_elf(const char* path, std::vector<uint8_t>& ram) {
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> f((std::istreambuf_iterator<char>(in)), {});
    if (f.size() < 52 || std::memcmp(f.data(), "\x7f" "ELF", 4) != 0 || f[4] != 1 || f[5] != 1 ||
        rd16(f, 18) != 243) {
        std::fprintf(stderr, "soc-sim: %s is not a little-endian ELF32 RISC-V image\n", path);
        return false;
    }
    uint32_t phoff = rd32(f, 28);
    uint16_t phentsize = rd16(f, 42), phnum = rd16(f, 44);
    for (uint16_t i = 0; i < phnum; ++i) {
        size_t ph = phoff + size_t(i) * phentsize;
        if (ph + 32 > f.size()) return false;
        if (rd32(f, ph) != 1) continue;  // PT_LOAD only
        uint32_t off = rd32(f, ph + 4), paddr = rd32(f, ph + 12);
        uint32_t filesz = rd32(f, ph + 16), memsz = rd32(f, ph + 20);
        if (memsz == 0) continue;
        if (uint64_t(paddr) + memsz > ram.size() || uint64_t(off) + filesz > f.size()) {
            std::fprintf(stderr,
                         "soc-sim: segment at %#x, %u bytes, does not fit the %zu-byte RAM\n",
                         paddr, memsz, ram.size());
            return false;
        }
        std::memcpy(&ram[paddr], &f[off], filesz);
    }
    return true;
}

}  // namespace

int main(int argc, char** argv) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: soc-sim FIRMWARE.elf [MAX_CYCLES]\n");
        return 2;
    }
    const uint64_t max_cycles = argc > 2 ? std::strtoull(argv[2], nullptr, 0) : 2000000000ull;
    auto ctx = std::make_unique<VerilatedContext>();
    auto top = std::make_unique<Vsoc>(ctx.get());

    std::vector<uint8_t> image(kRamBytes, 0);
    if (!load_elf(argv[1], image)) return 2;
    auto& ram = top->rootp->soc->ram;
    for (uint32_t w = 0; w < kRamBytes / 4; ++w) ram[w] = rd32(image, size_t(w) * 4);

    top->clk = 0;
    top->resetn = 0;
    uint64_t cycle = 0;
    int status = 124;
    for (; cycle < max_cycles; ++cycle) {
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
    std::fflush(stdout);
    if (status == 124) std::fprintf(stderr, "soc-sim: no exit within %llu cycles\n",
                                    (unsigned long long)max_cycles);
    std::fprintf(stderr, "soc-sim: exit code %d after %llu cycles (RAM %u KiB)\n", status,
                 (unsigned long long)cycle, kRamBytes / 1024);
    top->final();
    return status;
}
