// raymip texture co-processor for PicoRV32: custom-0 instructions on the
// Pico Co-Processor Interface (PCPI). Our own RTL (issue 23); soc.v
// instantiates it when built with `-DRAYMIP_PCPI` (ENABLE_PCPI on the core).
//
// Instructions (R-type, opcode custom-0 = 0001011, funct7 = 0):
//
//   funct3 0  tex.log2pl rd, rs1, rs2
//             rs1 = low word, rs2 = high word of a path length Pl in U32F32
//             (scene units, the firmware's `PathLength`). rd = log2 Pl in
//             I16F16 bits plus 0x80 (the I8F8 rounding offset of a lod),
//             exactly `biased − (lz << 16)` of the firmware's
//             `log2_u32f32_parts` (src/log2/mod.rs): lz = leading zeros of the
//             64-bit value (63 for zero: Pl = 0 reads as 2⁻³²), the 32-bit
//             mantissa m = top word of Pl << lz, index m[30:25] into the
//             64 intervals of round(log2(1 + i/64)·2¹⁶), weight m[24:9],
//             interval value base + ((slope·weight + 2¹⁵) >> 16), biased by
//             (31 << 16) + 0x80. Range: [−32·2¹⁶ + 0x80, 32·2¹⁶ + 0x80].
//
//   funct3 1  tex.lod rd, rs1, rs2
//             rs1 = the tex.log2pl result, rs2 = log2 Pb of the hit triangle
//             (I16F16 bits, the firmware's `Log2Pb`, markers included).
//             rd = the table lod `((rs1 − rs2) >> 8)` truncated to I8F8 and
//             sign-extended to 32 bits, as the firmware's `table_lod`; for
//             the untextured marker rs2 = 0x8000_0000 (`Log2Pb::UNTEXTURED`,
//             `table_lod` returns None) rd = 0x8000_0000, a value no I8F8
//             lod sign-extends to. The degenerate markers (±95 levels) are
//             ordinary entries: their lods saturate as in software (≥ 63 /
//             ≤ −63 levels).
//
//   The ACCURATE filter (the firmware's `texture::kernel::accurate`, bit
//   for bit): a stateful corner sum. Channel c of a texel is bits
//   [8c+7:8c]; weights fx, fy ∈ [0, 4096] (12 fractional bits), the level
//   fraction t ∈ [0, 256].
//
//   funct3 2  tex.bw rd, rs1, rs2
//             rs1 = fx, rs2 = fy (bits [12:0] read): latched as the
//             position weights of the footprint that follows. rd = 0.
//
//   funct3 3  tex.bt rd, rs1, rs2
//             rs1 = t00, rs2 = t10 (the footprint's top row): latches
//             top_c = t00_c·(4096 − fx) + t10_c·fx per channel (computed
//             as (t10_c − t00_c)·fx + t00_c·2¹², exact). rd = 0.
//
//   funct3 4  tex.bb rd, rs1, rs2
//             rs1 = t01, rs2 = t11 (the bottom row): bot_c likewise, the
//             corner sum X_c = top_c·(4096 − fy) + bot_c·fy (as
//             (bot_c − top_c)·fy + top_c·2¹²; X_c ≤ 255·2²⁴) and the
//             level's 8.16 value w_c = (X_c + 2⁷) >> 8; the previous
//             level's values move to w0, these become w1. rd = the
//             rounded texel, channel c = (w_c + 2¹⁵) >> 16 (the
//             firmware's `bilerp_rounded`).
//
//   funct3 5  tex.blend rd, rs1, rs2
//             rs1 = t (bits [8:0], ≤ 256), rs2 unused. rd = the level
//             blend of w0 and w1, channel c = (w0_c·(256 − t) + w1_c·t +
//             2²³) >> 24 (computed as (w1_c − w0_c)·t + w0_c·2⁸ + 2²³;
//             the firmware's `blend_wide_in_range`); t = 256 rounds w1
//             alone. Leaves the state as it was (repeatable).
//
// Any other custom-0 funct3/funct7 is not claimed (the core then traps as
// on any illegal instruction). Timing: operands registered; tex.lod and
// tex.bw then answer (pcpi_ready two cycles after pcpi_valid is first
// seen); tex.log2pl registers the coarse (32, 16, 8) and the fine
// (4, 2, 1) normalisation steps, then the table read, multiply and adds
// into pcpi_rd (pcpi_ready four cycles after pcpi_valid); the filter
// instructions run one channel per cycle through one shared 25×14-bit
// signed multiplier (tex.bt and tex.blend: ready five cycles after valid,
// tex.bb: two steps a channel, nine). PicoRV32 times out after 16 cycles
// without pcpi_wait; pcpi_wait is held meanwhile. Every output bit is
// checked against vectors written by the Rust firmware code
// (tb_pcpi_tex.cpp, scripts/softcore).
`timescale 1 ns / 1 ps
`default_nettype none

module pcpi_tex (
    input  wire        clk,
    input  wire        resetn,
    input  wire        pcpi_valid,
    /* verilator lint_off UNUSEDSIGNAL */  // register numbers: the core's business
    input  wire [31:0] pcpi_insn,
    /* verilator lint_on UNUSEDSIGNAL */
    input  wire [31:0] pcpi_rs1,
    input  wire [31:0] pcpi_rs2,
    output reg         pcpi_wr,
    output reg  [31:0] pcpi_rd,
    output wire        pcpi_wait,
    output reg         pcpi_ready
);
    localparam [6:0] CUSTOM0 = 7'b0001011;
    localparam [31:0] UNTEXTURED = 32'h8000_0000;

    wire is_tex = pcpi_valid && pcpi_insn[6:0] == CUSTOM0 && pcpi_insn[31:25] == 7'd0;
    wire [2:0] funct3 = pcpi_insn[14:12];
    wire claimed = is_tex && funct3 <= 3'd5;

    // Registered steps. tex.log2pl, tex.lod and tex.bw: the operands (the
    // cycle after valid); for tex.lod and tex.bw then the result (with
    // pcpi_ready, two cycles after valid); for tex.log2pl the coarse and the
    // fine normalisation, then the result (four cycles after valid). The
    // filter instructions: the operands, then one channel per cycle (two
    // for tex.bb) through the shared multiplier, the result with the last
    // channel. The operands are registered first so that no path starts
    // at the core's register file.
    localparam [2:0] IDLE = 3'd0, OPS = 3'd1, COARSE = 3'd2, FINE = 3'd3, FILTER = 3'd4;
    reg        busy;     // an instruction is in flight (until valid drops)
    reg  [2:0] stage;
    reg  [2:0] op;       // funct3 of the instruction in flight
    reg [63:0] x;        // operands {rs2, rs1}; the filters shift them by a channel per step
    // tex.log2pl: the shared pipeline (tex_log2pl.v) on the registered
    // operands x; its result is valid in the FINE stage.
    wire [31:0] log2pl;
    tex_log2pl log2 (.clk(clk), .x(x), .log2pl(log2pl));

    /* verilator lint_off UNUSEDSIGNAL */  // outside the I8F8 lod
    wire [31:0] diff = x[31:0] - x[63:32];
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] lod = x[63:32] == UNTEXTURED ? UNTEXTURED : {{16{diff[23]}}, diff[23:8]};

    // Filter state: the position weights of tex.bw, the four top-row
    // values of tex.bt (20 bits each, channel 0 first, rotated a channel
    // per step), one channel's bottom-row value, and the 8.16 values of
    // the last two levels tex.bb filtered (w1 the newest, w0 the one
    // before; 24 bits a channel, channel 0 in the low bits, rotated a
    // channel per step).
    reg [12:0] fx, fy;
    reg [79:0] top;
    reg [19:0] bot;
    reg [95:0] w0, w1;
    reg  [2:0] cnt;      // channel step of the filter instruction in flight

    // The shared multiplier: ma·mb + base, one channel per cycle. Operands
    // (all exact, the sum lies in [0, 2³²)):
    //   tex.bt, tex.bb even steps: (b − a)·fx + a·2¹², a, b the two texels' channel;
    //   tex.bb odd steps: (bot − top)·fy + top·2¹² (= X, the corner sum);
    //   tex.blend: (w1 − w0)·t + w0·2⁸ + 2²³.
    wire       vstep = op == 3'd4 && cnt[0];
    wire       blend = op == 3'd5;
    wire [23:0] mp = blend ? w1[23:0] : vstep ? {4'd0, bot} : {16'd0, x[39:32]};
    wire [23:0] mq = blend ? w0[23:0] : vstep ? {4'd0, top[19:0]} : {16'd0, x[7:0]};
    wire [24:0] ma = {1'b0, mp} - {1'b0, mq};
    wire [13:0] mb = blend ? {5'd0, x[8:0]} : vstep ? {1'b0, fy} : {1'b0, fx};
    /* verilator lint_off UNUSEDSIGNAL */  // the product's bits above the exact 34-bit sum
    wire signed [38:0] mprod = $signed(ma) * $signed(mb);
    /* verilator lint_on UNUSEDSIGNAL */
    wire [33:0] mbase = blend ? {2'd0, w0[23:0], 8'd0} + 34'h80_0000
                      : vstep ? {2'd0, top[19:0], 12'd0} : {14'd0, x[7:0], 12'd0};
    /* verilator lint_off UNUSEDSIGNAL */  // r[33:32] are zero (the sum is below 2³²)
    wire [33:0] r = mbase + mprod[33:0];
    // One level's 8.16 value (X + 2⁷) >> 8 and its rounded channel.
    wire [31:0] wsum = r[31:0] + 32'd128;
    wire [23:0] wide = wsum[31:8];
    wire [23:0] wround = wide + 24'h8000;
    /* verilator lint_on UNUSEDSIGNAL */
    wire  [7:0] chan = blend ? r[31:24] : wround[23:16];
    wire        last = cnt == (op == 3'd4 ? 3'd7 : 3'd3);

    assign pcpi_wait = claimed && !pcpi_ready;

    always @(posedge clk) begin
        pcpi_ready <= 1'b0;
        pcpi_wr    <= 1'b0;
        if (!resetn) begin
            busy  <= 1'b0;
            stage <= IDLE;
        end else if (stage == IDLE) begin
            // A new instruction only after the previous one's valid has
            // dropped (the core clears pcpi_valid the cycle after ready).
            if (claimed && !busy) begin
                busy  <= 1'b1;
                stage <= funct3 >= 3'd3 ? FILTER : OPS;
                op    <= funct3;
                cnt   <= 3'd0;
                x     <= {pcpi_rs2, pcpi_rs1};
                if (funct3 == 3'd2) begin
                    fx <= pcpi_rs1[12:0];
                    fy <= pcpi_rs2[12:0];
                end
            end else if (!pcpi_valid) begin
                busy <= 1'b0;
            end
        end else if (stage == OPS) begin
            if (op == 3'd0) begin
                stage <= COARSE;
            end else begin
                stage      <= IDLE;
                pcpi_ready <= 1'b1;
                pcpi_wr    <= 1'b1;
                pcpi_rd    <= op == 3'd1 ? lod : 32'd0;
            end
        end else if (stage == COARSE) begin
            stage <= FINE;
        end else if (stage == FINE) begin
            stage      <= IDLE;
            pcpi_ready <= 1'b1;
            pcpi_wr    <= 1'b1;
            pcpi_rd    <= log2pl;
        end else begin
            // FILTER: one step of tex.bt (4), tex.bb (8) or tex.blend (4).
            cnt <= cnt + 3'd1;
            if (op == 3'd3 || vstep) top <= {r[19:0], top[79:20]};
            if (op == 3'd4 && !cnt[0]) bot <= r[19:0];
            if (op == 3'd3 || vstep) x <= {8'd0, x[63:40], 8'd0, x[31:8]};
            if (vstep) begin
                w1 <= {wide, w1[95:24]};
                w0 <= {w1[23:0], w0[95:24]};
            end
            if (blend) begin
                w1 <= {w1[23:0], w1[95:24]};
                w0 <= {w0[23:0], w0[95:24]};
            end
            if (vstep || blend) pcpi_rd <= {chan, pcpi_rd[31:8]};
            if (last) begin
                stage      <= IDLE;
                pcpi_ready <= 1'b1;
                pcpi_wr    <= 1'b1;
                if (op == 3'd3) pcpi_rd <= 32'd0;
            end
        end
    end
endmodule

`default_nettype wire
