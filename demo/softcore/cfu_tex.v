// raymip texture co-processor for VexRiscv's CFU port (the Custom Function
// Unit interface of CFU-Playground; LiteX's `full+cfu` VexRiscv variant
// instantiates a module `Cfu` with the CFU ports), with a read port of its
// own on the SoC's RAM (litex_soc.py connects it). Our own RTL.
//
// The CPU sends an R-type instruction of the custom-0 opcode as
// function_id = {funct7, funct3} with the two source registers; the same
// instruction words as the PCPI unit (pcpi_tex.v, whose header specifies
// funct7 = 0), plus the addressing instructions (funct7 = 1) and the
// texture unit (funct7 = 2):
//
//   funct7 0: funct3 0 tex.log2pl, 1 tex.lod, 2 tex.bw, 3 tex.bt, 4 tex.bb,
//             5 tex.blend — bit for bit as pcpi_tex.v.
//
//   funct7 1, funct3 0  tex.lvl rd, rs1, rs2
//             Latches the level that tex.addr addresses: rs1 = the byte
//             address of its texel (0, 0) (RGBA8, row-major), rs2 =
//             kx[3:0] | ky[3:0] << 4 | mode_u[1:0] << 8 | mode_v[1:0] << 10:
//             the level is 2^kx × 2^ky texels (kx, ky ≤ 15), the address
//             mode per axis 0 wrap, 1 mirror, 2 clamp to edge, 3 mirror
//             once (the firmware's AddressMode numbers; border colour is
//             not handled here). rd = 0.
//   funct7 1, funct3 1  tex.addr rd, rs1, rs2
//             rs1 = u, rs2 = v: on a wrapped axis the coordinate's 32
//             fractional bits (the unit uses the top 28), else I4F28 (the
//             coordinate's 28 top fractional bits; the integer part:
//             `hi mod 2` for mirror, clamped to [−4, 3] for the clamping
//             modes, as the firmware's `AddressMode::scaled` reduces it).
//             Per axis with n = 2^k: x = (frac·n << 4) + 2¹⁹ − 2³¹ (the
//             firmware's `taps` for 12 weight bits in 2⁻³² texel units:
//             the weight rounded to nearest), i = x >> 32 + int·n, weight
//             f = x[31:20], i0 = map(i), i1 = map(i + 1) with the mode's
//             map for a power of two (wrap i mod n; mirror m = i mod 2n,
//             m mod n flipped when m ≥ n; clamp to [0, n − 1]; mirror once
//             (i < 0 ? −1 − i : i) clamped). Latches (fx, fy) as tex.bw does
//             and the four texel addresses base + 4·(y·2^kx + x);
//             rd = the address of t00 = (x0, y0).
//   funct7 1, funct3 2, 3, 4  tex.tap rd
//             rd = the address of t10 = (x1, y0), t01 = (x0, y1),
//             t11 = (x1, y1) of the last tex.addr.
//
//   The texture unit: a trilinear or bilinear sample fetched from the RAM
//   and filtered here, as the firmware's sampler computes it for a
//   power-of-two pyramid with the ACCURATE linear kernel (RGBA8).
//   funct7 2, funct3 0  tex.ram rd
//             rd = RAM_BASE | log2(RAM bytes): the RAM the unit reads (its
//             base is aligned to its size); 0 without a RAM (HAS_RAM = 0).
//   funct7 2, funct3 1  tex.sel rd, rs1, rs2
//             rs1 = the byte address of a sampler's descriptor block (19
//             words, src/texture/coproc.rs writes them):
//               word 0: the lod bias (I8F8 bits, sign-extended),
//               word 1: lo[11:0] | hi[23:12] | mode_u[25:24] | mode_v[27:26]
//                       | valid[28] (the lod window, I8F8 bits in
//                       [0, 3840]; modes as tex.lvl's; valid set in every
//                       block the firmware makes, clear in its empty one),
//               word 2 + l, l = 0 … 16: level l: the word offset of its
//                       texel (0, 0) from RAM_BASE [23:0] | kx[27:24] |
//                       ky[31:28];
//             rs2 = a lod (I8F8 bits, sign-extended). rd = 1 when the
//             block lies in the RAM (word-aligned) and word 1's valid bit
//             is set, else 0 (and nothing is selected; always 0 with
//             HAS_RAM = 0). The unit keeps the last block it read in a
//             cache of its own (its 19 words), which any CPU write into
//             the block's words drops (mem_wadr, below); it answers from
//             the cache, or once it has read the whole block into it;
//             then, in the background, it computes
//             bits = min(max(lod + bias, lo), hi) and takes the
//             descriptors of levels bits >> 8 and bits >> 8 + 1 from the
//             cache.
//   funct7 2, funct3 2  tex.tri rd, rs1, rs2
//             rs1 = u, rs2 = v as for tex.addr. rd = the trilinear sample:
//             levels bits >> 8 and bits >> 8 + 1, each addressed as
//             tex.addr, its four texels read from the RAM and filtered as
//             tex.bt/tex.bb, blended as tex.blend with t = bits & 255; the
//             rounded lower level when t = 0 (the same value; the upper
//             level is not read).
//   funct7 2, funct3 3  tex.bil rd, rs1, rs2
//             As tex.tri for the nearest level, (bits + 128) >> 8: the
//             rounded bilinear sample.
//
// Any other function id answers 0 and changes nothing (the CFU port has
// no way to refuse an instruction).
//
// The RAM port: two word banks, bank 0 the even and bank 1 the odd words
// of the RAM at RAM_BASE (2^(RAM_AW+1) words), one read per bank and cycle
// (mem_adr_b presented in cycle t, mem_dat_b read in t + 1), so the two
// texels of a footprint row (x0 and x1 = x0 ± 1 have different parities,
// or are the same texel) come in one cycle. mem_hold: the CPU has a write
// on its data bus (the store buffer of VexRiscv's write-through data cache
// drains after the store retires), mem_wadr its word address; tex.sel
// waits for mem_hold to end before it answers from the cache or reads the
// block, so it uses what the CPU wrote before it: a write into the cached
// block's words drops the cache in the cycle it is on the bus. Between
// tex.sel and its tex.tri/tex.bil the firmware writes neither the block
// nor texels.
//
// Timing: every instruction is taken in the cycle cmd_valid && cmd_ready.
// Pipelined for the clock (at most one multiply, one add or one index map
// per stage): tex.lod, tex.bt, tex.lvl, tex.tap, tex.ram and a tex.sel
// of a block outside the RAM answer one cycle later (rsp_valid
// registered; tex.bt goes on in the background), tex.sel of a cached block
// two (plus the cycles mem_hold delays it; the lod's window and the
// levels' words take two more cycles in the background), ten more when it
// reads the block first; tex.bw and tex.addr five (A1 the shifted
// coordinates, A2 the scaled positions and weights, B1 the index maps, B2
// the addresses and corner weights, then the answer), tex.log2pl five
// (tex_log2pl.v with PIPE = 1), tex.blend three (the two level products,
// their sum), tex.bb five (the row's corner products, their sum, the
// level's sum, the rounding). The texture unit fetches a level's two
// rows in consecutive cycles and answers tex.tri 15 cycles after the
// command (11 with t = 0), tex.bil 11 (as tb_cfu_tex.cpp counts: the cycle
// of the transfer is 1).
// The filter runs the four channels in parallel as the corner sum of
// src/texture/kernel/accurate.rs: X = Σ t_ij·W_ij with
// W = [(4096 − fx)(4096 − fy), fx(4096 − fy), (4096 − fx)fy, fx·fy]
// (the same integer as pcpi_tex.v's nested rows), then (X + 2⁷) >> 8 kept
// as the level's 8.16 value and (X + 2⁷ + 2²³) >> 24 the rounded texel;
// the blend (w0·(256 − t) + 2²³) + w1·t >> 24.
// Every output bit is checked against vectors written by the Rust firmware
// code (tb_cfu_tex.cpp, scripts/softcore).
`timescale 1 ns / 1 ps
`default_nettype none

/* verilator lint_off DECLFILENAME */  // LiteX instantiates the CFU as `Cfu`
module Cfu #(
    // 1: the mem_* ports are connected to the RAM at RAM_BASE; 0 (a CFU
    // instantiated without them): the texture unit has no RAM, tex.ram
    // answers 0 and tex.sel 0 (the firmware then samples without it).
    parameter integer HAS_RAM = 0,
    parameter [31:0] RAM_BASE = 32'h4000_0000,
    // Words per bank 2^RAM_AW: the RAM is 2^(RAM_AW + 3) bytes.
    parameter integer RAM_AW = 15
) (
    input  wire              clk,
    input  wire              reset,                    // synchronous, active high
    input  wire              cmd_valid,                // an instruction ...
    output wire              cmd_ready,                // ... taken when both are high
    input  wire [       9:0] cmd_payload_function_id,  // {funct7, funct3}
    input  wire [      31:0] cmd_payload_inputs_0,     // rs1
    input  wire [      31:0] cmd_payload_inputs_1,     // rs2
    output reg               rsp_valid,                // the answer ...
    input  wire              rsp_ready,                // ... taken when both are high
    output reg  [      31:0] rsp_payload_outputs_0,    // rd
    output wire [RAM_AW-1:0] mem_adr_0,                // bank 0 (even words): word index
    output wire [RAM_AW-1:0] mem_adr_1,                // bank 1 (odd words): word index
    input  wire [      31:0] mem_dat_0,                // bank 0's word, a cycle after
    input  wire [      31:0] mem_dat_1,                // bank 1's word, a cycle after
    input  wire              mem_hold,                 // the CPU has a write on its data bus
    input  wire [      29:0] mem_wadr                  // its word address (byte address >> 2)
);
    /* verilator lint_on DECLFILENAME */
    localparam [31:0] UNTEXTURED = 32'h8000_0000;
    localparam integer RAM_LOG2 = RAM_AW + 3;
    // The descriptor block: 19 words.
    localparam [31:0] BLOCK_BYTES = 32'd76;
    // Level tags of a filtered level: answer its rounded texel, keep it
    // quietly (the lower level of a trilinear sample), or blend it with the
    // one before (the upper level).
    localparam [1:0] LT_ROUND = 2'd0, LT_QUIET = 2'd1, LT_BLEND = 2'd2;
    // Tags of the addressing pipeline.
    localparam [1:0] AT_ADDR = 2'd0, AT_BW = 2'd1, AT_TMU = 2'd2;

    wire [6:0] funct7 = cmd_payload_function_id[9:3];
    wire [2:0] funct3 = cmd_payload_function_id[2:0];
    wire [31:0] a = cmd_payload_inputs_0;
    wire [31:0] b = cmd_payload_inputs_1;

    // An instruction waits while another's answer is due (`pend`), the
    // texture unit reads a descriptor block (`sq`) or an answer waits.
    reg        pend;
    reg  [2:0] sq;
    assign cmd_ready = !pend && sq == 3'd0 && (!rsp_valid || rsp_ready);
    wire fire = cmd_valid && cmd_ready;
    wire op0 = fire && funct7 == 7'd0;
    wire op1 = fire && funct7 == 7'd1;
    wire op2 = fire && funct7 == 7'd2;

    // ---- tex.log2pl and tex.lod -----------------------------------------
    reg  [1:0] lcnt;
    reg        lbusy;
    wire [31:0] log2pl;
    tex_log2pl #(.PIPE(1)) log2 (.clk(clk), .x({b, a}), .log2pl(log2pl));
    /* verilator lint_off UNUSEDSIGNAL */  // outside the I8F8 lod
    wire [31:0] diff = a - b;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] lod = b == UNTEXTURED ? UNTEXTURED : {{16{diff[23]}}, diff[23:8]};

    // ---- Addressing -------------------------------------------------------
    // Texel index `i` of an axis of 2^k texels in `mode` (see the header),
    // with mx = 2^k − 1 and kb = 2^k: i[k] and "i > mx" as masks, not as
    // a variable bit select and a 32-bit compare.
    function [15:0] mapi(input [31:0] i, input [15:0] mx, input [15:0] kb, input [1:0] mode);
        reg ik, ov, ovr;
        reg [31:0] r;
        begin
            ik = |(i[15:0] & kb);
            r = i ^ {32{i[31]}};
            ov = |i[31:16] || |(i[15:0] & ~mx);
            ovr = |r[31:16] || |(r[15:0] & ~mx);
            case (mode)
                2'd0: mapi = i[15:0] & mx;
                2'd1: mapi = (i[15:0] ^ {16{ik}}) & mx;
                2'd2: mapi = i[31] ? 16'd0 : ov ? mx : i[15:0];
                default: mapi = ovr ? mx : r[15:0];
            endcase
        end
    endfunction

    // One axis of coordinate `q` on 2^k texels, fraction fr (q[31:4] for
    // wrap, else q[27:0] of I4F28): the scaled
    // position p = (fr << (k + 4)) + 2¹⁹ − 2³¹ plus the integer part
    // `hi << k` (hi as the mode reduces q's integer bits) in its top word
    // is one 64-bit sum s + {h, 2³¹ + 2¹⁹}: s = fr << (k + 4) and
    // h = (hi << k) − 1 = ((hi − 1) << k) | (2^k − 1) for the first tap's
    // index, h = hi << k for the second's (index + 1). Returns
    // {s[47:4], h − 1 part, h part}.
    function [107:0] shifted(input [31:0] q, input [3:0] k, input [1:0] mode);
        reg [4:0] hi, him1;
        reg [27:0] fr;
        reg [31:0] mx;
        begin
            hi = mode == 2'd0 ? 5'd0 : mode == 2'd1 ? {4'd0, q[28]} : {q[31], q[31:28]};
            fr = mode == 2'd0 ? q[31:4] : q[27:0];
            him1 = hi - 5'd1;
            mx = (32'd1 << k) - 32'd1;
            shifted = {{16'd0, fr} << k, ({{27{him1[4]}}, him1} << k) | mx, {{27{hi[4]}}, hi} << k};
        end
    endfunction

    // The level tex.addr addresses (tex.lvl).
    reg [31:0] lbase;
    reg  [3:0] lkx, lky;
    reg  [1:0] lmu, lmv;
    // The texture unit's state after tex.sel: the block's address, the
    // windowed lod, the modes and the two levels (texel (0, 0) and sides).
    reg [31:0] sp;                      // the block's byte address
    reg [17:0] slod;                    // the lod operand (I8F8 bits)
    reg [15:0] swin1;                   // word 1 [27:12]: the window's top and the modes
    reg [17:0] swmax;                   // max(lod + bias, lo)
    reg  [7:0] tt;                      // the windowed lod: level fraction t
    reg  [3:0] tlow;                    // and lower level
    reg  [1:0] tmu, tmv;                // the address modes
    reg [31:0] tb0, tb1;                // the two levels' texel (0, 0)
    reg  [3:0] tkx0, tky0, tkx1, tky1;  // and log2 of their sides
    // tex.tri's coordinates, for its upper level.
    reg [31:0] tu, tv;
    // The upper level enters the addressing two cycles after the lower.
    reg  [1:0] l1cnt;

    // Stage A1: the shifted coordinates. Sources: tex.addr (the tex.lvl
    // level), tex.bw (the weights alone), tex.tri/tex.bil (the lower or
    // nearest level), the upper level of tex.tri.
    wire inj_addr = op1 && funct3 == 3'd1;
    wire inj_bw = op0 && funct3 == 3'd2;
    wire inj_tri = op2 && funct3 == 3'd2;
    wire inj_bil = op2 && funct3 == 3'd3;
    wire inj_up = l1cnt == 2'd1;
    wire near_up = tt[7];  // tex.bil: the nearest level is the upper one
    wire [31:0] in_u = inj_up ? tu : a, in_v = inj_up ? tv : b;
    wire [31:0] in_base = inj_addr ? lbase : (inj_up || (inj_bil && near_up)) ? tb1 : tb0;
    wire [3:0] in_kx = inj_addr ? lkx : (inj_up || (inj_bil && near_up)) ? tkx1 : tkx0;
    wire [3:0] in_ky = inj_addr ? lky : (inj_up || (inj_bil && near_up)) ? tky1 : tky0;
    wire [1:0] in_mu = inj_addr ? lmu : tmu, in_mv = inj_addr ? lmv : tmv;
    wire [107:0] shx = shifted(in_u, in_kx, in_mu), shy = shifted(in_v, in_ky, in_mv);
    reg        a_v, a_bw;
    reg  [1:0] a_tag, a_lt;
    reg [43:0] a_sx, a_sy;
    reg [31:0] a_hmx, a_hpx, a_hmy, a_hpy, a_base;
    reg [12:0] a_bwx, a_bwy;
    reg  [3:0] a_kx, a_ky;
    reg  [1:0] a_mu, a_mv;

    // Stage A2: the two sums per axis: the taps' indices and the weights.
    /* verilator lint_off UNUSEDSIGNAL */  // below the weight; the second sum's low word is the first's
    wire [63:0] pmx = {16'd0, a_sx, 4'd0} + {a_hmx, 32'h8008_0000};
    wire [63:0] ppx = {16'd0, a_sx, 4'd0} + {a_hpx, 32'h8008_0000};
    wire [63:0] pmy = {16'd0, a_sy, 4'd0} + {a_hmy, 32'h8008_0000};
    wire [63:0] ppy = {16'd0, a_sy, 4'd0} + {a_hpy, 32'h8008_0000};
    /* verilator lint_on UNUSEDSIGNAL */
    reg        b_v;
    reg  [1:0] b_tag, b_lt;
    reg [31:0] b_i0x, b_i1x, b_i0y, b_i1y, b_base;
    reg [12:0] b_wx, b_wy;
    reg [15:0] b_mxx, b_kbx, b_mxy, b_kby;
    reg  [3:0] b_kx;
    reg  [1:0] b_mu, b_mv;

    // Stage B1: index maps and the weights' complements.
    reg        c_v;
    reg  [1:0] c_tag, c_lt;
    reg [15:0] c_x0, c_x1, c_y0, c_y1;
    reg [12:0] c_wx, c_wy, c_fxc, c_fyc;
    reg [31:0] c_base;
    reg  [3:0] c_kx;

    // Stage B2: the four texel addresses base + 4·(y·2^kx + x) (x < 2^kx:
    // an OR), the corner weights.
    function [31:0] texel(input [31:0] base, input [3:0] k, input [15:0] x, input [15:0] y);
        texel = base + ((({16'd0, y} << k) | {16'd0, x}) << 2);
    endfunction
    /* verilator lint_off UNUSEDSIGNAL */  // every weight ≤ 2²⁴
    wire [25:0] w00 = c_fxc * c_fyc, w10 = c_wx * c_fyc, w01 = c_fxc * c_wy, w11 = c_wx * c_wy;
    /* verilator lint_on UNUSEDSIGNAL */
    // tex.addr's taps (answered from d_* a cycle after B2), the weights of
    // tex.bw / tex.addr.
    reg        d_v;
    reg        d_addr;
    reg [31:0] a10, a01, a11;
    reg [24:0] lw00, lw10, lw01, lw11;
    // A level of the texture unit: its four texel addresses and weights,
    // its two rows presented to the RAM in consecutive cycles (`lrow`).
    reg        lv_v, lrow;
    reg  [1:0] lv_lt;
    reg [31:0] lp00, lp10, lp01, lp11;
    reg [24:0] lv00, lv10, lv01, lv11;

    // ---- The RAM port -----------------------------------------------------
    // Two words a cycle, at byte addresses `wa` and `wb` (different
    // parities, or equal): each bank reads the one of its parity. The
    // descriptor block's pairs come from registers (ra, rb).
    reg [31:0] ra, rb;
    /* verilator lint_off UNUSEDSIGNAL */  // outside the RAM's offset bits
    wire [31:0] wa = sq != 3'd0 ? ra : lrow ? lp01 : lp00;
    wire [31:0] wb = sq != 3'd0 ? rb : lrow ? lp11 : lp10;
    /* verilator lint_on UNUSEDSIGNAL */
    assign mem_adr_0 = wa[2] ? wb[RAM_AW+2:3] : wa[RAM_AW+2:3];
    assign mem_adr_1 = wa[2] ? wa[RAM_AW+2:3] : wb[RAM_AW+2:3];
    // The banks of the words in the data cycle, and what the data is.
    reg        da, db;
    reg        md_v, md_row;
    reg  [1:0] md_lt;
    reg [24:0] md_wa, md_wb;
    wire [31:0] dat_a = da ? mem_dat_1 : mem_dat_0, dat_b = db ? mem_dat_1 : mem_dat_0;

    // tex.sel: is the block in the RAM.
    /* verilator lint_off UNUSEDSIGNAL */
    wire [31:0] off = a - RAM_BASE;
    /* verilator lint_on UNUSEDSIGNAL */
    wire blk_ok = HAS_RAM != 0 && a[1:0] == 2'd0 && off <= (32'd1 << RAM_LOG2) - BLOCK_BYTES;
    // The block cache: the 19 words of the block at `cp` (and one word
    // after it) while `cv`, word i in cblk[32i+31:32i]; filled by tex.sel
    // (ten reads of two words, `cfc`), dropped by any CPU write into the
    // block's words (`cdt`: one came during the fill).
    reg          cv, cdt;
    reg  [31:0]  cp;
    reg  [ 3:0]  cfc;
    reg  [639:0] cblk;
    wire chit = cv && cp == sp;
    /* verilator lint_off UNUSEDSIGNAL */  // the block's word offset: only < 19 matters
    wire [29:0] wrel = mem_wadr - cp[31:2];
    /* verilator lint_on UNUSEDSIGNAL */
    // The selected levels' words (word 2 + tlow and the next).
    /* verilator lint_off UNUSEDSIGNAL */  // offset bits above the RAM's
    wire [31:0] lw_a = cblk[64 + 32 * tlow +: 32], lw_b = cblk[96 + 32 * tlow +: 32];
    /* verilator lint_on UNUSEDSIGNAL */
    // The window: bits = min(max(lod + bias, lo), hi), 18-bit signed sum,
    // from the cached words 0 (bias) and 1 (window).
    /* verilator lint_off UNUSEDSIGNAL */  // the bias and lod are I8F8 bits: 18 bits hold their sum
    wire [17:0] wsum = slod + cblk[17:0];
    /* verilator lint_on UNUSEDSIGNAL */
    wire [11:0] wlo = cblk[43:32], whi = swin1[11:0];
    wire [17:0] wmax = $signed(wsum) < $signed({6'd0, wlo}) ? {6'd0, wlo} : wsum;
    /* verilator lint_off UNUSEDSIGNAL */  // wmax ≥ lo ≥ 0: the top bits only compare
    wire [17:0] wbits = swmax > {6'd0, whi} ? {6'd0, whi} : swmax;
    /* verilator lint_on UNUSEDSIGNAL */

    // ---- The filter: four channels in parallel ----------------------------
    // F0: a footprint row (two texels and their weights); F1: the corner
    // products; F2: the row's sum (the first row's kept in `sum0`); F3: the
    // level's sum X; F4: X's 8.16 value (w1, the one before moves to w0)
    // and the rounded texel.
    reg        f0_v, f0_row;
    reg  [1:0] f0_lt;
    reg [31:0] f0_ta, f0_tb;
    reg [24:0] f0_wa, f0_wb;
    reg        f1_v, f1_row;
    reg  [1:0] f1_lt;
    reg [127:0] f1_pa, f1_pb;
    reg [127:0] sum0;
    reg        f2_v;
    reg  [1:0] f2_lt;
    reg [127:0] f2_r;
    reg        f3_v;
    reg  [1:0] f3_lt;
    reg [127:0] f3_x;
    reg [95:0] w0, w1;
    // The blend: B1 the two products per channel (the first with the
    // rounding term 2²³), B2 their sum.
    reg        bl_v, b2_v;
    reg  [8:0] bl_t;
    reg [127:0] b2_q0, b2_q1;

    wire [127:0] pa_n, pb_n, r_n, x_n, q0_n, q1_n;
    wire [95:0] wide_n;
    wire [31:0] round_n, blend_n;
    wire [8:0] bl_tc = 9'd256 - bl_t;
    genvar c;
    generate
        for (c = 0; c < 4; c = c + 1) begin : ch
            /* verilator lint_off UNUSEDSIGNAL */  // every product < 2³², the sums too
            wire [32:0] pa = {25'd0, f0_ta[8*c+7:8*c]} * {8'd0, f0_wa};
            wire [32:0] pb = {25'd0, f0_tb[8*c+7:8*c]} * {8'd0, f0_wb};
            wire [31:0] xw = f3_x[32*c+31:32*c] + 32'd128;
            wire [31:0] xr = f3_x[32*c+31:32*c] + 32'h0080_0080;
            wire [32:0] q0 = {9'd0, w0[24*c+23:24*c]} * {24'd0, bl_tc};
            wire [32:0] q1 = {9'd0, w1[24*c+23:24*c]} * {24'd0, bl_t};
            wire [31:0] bs = b2_q0[32*c+31:32*c] + b2_q1[32*c+31:32*c];
            /* verilator lint_on UNUSEDSIGNAL */
            assign pa_n[32*c+31:32*c] = pa[31:0];
            assign pb_n[32*c+31:32*c] = pb[31:0];
            assign r_n[32*c+31:32*c] = f1_pa[32*c+31:32*c] + f1_pb[32*c+31:32*c];
            assign x_n[32*c+31:32*c] = sum0[32*c+31:32*c] + f2_r[32*c+31:32*c];
            assign wide_n[24*c+23:24*c] = xw[31:8];
            assign round_n[8*c+7:8*c] = xr[31:24];
            assign q0_n[32*c+31:32*c] = q0[31:0] + 32'h0080_0000;
            assign q1_n[32*c+31:32*c] = q1[31:0];
            assign blend_n[8*c+7:8*c] = bs[31:24];
        end
    endgenerate

    // ---- The answers and the pipeline -------------------------------------
    always @(posedge clk) begin
        if (rsp_valid && rsp_ready) rsp_valid <= 1'b0;

        // tex.log2pl.
        if (lbusy) begin
            lcnt <= lcnt + 2'd1;
            if (lcnt == 2'd3) begin
                lbusy                 <= 1'b0;
                pend                  <= 1'b0;
                rsp_valid             <= 1'b1;
                rsp_payload_outputs_0 <= log2pl;
            end
        end

        // The upper level of tex.tri.
        if (l1cnt != 2'd0) l1cnt <= l1cnt - 2'd1;

        // Stage A1.
        a_v <= inj_addr || inj_bw || inj_tri || inj_bil || inj_up;
        a_bw <= inj_bw;
        a_tag <= inj_addr ? AT_ADDR : inj_bw ? AT_BW : AT_TMU;
        a_lt <= inj_up ? LT_BLEND : (inj_tri && tt != 8'd0) ? LT_QUIET : LT_ROUND;
        a_sx <= shx[107:64];
        a_hmx <= shx[63:32];
        a_hpx <= shx[31:0];
        a_sy <= shy[107:64];
        a_hmy <= shy[63:32];
        a_hpy <= shy[31:0];
        a_bwx <= a[12:0];
        a_bwy <= b[12:0];
        a_base <= in_base;
        a_kx <= in_kx;
        a_ky <= in_ky;
        a_mu <= in_mu;
        a_mv <= in_mv;

        // Stage A2.
        b_v <= a_v;
        b_tag <= a_tag;
        b_lt <= a_lt;
        b_i0x <= pmx[63:32];
        b_i1x <= ppx[63:32];
        b_i0y <= pmy[63:32];
        b_i1y <= ppy[63:32];
        b_wx <= a_bw ? a_bwx : {1'b0, pmx[31:20]};
        b_wy <= a_bw ? a_bwy : {1'b0, pmy[31:20]};
        b_mxx <= (16'd1 << a_kx) - 16'd1;
        b_kbx <= 16'd1 << a_kx;
        b_mxy <= (16'd1 << a_ky) - 16'd1;
        b_kby <= 16'd1 << a_ky;
        b_base <= a_base;
        b_kx <= a_kx;
        b_mu <= a_mu;
        b_mv <= a_mv;

        // Stage B1.
        c_v <= b_v;
        c_tag <= b_tag;
        c_lt <= b_lt;
        c_x0 <= mapi(b_i0x, b_mxx, b_kbx, b_mu);
        c_x1 <= mapi(b_i1x, b_mxx, b_kbx, b_mu);
        c_y0 <= mapi(b_i0y, b_mxy, b_kby, b_mv);
        c_y1 <= mapi(b_i1y, b_mxy, b_kby, b_mv);
        c_wx <= b_wx;
        c_wy <= b_wy;
        c_fxc <= 13'd4096 - b_wx;
        c_fyc <= 13'd4096 - b_wy;
        c_base <= b_base;
        c_kx <= b_kx;

        // Stage B2: a level of the texture unit, or tex.addr's taps and
        // tex.bw's weights (answered the cycle after).
        d_v <= 1'b0;
        if (c_v) begin
            lp00 <= texel(c_base, c_kx, c_x0, c_y0);
            lp10 <= texel(c_base, c_kx, c_x1, c_y0);
            lp01 <= texel(c_base, c_kx, c_x0, c_y1);
            lp11 <= texel(c_base, c_kx, c_x1, c_y1);
            if (c_tag == AT_TMU) begin
                lv_v  <= 1'b1;
                lv_lt <= c_lt;
                lv00  <= w00[24:0];
                lv10  <= w10[24:0];
                lv01  <= w01[24:0];
                lv11  <= w11[24:0];
            end else begin
                lw00   <= w00[24:0];
                lw10   <= w10[24:0];
                lw01   <= w01[24:0];
                lw11   <= w11[24:0];
                d_v    <= 1'b1;
                d_addr <= c_tag == AT_ADDR;
            end
        end
        if (d_v) begin
            pend                  <= 1'b0;
            rsp_valid             <= 1'b1;
            rsp_payload_outputs_0 <= d_addr ? lp00 : 32'd0;
            if (d_addr) begin
                a10 <= lp10;
                a01 <= lp01;
                a11 <= lp11;
            end
        end

        // The RAM: a level's rows, or the descriptor block's words.
        da   <= wa[2];
        db   <= wb[2];
        md_v <= 1'b0;
        if (sq == 3'd0 && lv_v) begin
            md_v   <= 1'b1;
            md_row <= lrow;
            md_lt  <= lv_lt;
            md_wa  <= lrow ? lv01 : lv00;
            md_wb  <= lrow ? lv11 : lv10;
            lrow   <= !lrow;
            if (lrow) lv_v <= 1'b0;
        end
        if (c_v && c_tag == AT_TMU) lv_v <= 1'b1;

        // tex.sel: 1 waits for the CPU's writes to end (mem_hold), then
        // answers from the block cache when it holds this block (word 1's
        // valid bit; an invalid block ends here) and clamps the lod below,
        // else reads the block into the cache (2, ten pairs of words, then
        // 1 again); 4 the lod clamped above, 5 the two levels' words from
        // the cache.
        case (sq)
            3'd1:
            if (!mem_hold) begin
                if (chit) begin
                    pend                  <= 1'b0;
                    rsp_valid             <= 1'b1;
                    rsp_payload_outputs_0 <= {31'd0, cblk[60]};
                    swin1                 <= cblk[59:44];
                    swmax                 <= wmax;
                    sq                    <= cblk[60] ? 3'd4 : 3'd0;
                end else begin
                    cv  <= 1'b0;
                    cp  <= sp;
                    cdt <= 1'b0;
                    cfc <= 4'd0;
                    ra  <= ra + 32'd8;
                    rb  <= rb + 32'd8;
                    sq  <= 3'd2;
                end
            end
            3'd2: begin
                cblk <= {dat_b, dat_a, cblk[639:64]};
                ra   <= ra + 32'd8;
                rb   <= rb + 32'd8;
                cfc  <= cfc + 4'd1;
                if (cfc == 4'd9) begin
                    cv <= !cdt;
                    ra <= sp;
                    rb <= sp + 32'd4;
                    sq <= 3'd1;
                end
            end
            3'd4: begin
                tt   <= wbits[7:0];
                tlow <= wbits[11:8];
                tmu  <= swin1[13:12];
                tmv  <= swin1[15:14];
                sq   <= 3'd5;
            end
            3'd5: begin
                tb0  <= {RAM_BASE[31:RAM_LOG2], lw_a[RAM_LOG2-3:0], 2'd0};
                tkx0 <= lw_a[27:24];
                tky0 <= lw_a[31:28];
                tb1  <= {RAM_BASE[31:RAM_LOG2], lw_b[RAM_LOG2-3:0], 2'd0};
                tkx1 <= lw_b[27:24];
                tky1 <= lw_b[31:28];
                sq   <= 3'd0;
            end
            default: ;
        endcase
        // A CPU write into the cached block's words drops the cache (and
        // a fill under way keeps it dropped).
        if (mem_hold && wrel < 30'd19) begin
            cv  <= 1'b0;
            cdt <= 1'b1;
        end

        // F0: a row from the RAM (or from tex.bt / tex.bb below).
        f0_v <= md_v;
        if (md_v) begin
            f0_row <= md_row;
            f0_lt  <= md_lt;
            f0_ta  <= dat_a;
            f0_tb  <= dat_b;
            f0_wa  <= md_wa;
            f0_wb  <= md_wb;
        end
        // F1 … F4.
        f1_v   <= f0_v;
        f1_row <= f0_row;
        f1_lt  <= f0_lt;
        f1_pa  <= pa_n;
        f1_pb  <= pb_n;
        f2_v   <= f1_v && f1_row;
        f2_lt  <= f1_lt;
        f2_r   <= r_n;
        if (f1_v && !f1_row) sum0 <= r_n;
        f3_v  <= f2_v;
        f3_lt <= f2_lt;
        f3_x  <= x_n;
        if (f3_v) begin
            w0 <= w1;
            w1 <= wide_n;
            if (f3_lt == LT_ROUND) begin
                pend                  <= 1'b0;
                rsp_valid             <= 1'b1;
                rsp_payload_outputs_0 <= round_n;
            end
        end
        // The blend (after the upper level, or tex.blend below).
        bl_v <= f3_v && f3_lt == LT_BLEND;
        if (f3_v && f3_lt == LT_BLEND) bl_t <= {1'b0, tt};
        b2_v  <= bl_v;
        b2_q0 <= q0_n;
        b2_q1 <= q1_n;
        if (b2_v) begin
            pend                  <= 1'b0;
            rsp_valid             <= 1'b1;
            rsp_payload_outputs_0 <= blend_n;
        end

        if (fire) begin
            rsp_valid             <= 1'b1;
            rsp_payload_outputs_0 <= 32'd0;
            if (op0) begin
                case (funct3)
                    3'd0: begin
                        rsp_valid <= 1'b0;
                        pend      <= 1'b1;
                        lbusy     <= 1'b1;
                        lcnt      <= 2'd0;
                    end
                    3'd1: rsp_payload_outputs_0 <= lod;
                    3'd2: begin
                        rsp_valid <= 1'b0;
                        pend      <= 1'b1;
                    end
                    3'd3, 3'd4: begin
                        f0_v   <= 1'b1;
                        f0_row <= funct3 == 3'd4;
                        f0_lt  <= LT_ROUND;
                        f0_ta  <= a;
                        f0_tb  <= b;
                        f0_wa  <= funct3 == 3'd4 ? lw01 : lw00;
                        f0_wb  <= funct3 == 3'd4 ? lw11 : lw10;
                        if (funct3 == 3'd4) begin
                            rsp_valid <= 1'b0;
                            pend      <= 1'b1;
                        end
                    end
                    3'd5: begin
                        rsp_valid <= 1'b0;
                        pend      <= 1'b1;
                        bl_v      <= 1'b1;
                        bl_t      <= a[8:0] > 9'd256 ? 9'd256 : a[8:0];
                    end
                    default: ;
                endcase
            end else if (op1) begin
                case (funct3)
                    3'd0: begin
                        lbase <= a;
                        lkx   <= b[3:0];
                        lky   <= b[7:4];
                        lmu   <= b[9:8];
                        lmv   <= b[11:10];
                    end
                    3'd1: begin
                        rsp_valid <= 1'b0;
                        pend      <= 1'b1;
                    end
                    3'd2: rsp_payload_outputs_0 <= a10;
                    3'd3: rsp_payload_outputs_0 <= a01;
                    3'd4: rsp_payload_outputs_0 <= a11;
                    default: ;
                endcase
            end else if (op2) begin
                case (funct3)
                    3'd0: rsp_payload_outputs_0 <= HAS_RAM != 0 ? RAM_BASE | RAM_LOG2 : 32'd0;
                    3'd1: begin
                        if (blk_ok) begin
                            rsp_valid <= 1'b0;
                            pend      <= 1'b1;
                            sp        <= a;
                            ra        <= a;
                            rb        <= a + 32'd4;
                            slod      <= b[17:0];
                            sq        <= 3'd1;
                        end
                    end
                    3'd2, 3'd3: begin
                        rsp_valid <= 1'b0;
                        pend      <= 1'b1;
                        if (inj_tri && tt != 8'd0) begin
                            tu    <= a;
                            tv    <= b;
                            l1cnt <= 2'd2;
                        end
                    end
                    default: ;
                endcase
            end
        end
        if (reset) begin
            rsp_valid <= 1'b0;
            pend      <= 1'b0;
            lbusy     <= 1'b0;
            sq        <= 3'd0;
            cv        <= 1'b0;
            l1cnt     <= 2'd0;
            a_v       <= 1'b0;
            b_v       <= 1'b0;
            c_v       <= 1'b0;
            d_v       <= 1'b0;
            lv_v      <= 1'b0;
            lrow      <= 1'b0;
            md_v      <= 1'b0;
            f0_v      <= 1'b0;
            f1_v      <= 1'b0;
            f2_v      <= 1'b0;
            f3_v      <= 1'b0;
            bl_v      <= 1'b0;
            b2_v      <= 1'b0;
        end
    end
endmodule

`default_nettype wire
