// The frame both soft-core simulation drivers share (sim.cpp for the
// PicoRV32 SoC, litex_sim.cpp for the LiteX SoC): the command line
// `NAME FIRMWARE.elf [MAX_CYCLES]`, the firmware image in a RAM image, and
// the summary at the end of a run.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include "elf_load.h"

namespace sim {

// Exit status of a run that reached its cycle limit.
constexpr int kTimeout = 124;

struct Args {
    const char* elf;
    // Default 2e9.
    uint64_t max_cycles;
};

// The command line of driver `name`; false (after printing the usage)
// when the firmware is missing.
inline bool parse(int argc, char** argv, const char* name, Args& a) {
    if (argc < 2) {
        std::fprintf(stderr, "usage: %s FIRMWARE.elf [MAX_CYCLES]\n", name);
        return false;
    }
    a.elf = argv[1];
    a.max_cycles = argc > 2 ? std::strtoull(argv[2], nullptr, 0) : 2000000000ull;
    return true;
}

// The firmware `path` as the contents of a `ram_bytes`-byte RAM at
// address `base`, one little-endian word per element; empty on an ELF
// error (printed).
inline std::vector<uint32_t> ram_words(const char* path, uint32_t ram_bytes, uint32_t base) {
    std::vector<uint8_t> image(ram_bytes, 0);
    if (!elf::load(path, image, base)) return {};
    std::vector<uint32_t> words(ram_bytes / 4);
    for (uint32_t w = 0; w < ram_bytes / 4; ++w) words[w] = elf::rd32(image, size_t(w) * 4);
    return words;
}

// Flushes the console and prints driver `name`'s summary line (and the
// timeout's) to stderr; returns `status`.
inline int summary(const char* name, int status, uint64_t cycle, const Args& a,
                   uint32_t ram_bytes) {
    std::fflush(stdout);
    if (status == kTimeout)
        std::fprintf(stderr, "%s: no exit within %llu cycles\n", name,
                     (unsigned long long)a.max_cycles);
    std::fprintf(stderr, "%s: exit code %d after %llu cycles (RAM %u KiB)\n", name, status,
                 (unsigned long long)cycle, ram_bytes / 1024);
    return status;
}

}  // namespace sim
