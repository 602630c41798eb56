// ELF loading of the soft-core simulation drivers (sim.cpp for the PicoRV32
// SoC, litex_sim.cpp for the LiteX SoC): one home for reading a firmware
// image into a RAM image.
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

namespace elf {

inline uint32_t rd32(const std::vector<uint8_t>& f, size_t o) {
    return uint32_t(f[o]) | uint32_t(f[o + 1]) << 8 | uint32_t(f[o + 2]) << 16 |
           uint32_t(f[o + 3]) << 24;
}
inline uint16_t rd16(const std::vector<uint8_t>& f, size_t o) {
    return uint16_t(f[o] | f[o + 1] << 8);
}

// Copies the PT_LOAD segments of a little-endian ELF32 RISC-V image into
// `ram` (bytes; the RAM starts at address `base`; zero-filled beyond the
// file size). Returns false with a message on anything unexpected.
inline bool load(const char* path, std::vector<uint8_t>& ram, uint32_t base) {
    std::ifstream in(path, std::ios::binary);
    std::vector<uint8_t> f((std::istreambuf_iterator<char>(in)), {});
    if (f.size() < 52 || std::memcmp(f.data(), "\x7f" "ELF", 4) != 0 || f[4] != 1 || f[5] != 1 ||
        rd16(f, 18) != 243) {
        std::fprintf(stderr, "%s is not a little-endian ELF32 RISC-V image\n", path);
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
        if (paddr < base || uint64_t(paddr - base) + memsz > ram.size() ||
            uint64_t(off) + filesz > f.size()) {
            std::fprintf(stderr,
                         "segment at %#x, %u bytes, does not fit the %zu-byte RAM at %#x\n",
                         paddr, memsz, ram.size(), base);
            return false;
        }
        std::memcpy(&ram[paddr - base], &f[off], filesz);
    }
    return true;
}

}  // namespace elf
