// raymip soft-core test SoC: PicoRV32 (RV32IMC) + one on-chip RAM + a
// memory-mapped console and exit register. Simulated by Verilator with the
// C++ driver sim.cpp (scripts/softcore builds and runs it).
//
// Parameter ENABLE_TEX = 1 adds the texture co-processor (pcpi_tex.v,
// custom-0 instructions) on the PCPI port; 0 (default) is the plain core.
//
// Core configuration (issue 15): RV32IMC, ENABLE_FAST_MUL (single-cycle
// multiplier, DSP blocks on an FPGA), ENABLE_DIV, BARREL_SHIFTER,
// COMPRESSED_ISA, ENABLE_COUNTERS (+ 64-bit: rdcycle[h], rdinstret[h]). No
// interrupts. Illegal instructions (any CSR other than the counters,
// including riscv-rt's mtvec/mie writes unless disabled), misaligned
// accesses and ebreak stop the core: the `trap` output.
//
// Memory map:
//   0x0000_0000 .. RAM_BYTES  RAM, code and data (reset vector at 0). One
//                             block RAM with a registered read port: the
//                             request is taken in cycle t, data and ready
//                             come in t+1 (as a synchronous FPGA block RAM
//                             delivers them; no further wait states).
//   0x1000_0000               console: a byte write prints the low byte.
//   0x1000_0004               exit: a write ends the simulation with the
//                             written value as exit code.
//   anything else             bus fault: the simulation stops (fault output).
`timescale 1 ns / 1 ps
`default_nettype none

module soc #(
    // 256 KiB for the Verilator runs: the demo fits in 128 KiB (the four
    // SPRAM blocks of an iCE40 UP5K), the measurement binaries with every
    // sampler of the matrix and their inputs on the stack do not. FPGA
    // synthesis sets its own size (scripts/fpga). memory.x next to this
    // file must state the same length.
    parameter integer RAM_BYTES = 256 * 1024,
    // 1: the texture co-processor pcpi_tex.v on the core's PCPI port
    // (ENABLE_PCPI; custom-0 instructions tex.log2pl and tex.lod, issue
    // 23). 0: the plain core, no PCPI logic.
    parameter integer ENABLE_TEX = 0
) (
    input  wire        clk,
    input  wire        resetn,
    output wire        trap,
    output reg         con_valid,
    output reg  [ 7:0] con_byte,
    output reg         exit_valid,
    output reg  [31:0] exit_code,
    output reg         fault,
    output reg  [31:0] fault_addr
);
    localparam integer RAM_WORDS = RAM_BYTES / 4;
    localparam [31:0] CONSOLE = 32'h1000_0000;
    localparam [31:0] EXIT = 32'h1000_0004;

    wire        mem_valid;
    wire        mem_instr;
    reg         mem_ready;
    wire [31:0] mem_addr;
    wire [31:0] mem_wdata;
    wire [ 3:0] mem_wstrb;
    reg  [31:0] mem_rdata;

    wire        pcpi_valid;
    wire [31:0] pcpi_insn;
    wire [31:0] pcpi_rs1;
    wire [31:0] pcpi_rs2;
    wire        pcpi_wr;
    wire [31:0] pcpi_rd;
    wire        pcpi_wait;
    wire        pcpi_ready;

    picorv32 #(
        .ENABLE_PCPI(ENABLE_TEX),
        .ENABLE_COUNTERS(1),
        .ENABLE_COUNTERS64(1),
        .ENABLE_REGS_16_31(1),
        .ENABLE_REGS_DUALPORT(1),
        .BARREL_SHIFTER(1),
        .COMPRESSED_ISA(1),
        .ENABLE_MUL(0),
        .ENABLE_FAST_MUL(1),
        .ENABLE_DIV(1),
        .ENABLE_IRQ(0),
        .CATCH_MISALIGN(1),
        .CATCH_ILLINSN(1),
        .PROGADDR_RESET(32'h0000_0000)
    ) cpu (
        .clk(clk),
        .resetn(resetn),
        .trap(trap),
        .mem_valid(mem_valid),
        .mem_instr(mem_instr),
        .mem_ready(mem_ready),
        .mem_addr(mem_addr),
        .mem_wdata(mem_wdata),
        .mem_wstrb(mem_wstrb),
        .mem_rdata(mem_rdata),
        .mem_la_read(),
        .mem_la_write(),
        .mem_la_addr(),
        .mem_la_wdata(),
        .mem_la_wstrb(),
        .pcpi_valid(pcpi_valid),
        .pcpi_insn(pcpi_insn),
        .pcpi_rs1(pcpi_rs1),
        .pcpi_rs2(pcpi_rs2),
        .pcpi_wr(pcpi_wr),
        .pcpi_rd(pcpi_rd),
        .pcpi_wait(pcpi_wait),
        .pcpi_ready(pcpi_ready),
        .irq(32'b0),
        .eoi(),
        .trace_valid(),
        .trace_data()
    );

    generate
        if (ENABLE_TEX != 0) begin : tex
            // Its ports are clk, resetn and the core's PCPI wires, of the
            // same names here (SystemVerilog `.*`).
            pcpi_tex cop (.*);
        end else begin : no_tex
            assign pcpi_wr = 1'b0;
            assign pcpi_rd = 32'b0;
            assign pcpi_wait = 1'b0;
            assign pcpi_ready = 1'b0;
        end
    endgenerate

    // The RAM; sim.cpp loads the firmware image into it before reset ends.
    reg [31:0] ram[0:RAM_WORDS-1] /*verilator public*/;

    wire in_ram = mem_addr < RAM_BYTES;
    wire [31:0] word = mem_addr >> 2;

    always @(posedge clk) begin
        mem_ready  <= 1'b0;
        con_valid  <= 1'b0;
        exit_valid <= 1'b0;
        if (!resetn) begin
            fault <= 1'b0;
        end else if (mem_valid && !mem_ready) begin
            mem_ready <= 1'b1;
            mem_rdata <= 32'b0;
            if (in_ram) begin
                mem_rdata <= ram[word];
                if (mem_wstrb[0]) ram[word][ 7: 0] <= mem_wdata[ 7: 0];
                if (mem_wstrb[1]) ram[word][15: 8] <= mem_wdata[15: 8];
                if (mem_wstrb[2]) ram[word][23:16] <= mem_wdata[23:16];
                if (mem_wstrb[3]) ram[word][31:24] <= mem_wdata[31:24];
            end else if (mem_addr == CONSOLE && mem_wstrb != 4'b0) begin
                con_valid <= 1'b1;
                con_byte  <= mem_wdata[7:0];
            end else if (mem_addr == EXIT && mem_wstrb != 4'b0) begin
                exit_valid <= 1'b1;
                exit_code  <= mem_wdata;
            end else begin
                fault      <= 1'b1;
                fault_addr <= mem_addr;
            end
        end
    end
endmodule

`default_nettype wire
