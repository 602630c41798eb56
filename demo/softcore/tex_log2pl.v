// The ACCURATE logarithm of the raymip texture co-processors (pcpi_tex.v
// on PicoRV32's PCPI port, cfu_tex.v on VexRiscv's CFU port): `tex.log2pl`,
// log2 of a U32F32 path length in I16F16 bits plus 0x80, exactly
// `biased − (lz << 16)` of the firmware's `log2_u32f32_parts`
// (src/log2/mod.rs); see pcpi_tex.v's header for the instruction.
//
// A free-running pipeline: `x` presented in cycle t is normalised in two
// registered steps (the coarse shifts 32/16/8 at the end of t, the fine
// shifts 4/2/1 at the end of t+1), and `log2pl` (table, one 11×16-bit
// multiply, adds) is valid combinationally in cycle t+2 (t+4 with
// PIPE = 1), as long as `x` was held in cycle t. The instances sample
// `log2pl` at that cycle.
`timescale 1 ns / 1 ps
`default_nettype none

module tex_log2pl #(
    // 1: two more registers for the clock (the table's outputs, then the
    // rounded product): `log2pl` is valid in cycle t+4 instead of t+2.
    parameter integer PIPE = 0
) (
    input  wire        clk,
    input  wire [63:0] x,
    output wire [31:0] log2pl
);
    localparam [31:0] LOD_BIAS = (32'd31 << 16) + 32'h80;

    // Normalisation of the 64-bit path length: six shift-if-zero steps
    // (32, 16, 8, 4, 2, 1) give the leading-zero count and the shifted
    // value together; zero gives lz = 63 and m = 0 (whose interval value
    // equals that of m = 2³¹, as in software). Two pipeline stages: the
    // coarse steps (32, 16, 8) keep the top 39 bits (the fine steps shift
    // by at most 7), the fine steps (4, 2, 1) the top 32.
    function [44:0] normalise_coarse(input [63:0] v64);
        reg [63:0] v;
        reg [5:0] n;
        begin
            v = v64;
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

    reg [44:0] coarse;   // {lz so far, top 39 bits}
    reg  [5:0] lz;
    /* verilator lint_off UNUSEDSIGNAL */  // m[31] is the leading one, m[8:0] below the weight
    reg [31:0] m;
    /* verilator lint_on UNUSEDSIGNAL */
    always @(posedge clk) begin
        coarse  <= normalise_coarse(x);
        {lz, m} <= normalise_fine(coarse);
    end

    always @* idx = m[30:25];
    generate
        if (PIPE != 0) begin : piped
            reg [16:0] base1;
            reg [10:0] slope1;
            reg [15:0] mlo1;
            reg  [5:0] lz1;
            reg [31:0] sum2;
            /* verilator lint_off UNUSEDSIGNAL */  // rounded away
            reg [26:0] rnd2;
            /* verilator lint_on UNUSEDSIGNAL */
            always @(posedge clk) begin
                base1  <= base;
                slope1 <= slope;
                mlo1   <= m[24:9];
                lz1    <= lz;
                sum2   <= LOD_BIAS + {15'd0, base1} - {10'd0, lz1, 16'd0};
                rnd2   <= slope1 * mlo1 + 27'h8000;  // ≤ 1466·65535 + 2¹⁵ < 2²⁷
            end
            assign log2pl = sum2 + {21'd0, rnd2[26:16]};
        end else begin : comb
            wire [26:0] prod = slope * m[24:9];  // ≤ 1466·65535 < 2²⁷
            /* verilator lint_off UNUSEDSIGNAL */  // rounded away
            wire [26:0] rnd = prod + 27'h8000;
            /* verilator lint_on UNUSEDSIGNAL */
            assign log2pl = LOD_BIAS + {15'd0, base} + {21'd0, rnd[26:16]} - {10'd0, lz, 16'd0};
        end
    endgenerate
endmodule

`default_nettype wire
