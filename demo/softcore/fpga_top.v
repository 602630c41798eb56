// FPGA top level of the raymip soft-core SoC for the area and clock figures
// of scripts/fpga (issue 23): soc.v with its console, exit and fault
// signals reduced to the pins a 48-pin iCE40 UP5K package offers. The core,
// the co-processor (ENABLE_TEX) and the RAM are those the Verilator runs
// use; only the RAM size differs (soc's RAM_BYTES, which scripts/fpga sets
// with ENABLE_TEX on soc itself: the SoC's 128 KiB would be the UP5K's four
// SPRAM blocks, which Yosys 0.23 does not infer, so the flow maps a smaller
// RAM to block RAM).
`timescale 1 ns / 1 ps
`default_nettype none

module fpga_top (
    input  wire       clk,
    input  wire       resetn,
    output wire       trap,
    output wire       con_valid,
    output wire [7:0] con_byte,
    output wire       exit_valid,
    output wire       exit_nonzero,
    output wire       fault
);
    wire [31:0] exit_code;
    wire [31:0] fault_addr;
    assign exit_nonzero = |exit_code;

    soc soc (
        .clk(clk),
        .resetn(resetn),
        .trap(trap),
        .con_valid(con_valid),
        .con_byte(con_byte),
        .exit_valid(exit_valid),
        .exit_code(exit_code),
        .fault(fault),
        .fault_addr(fault_addr)
    );
endmodule

`default_nettype wire
