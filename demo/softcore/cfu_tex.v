// raymip texture co-processor for VexRiscv's CFU port (the Custom Function
// Unit interface of CFU-Playground; LiteX's `full+cfu` VexRiscv variant
// instantiates a module `Cfu` with these ports). Our own RTL.
//
// The CPU sends an R-type instruction of the custom-0 opcode as
// function_id = {funct7, funct3} with the two source registers; the same
// instruction words as the PCPI unit (pcpi_tex.v, whose header specifies
// funct7 = 0), plus the addressing instructions (funct7 = 1):
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
//             rs1 = u, rs2 = v in I4F28 (the coordinate's 28 top fractional
//             bits; the integer part: ignored for wrap, `hi mod 2` for
//             mirror, the integer part clamped to [−4, 3] for the clamping
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
// Any other function id answers 0 and changes nothing (the CFU port has
// no way to refuse an instruction).
//
// Timing: every instruction is taken in the cycle cmd_valid && cmd_ready
// and answers one cycle later (rsp_valid registered), except tex.addr, two
// cycles later (the scaled positions, then the index maps and addresses),
// and tex.log2pl, three cycles later (the two normalisation steps of
// tex_log2pl.v).
// Unlike pcpi_tex.v the filter runs the four channels in parallel and
// tex.bb in one multiply level, for an FPGA with DSP blocks to spare:
// X_c = (t11_c − t01_c)·fx·fy + t01_c·fy·2¹² + top_c·(2¹² − fy), the same
// integer as pcpi_tex.v's (bot − top)·fy + top·2¹² with
// bot = (t11 − t01)·fx + t01·2¹² (expanded; every product exact); fx·fy
// is registered the cycle after tex.bw / tex.addr latch the weights.
// Every output bit is checked against vectors written by the Rust firmware
// code (tb_cfu_tex.cpp, scripts/softcore).
`timescale 1 ns / 1 ps
`default_nettype none

/* verilator lint_off DECLFILENAME */  // LiteX instantiates the CFU as `Cfu`
module Cfu (
    input  wire        clk,
    input  wire        reset,
    input  wire        cmd_valid,
    output wire        cmd_ready,
    input  wire [ 9:0] cmd_payload_function_id,
    input  wire [31:0] cmd_payload_inputs_0,
    input  wire [31:0] cmd_payload_inputs_1,
    output reg         rsp_valid,
    input  wire        rsp_ready,
    output reg  [31:0] rsp_payload_outputs_0
);
    /* verilator lint_on DECLFILENAME */
    localparam [31:0] UNTEXTURED = 32'h8000_0000;

    wire [6:0] funct7 = cmd_payload_function_id[9:3];
    wire [2:0] funct3 = cmd_payload_function_id[2:0];
    wire [31:0] a = cmd_payload_inputs_0;
    wire [31:0] b = cmd_payload_inputs_1;

    // tex.log2pl in flight: answers when `lcnt` reaches 2.
    reg  [1:0] lcnt;
    reg        lbusy;
    // A new instruction when no answer waits and no tex.log2pl or
    // tex.addr runs.
    wire       abusy_w;
    assign cmd_ready = !lbusy && !abusy_w && (!rsp_valid || rsp_ready);
    wire fire = cmd_valid && cmd_ready;

    wire [31:0] log2pl;
    tex_log2pl log2 (.clk(clk), .x({b, a}), .log2pl(log2pl));

    // tex.lod: as pcpi_tex.v.
    /* verilator lint_off UNUSEDSIGNAL */  // outside the I8F8 lod
    wire [31:0] diff = a - b;
    /* verilator lint_on UNUSEDSIGNAL */
    wire [31:0] lod = b == UNTEXTURED ? UNTEXTURED : {{16{diff[23]}}, diff[23:8]};

    // ---- The filter: four channels in parallel ------------------------
    reg  [12:0] fx, fy;
    reg  [25:0] fxy;        // fx·fy ≤ 2²⁴, registered after the weights
    reg  [79:0] top;        // tex.bt's rows, 20 bits a channel
    reg  [95:0] w0, w1;     // the last two levels' 8.16 values, 24 bits a channel
    wire [12:0] fyc = 13'd4096 - fy;

    wire [79:0] top_n;      // tex.bt of (a, b)
    wire [95:0] wide_n;     // tex.bb's 8.16 values of (a, b)
    wire [31:0] round_n;    // tex.bb's rounded texel
    wire [31:0] blend_n;    // tex.blend of w0, w1 with t = a[8:0]
    genvar c;
    generate
        for (c = 0; c < 4; c = c + 1) begin : ch
            wire [7:0] t00 = a[8*c+7:8*c], t10 = b[8*c+7:8*c];
            // tex.bt: (t10 − t00)·fx + t00·2¹² ∈ [0, 255·2¹²].
            wire signed [9:0] dx = $signed({2'd0, t10}) - $signed({2'd0, t00});
            wire signed [23:0] ph = dx * $signed({1'b0, fx});
            /* verilator lint_off UNUSEDSIGNAL */  // th < 2²⁰
            wire [23:0] th = ph + {4'd0, t00, 12'd0};
            /* verilator lint_on UNUSEDSIGNAL */
            assign top_n[20*c+19:20*c] = th[19:0];
            // tex.bb: a = t01, b = t11.
            wire [7:0] t01 = a[8*c+7:8*c], t11 = b[8*c+7:8*c];
            wire signed [9:0] dy = $signed({2'd0, t11}) - $signed({2'd0, t01});
            wire signed [35:0] p1 = dy * $signed({1'b0, fxy});
            /* verilator lint_off UNUSEDSIGNAL */  // p2 < 2²⁰
            wire [35:0] p2 = {28'd0, t01} * {23'd0, fy};
            /* verilator lint_on UNUSEDSIGNAL */
            wire [35:0] p3 = {16'd0, top[20*c+19:20*c]} * {23'd0, fyc};
            /* verilator lint_off UNUSEDSIGNAL */  // X < 2³², the sums' top bits are zero
            wire [35:0] x = p1 + {p2[23:0], 12'd0} + p3;
            wire [31:0] ws = x[31:0] + 32'd128;
            wire [23:0] wr = ws[31:8] + 24'h8000;
            /* verilator lint_on UNUSEDSIGNAL */
            assign wide_n[24*c+23:24*c] = ws[31:8];
            assign round_n[8*c+7:8*c] = wr[23:16];
            // tex.blend: ((w1 − w0)·t + w0·2⁸ + 2²³) >> 24.
            wire [23:0] v0 = w0[24*c+23:24*c], v1 = w1[24*c+23:24*c];
            wire signed [24:0] dw = $signed({1'b0, v1}) - $signed({1'b0, v0});
            wire signed [35:0] pb = dw * $signed({1'b0, a[8:0]});
            /* verilator lint_off UNUSEDSIGNAL */
            wire [35:0] bs = pb + {4'd0, v0, 8'd0} + 36'h80_0000;
            /* verilator lint_on UNUSEDSIGNAL */
            assign blend_n[8*c+7:8*c] = bs[31:24];
        end
    endgenerate

    // ---- Addressing ---------------------------------------------------
    reg [31:0] base;
    reg  [3:0] kx, ky;
    reg  [1:0] mu, mv;
    reg [31:0] a10, a01, a11;

    // Texel index `i` of an axis of 2^k texels in `mode` (see the header).
    function [15:0] mapi(input [31:0] i, input [3:0] k, input [1:0] mode);
        reg [31:0] mx, m, r;
        /* verilator lint_off UNUSEDSIGNAL */  // o < 2¹⁵
        reg [31:0] o;
        /* verilator lint_on UNUSEDSIGNAL */
        begin
            mx = (32'd1 << k) - 32'd1;
            m = i & ((mx << 1) | 32'd1);
            r = i ^ {32{i[31]}};
            case (mode)
                2'd0: o = i & mx;
                2'd1: o = (m & mx) ^ (m[{1'b0, k}] ? mx : 32'd0);
                2'd2: o = i[31] ? 32'd0 : i > mx ? mx : i;
                default: o = r > mx ? mx : r;
            endcase
            mapi = o[15:0];
        end
    endfunction

    // One axis of tex.addr: the first tap's scaled position `i` (32-bit
    // two's complement) and the weight `f` of coordinate `q` (I4F28).
    function [43:0] scaled(input [31:0] q, input [3:0] k, input [1:0] mode);
        /* verilator lint_off UNUSEDSIGNAL */  // p[19:0]: below the weight
        reg [63:0] p;
        /* verilator lint_on UNUSEDSIGNAL */
        reg [31:0] hi;
        begin
            p = ({36'd0, q[27:0]} << ({1'b0, k} + 5'd4)) + 64'h0000_0000_0008_0000 - 64'h0000_0000_8000_0000;
            hi = mode == 2'd0 ? 32'd0 : mode == 2'd1 ? {31'd0, q[28]} : {{28{q[31]}}, q[31:28]};
            scaled = {p[63:32] + (hi << k), p[31:20]};
        end
    endfunction

    // tex.addr in two registered steps: the scaled positions and weights
    // of the operands, then the index maps and the addresses.
    wire [43:0] sx = scaled(a, kx, mu), sy = scaled(b, ky, mv);
    reg  [31:0] ix, iy;
    reg  [11:0] wx, wy;
    reg         abusy;
    assign abusy_w = abusy;
    wire [15:0] x0 = mapi(ix, kx, mu), x1 = mapi(ix + 32'd1, kx, mu);
    wire [15:0] y0 = mapi(iy, ky, mv), y1 = mapi(iy + 32'd1, ky, mv);
    // base + 4·(y·2^kx + x): the index has at most 30 bits (kx + ky ≤ 30).
    function [31:0] texel(input [15:0] x, input [15:0] y);
        texel = base + ({16'd0, y} << (kx + 5'd2)) + {14'd0, x, 2'd0};
    endfunction

    // ---- The answers --------------------------------------------------
    always @(posedge clk) begin
        fxy <= fx * fy;
        if (rsp_valid && rsp_ready) rsp_valid <= 1'b0;
        if (abusy) begin
            abusy                 <= 1'b0;
            fx                    <= {1'b0, wx};
            fy                    <= {1'b0, wy};
            a10                   <= texel(x1, y0);
            a01                   <= texel(x0, y1);
            a11                   <= texel(x1, y1);
            rsp_valid             <= 1'b1;
            rsp_payload_outputs_0 <= texel(x0, y0);
        end
        if (lbusy) begin
            lcnt <= lcnt + 2'd1;
            if (lcnt == 2'd1) begin
                lbusy                 <= 1'b0;
                rsp_valid             <= 1'b1;
                rsp_payload_outputs_0 <= log2pl;
            end
        end
        if (fire) begin
            rsp_valid             <= !(funct7 == 7'd0 && funct3 == 3'd0) && !(funct7 == 7'd1 && funct3 == 3'd1);
            rsp_payload_outputs_0 <= 32'd0;
            if (funct7 == 7'd0) begin
                case (funct3)
                    3'd0: begin
                        lbusy <= 1'b1;
                        lcnt  <= 2'd0;
                    end
                    3'd1: rsp_payload_outputs_0 <= lod;
                    3'd2: begin
                        fx <= a[12:0];
                        fy <= b[12:0];
                    end
                    3'd3: top <= top_n;
                    3'd4: begin
                        rsp_payload_outputs_0 <= round_n;
                        w0 <= w1;
                        w1 <= wide_n;
                    end
                    3'd5: rsp_payload_outputs_0 <= blend_n;
                    default: ;
                endcase
            end else if (funct7 == 7'd1) begin
                case (funct3)
                    3'd0: begin
                        base <= a;
                        kx   <= b[3:0];
                        ky   <= b[7:4];
                        mu   <= b[9:8];
                        mv   <= b[11:10];
                    end
                    3'd1: begin
                        abusy <= 1'b1;
                        ix    <= sx[43:12];
                        iy    <= sy[43:12];
                        wx    <= sx[11:0];
                        wy    <= sy[11:0];
                    end
                    3'd2: rsp_payload_outputs_0 <= a10;
                    3'd3: rsp_payload_outputs_0 <= a01;
                    3'd4: rsp_payload_outputs_0 <= a11;
                    default: ;
                endcase
            end
        end
        if (reset) begin
            rsp_valid <= 1'b0;
            lbusy     <= 1'b0;
            abusy     <= 1'b0;
        end
    end
endmodule

`default_nettype wire
