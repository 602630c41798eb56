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
//             `log2_u32f32_parts` (src/lod/log2.rs): lz = leading zeros of the
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
    localparam [31:0] LOD_BIAS = (32'd31 << 16) + 32'h80;

    wire is_tex = pcpi_valid && pcpi_insn[6:0] == CUSTOM0 && pcpi_insn[31:25] == 7'd0;
    wire [2:0] funct3 = pcpi_insn[14:12];
    wire claimed = is_tex && funct3 <= 3'd5;

    // Normalisation of the 64-bit path length: six shift-if-zero steps
    // (32, 16, 8, 4, 2, 1) give the leading-zero count and the shifted
    // value together; zero gives lz = 63 and m = 0 (whose interval value
    // equals that of m = 2³¹, as in software). Two pipeline stages: the
    // coarse steps (32, 16, 8) keep the top 39 bits (the fine steps shift
    // by at most 7), the fine steps (4, 2, 1) the top 32.
    function [44:0] normalise_coarse(input [63:0] x);
        reg [63:0] v;
        reg [5:0] n;
        begin
            v = x;
            n = 6'd0;
            if (v[63:32] == 32'd0) begin v = v << 32; n = n + 6'd32; end
            if (v[63:48] == 16'd0) begin v = v << 16; n = n + 6'd16; end
            if (v[63:56] == 8'd0) begin v = v << 8; n = n + 6'd8; end
            normalise_coarse = {n, v[63:25]};
        end
    endfunction

    function [37:0] normalise_fine(input [44:0] c);
        reg [38:0] v;
        reg [5:0] n;
        begin
            n = c[44:39];
            v = c[38:0];
            if (v[38:35] == 4'd0) begin v = v << 4; n = n + 6'd4; end
            if (v[38:37] == 2'd0) begin v = v << 2; n = n + 6'd2; end
            if (v[38] == 1'b0) begin v = v << 1; n = n + 6'd1; end
            normalise_fine = {n, v[38:7]};
        end
    endfunction

    // round(log2(1 + i/64)·2¹⁶) (base) and the step to the next entry (slope).
    reg [16:0] base;
    reg [10:0] slope;
    reg [5:0] idx;
    always @* begin
        case (idx)
            6'd0: begin base = 17'd0; slope = 11'd1466; end
            6'd1: begin base = 17'd1466; slope = 11'd1443; end
            6'd2: begin base = 17'd2909; slope = 11'd1422; end
            6'd3: begin base = 17'd4331; slope = 11'd1401; end
            6'd4: begin base = 17'd5732; slope = 11'd1380; end
            6'd5: begin base = 17'd7112; slope = 11'd1361; end
            6'd6: begin base = 17'd8473; slope = 11'd1341; end
            6'd7: begin base = 17'd9814; slope = 11'd1322; end
            6'd8: begin base = 17'd11136; slope = 11'd1304; end
            6'd9: begin base = 17'd12440; slope = 11'd1287; end
            6'd10: begin base = 17'd13727; slope = 11'd1269; end
            6'd11: begin base = 17'd14996; slope = 11'd1252; end
            6'd12: begin base = 17'd16248; slope = 11'd1236; end
            6'd13: begin base = 17'd17484; slope = 11'd1220; end
            6'd14: begin base = 17'd18704; slope = 11'd1205; end
            6'd15: begin base = 17'd19909; slope = 11'd1189; end
            6'd16: begin base = 17'd21098; slope = 11'd1174; end
            6'd17: begin base = 17'd22272; slope = 11'd1161; end
            6'd18: begin base = 17'd23433; slope = 11'd1146; end
            6'd19: begin base = 17'd24579; slope = 11'd1132; end
            6'd20: begin base = 17'd25711; slope = 11'd1119; end
            6'd21: begin base = 17'd26830; slope = 11'd1106; end
            6'd22: begin base = 17'd27936; slope = 11'd1093; end
            6'd23: begin base = 17'd29029; slope = 11'd1080; end
            6'd24: begin base = 17'd30109; slope = 11'd1069; end
            6'd25: begin base = 17'd31178; slope = 11'd1056; end
            6'd26: begin base = 17'd32234; slope = 11'd1045; end
            6'd27: begin base = 17'd33279; slope = 11'd1033; end
            6'd28: begin base = 17'd34312; slope = 11'd1022; end
            6'd29: begin base = 17'd35334; slope = 11'd1012; end
            6'd30: begin base = 17'd36346; slope = 11'd1000; end
            6'd31: begin base = 17'd37346; slope = 11'd990; end
            6'd32: begin base = 17'd38336; slope = 11'd980; end
            6'd33: begin base = 17'd39316; slope = 11'd970; end
            6'd34: begin base = 17'd40286; slope = 11'd960; end
            6'd35: begin base = 17'd41246; slope = 11'd950; end
            6'd36: begin base = 17'd42196; slope = 11'd941; end
            6'd37: begin base = 17'd43137; slope = 11'd931; end
            6'd38: begin base = 17'd44068; slope = 11'd922; end
            6'd39: begin base = 17'd44990; slope = 11'd914; end
            6'd40: begin base = 17'd45904; slope = 11'd905; end
            6'd41: begin base = 17'd46809; slope = 11'd896; end
            6'd42: begin base = 17'd47705; slope = 11'd888; end
            6'd43: begin base = 17'd48593; slope = 11'd879; end
            6'd44: begin base = 17'd49472; slope = 11'd872; end
            6'd45: begin base = 17'd50344; slope = 11'd863; end
            6'd46: begin base = 17'd51207; slope = 11'd856; end
            6'd47: begin base = 17'd52063; slope = 11'd848; end
            6'd48: begin base = 17'd52911; slope = 11'd840; end
            6'd49: begin base = 17'd53751; slope = 11'd833; end
            6'd50: begin base = 17'd54584; slope = 11'd826; end
            6'd51: begin base = 17'd55410; slope = 11'd819; end
            6'd52: begin base = 17'd56229; slope = 11'd811; end
            6'd53: begin base = 17'd57040; slope = 11'd805; end
            6'd54: begin base = 17'd57845; slope = 11'd798; end
            6'd55: begin base = 17'd58643; slope = 11'd791; end
            6'd56: begin base = 17'd59434; slope = 11'd785; end
            6'd57: begin base = 17'd60219; slope = 11'd778; end
            6'd58: begin base = 17'd60997; slope = 11'd772; end
            6'd59: begin base = 17'd61769; slope = 11'd765; end
            6'd60: begin base = 17'd62534; slope = 11'd760; end
            6'd61: begin base = 17'd63294; slope = 11'd753; end
            6'd62: begin base = 17'd64047; slope = 11'd747; end
            6'd63: begin base = 17'd64794; slope = 11'd742; end
            default: begin base = 17'd0; slope = 11'd0; end
        endcase
    end

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
    reg [44:0] coarse;   // {lz so far, top 39 bits}
    reg  [5:0] lz;
    /* verilator lint_off UNUSEDSIGNAL */  // m[31] is the leading one, m[8:0] below the weight
    reg [31:0] m;
    /* verilator lint_on UNUSEDSIGNAL */

    always @* idx = m[30:25];
    wire [26:0] prod = slope * m[24:9];  // ≤ 1466·65535 < 2²⁷
    /* verilator lint_off UNUSEDSIGNAL */  // rounded away / outside the I8F8 lod
    wire [26:0] rnd = prod + 27'h8000;
    wire [31:0] log2pl = LOD_BIAS + {15'd0, base} + {21'd0, rnd[26:16]} - {10'd0, lz, 16'd0};
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
                stage  <= COARSE;
                coarse <= normalise_coarse(x);
            end else begin
                stage      <= IDLE;
                pcpi_ready <= 1'b1;
                pcpi_wr    <= 1'b1;
                pcpi_rd    <= op == 3'd1 ? lod : 32'd0;
            end
        end else if (stage == COARSE) begin
            stage   <= FINE;
            {lz, m} <= normalise_fine(coarse);
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
