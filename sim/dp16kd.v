// A 4-state simulation model of the Lattice ECP5 DP16KD block RAM (18 kbit, true dual port),
// covering the subset that dptbd's gateware instantiates (hw/dp16kd.py) and refusing every
// other parameter value with $fatal at time 0 (Icarus 11 has no elaboration-time $fatal).
// Shipped with dptbd (dptbd.sim.cell_models finds it); the Yosys ECP5 cell library has
// DP16KD as a blackbox only.
//
// Semantics followed: Lattice, "ECP5 and ECP5-5G Memory Usage Guide", Technical Note
// FPGA-TN-02204 (formerly TN1264), sysMEM EBR, "True Dual Port RAM" (DP16KD): a synchronous
// port per side; CEx enables the port's clock (the write, and the read into the array's
// output latch), OCEx enables the output register (REGMODE_x = "OUTREG"), which loads the
// latch's word; WRITEMODE "NORMAL": a write leaves its own port's output unchanged;
// RSTx clears the output latch and register synchronously (RESETMODE "SYNC"); CSDECODE_x
// "0b000" selects the port when CSx[2:0] = 000.
//
// The subset (anything else is refused):
//   DATA_WIDTH_A = DATA_WIDTH_B in {18, 9, 4, 2, 1}: 1024 x 18 … 16384 x 1; the word address
//     is ADx[13:k], k = 4, 3, 2, 1, 0; at 18 bits ADA[1:0] are the write's byte enables
//     (ADA0: DIA[8:0], ADA1: DIA[17:9]), as Yosys maps them;
//   REGMODE_A "NOREG"; REGMODE_B "NOREG" or "OUTREG"; WRITEMODE_A/B "NORMAL";
//   RESETMODE "SYNC", ASYNC_RESET_RELEASE "SYNC"; CSDECODE_A/B "0b000"; GSR "DISABLED";
//   port B never writes (WEB = 1 with CEB is a $fatal at that edge);
//   INITVAL_00 … INITVAL_3F only at 18 bits, in Yosys's layout (brams_map_16kd.v: the
//     18-bit word 16 n + i in bits [20 i + 17 : 20 i] of INITVAL_n).
//
// 4-state, strict: every array word is X until written (or given by an INITVAL_nn; an
// INITVAL_nn not given leaves its 16 words X), and the output latches and registers are X
// until first loaded (GSR "DISABLED"). On the chip the array starts as the bitstream loads
// it (zeros when not initialised) and the registers at their configuration value; a design
// that must not depend on those values sees X here when it reads a word it has not written
// or an output register before its first load. An X or Z on an enable, a select or an address makes the affected word (the whole
// array for a write address) X. CLKA and CLKB must be one clock (hw/dp16kd.py connects both
// to the domain's; otherwise a $fatal at a CLKB edge). A read on port B of the word that
// port A writes at the same edge reads X: the strict choice (the behavioural DP16KD reads
// the word before the write), so a design that passes never depends on that collision.
`timescale 1ns/1ps
module DP16KD (
  input DIA17, DIA16, DIA15, DIA14, DIA13, DIA12, DIA11, DIA10, DIA9, DIA8, DIA7, DIA6, DIA5, DIA4, DIA3, DIA2, DIA1, DIA0,
  input ADA13, ADA12, ADA11, ADA10, ADA9, ADA8, ADA7, ADA6, ADA5, ADA4, ADA3, ADA2, ADA1, ADA0,
  input CEA, OCEA, CLKA, WEA, RSTA, CSA2, CSA1, CSA0,
  output DOA17, DOA16, DOA15, DOA14, DOA13, DOA12, DOA11, DOA10, DOA9, DOA8, DOA7, DOA6, DOA5, DOA4, DOA3, DOA2, DOA1, DOA0,
  input DIB17, DIB16, DIB15, DIB14, DIB13, DIB12, DIB11, DIB10, DIB9, DIB8, DIB7, DIB6, DIB5, DIB4, DIB3, DIB2, DIB1, DIB0,
  input ADB13, ADB12, ADB11, ADB10, ADB9, ADB8, ADB7, ADB6, ADB5, ADB4, ADB3, ADB2, ADB1, ADB0,
  input CEB, OCEB, CLKB, WEB, RSTB, CSB2, CSB1, CSB0,
  output DOB17, DOB16, DOB15, DOB14, DOB13, DOB12, DOB11, DOB10, DOB9, DOB8, DOB7, DOB6, DOB5, DOB4, DOB3, DOB2, DOB1, DOB0
);
  localparam [319:0] UNSET = {320{1'bx}};
  parameter DATA_WIDTH_A = 18;
  parameter DATA_WIDTH_B = 18;
  parameter REGMODE_A = "NOREG";
  parameter REGMODE_B = "NOREG";
  parameter RESETMODE = "SYNC";
  parameter ASYNC_RESET_RELEASE = "SYNC";
  parameter CSDECODE_A = "0b000";
  parameter CSDECODE_B = "0b000";
  parameter WRITEMODE_A = "NORMAL";
  parameter WRITEMODE_B = "NORMAL";
  parameter GSR = "DISABLED";
  parameter [319:0] INITVAL_00 = UNSET, INITVAL_01 = UNSET, INITVAL_02 = UNSET, INITVAL_03 = UNSET;
  parameter [319:0] INITVAL_04 = UNSET, INITVAL_05 = UNSET, INITVAL_06 = UNSET, INITVAL_07 = UNSET;
  parameter [319:0] INITVAL_08 = UNSET, INITVAL_09 = UNSET, INITVAL_0A = UNSET, INITVAL_0B = UNSET;
  parameter [319:0] INITVAL_0C = UNSET, INITVAL_0D = UNSET, INITVAL_0E = UNSET, INITVAL_0F = UNSET;
  parameter [319:0] INITVAL_10 = UNSET, INITVAL_11 = UNSET, INITVAL_12 = UNSET, INITVAL_13 = UNSET;
  parameter [319:0] INITVAL_14 = UNSET, INITVAL_15 = UNSET, INITVAL_16 = UNSET, INITVAL_17 = UNSET;
  parameter [319:0] INITVAL_18 = UNSET, INITVAL_19 = UNSET, INITVAL_1A = UNSET, INITVAL_1B = UNSET;
  parameter [319:0] INITVAL_1C = UNSET, INITVAL_1D = UNSET, INITVAL_1E = UNSET, INITVAL_1F = UNSET;
  parameter [319:0] INITVAL_20 = UNSET, INITVAL_21 = UNSET, INITVAL_22 = UNSET, INITVAL_23 = UNSET;
  parameter [319:0] INITVAL_24 = UNSET, INITVAL_25 = UNSET, INITVAL_26 = UNSET, INITVAL_27 = UNSET;
  parameter [319:0] INITVAL_28 = UNSET, INITVAL_29 = UNSET, INITVAL_2A = UNSET, INITVAL_2B = UNSET;
  parameter [319:0] INITVAL_2C = UNSET, INITVAL_2D = UNSET, INITVAL_2E = UNSET, INITVAL_2F = UNSET;
  parameter [319:0] INITVAL_30 = UNSET, INITVAL_31 = UNSET, INITVAL_32 = UNSET, INITVAL_33 = UNSET;
  parameter [319:0] INITVAL_34 = UNSET, INITVAL_35 = UNSET, INITVAL_36 = UNSET, INITVAL_37 = UNSET;
  parameter [319:0] INITVAL_38 = UNSET, INITVAL_39 = UNSET, INITVAL_3A = UNSET, INITVAL_3B = UNSET;
  parameter [319:0] INITVAL_3C = UNSET, INITVAL_3D = UNSET, INITVAL_3E = UNSET, INITVAL_3F = UNSET;

  // the array's width (a width outside the subset builds 18 and is refused at time 0)
  localparam integer W = DATA_WIDTH_A == 9 || DATA_WIDTH_A == 4 || DATA_WIDTH_A == 2
                        || DATA_WIDTH_A == 1 ? DATA_WIDTH_A : 18;
  localparam integer LSB = W == 18 ? 4 : W == 9 ? 3 : W == 4 ? 2 : W == 2 ? 1 : 0;
  localparam integer DEPTH = 16384 >> LSB;

  reg [W-1:0] mem [0:DEPTH-1];
  reg [W-1:0] latch_a, latch_b, out_b;       // X until first loaded: no GSR

  wire [17:0] dia = {DIA17, DIA16, DIA15, DIA14, DIA13, DIA12, DIA11, DIA10, DIA9, DIA8, DIA7, DIA6, DIA5, DIA4, DIA3, DIA2, DIA1, DIA0};
  wire [13:0] ada = {ADA13, ADA12, ADA11, ADA10, ADA9, ADA8, ADA7, ADA6, ADA5, ADA4, ADA3, ADA2, ADA1, ADA0};
  wire [13:0] adb = {ADB13, ADB12, ADB11, ADB10, ADB9, ADB8, ADB7, ADB6, ADB5, ADB4, ADB3, ADB2, ADB1, ADB0};
  wire [13-LSB:0] word_a = ada[13:LSB];
  wire [13-LSB:0] word_b = adb[13:LSB];
  wire [1:0] byte_en = W == 18 ? ada[1:0] : 2'b11;
  wire sel_a = {CSA2, CSA1, CSA0} == 3'b000;
  wire sel_b = {CSB2, CSB1, CSB0} == 3'b000;
  wire [W-1:0] dob = REGMODE_B == "OUTREG" ? out_b : latch_b;
  wire [17:0] doa_pins, dob_pins;          // the pins above W bits carry X
  assign {DOA17, DOA16, DOA15, DOA14, DOA13, DOA12, DOA11, DOA10, DOA9, DOA8, DOA7, DOA6, DOA5, DOA4, DOA3, DOA2, DOA1, DOA0} = doa_pins;
  assign {DOB17, DOB16, DOB15, DOB14, DOB13, DOB12, DOB11, DOB10, DOB9, DOB8, DOB7, DOB6, DOB5, DOB4, DOB3, DOB2, DOB1, DOB0} = dob_pins;
  generate if (W == 18) begin : full
    assign doa_pins = latch_a;
    assign dob_pins = dob;
  end else begin : narrow
    assign doa_pins = {{(18 - W){1'bx}}, latch_a};
    assign dob_pins = {{(18 - W){1'bx}}, dob};
  end endgenerate

  function [319:0] initval(input integer n);
    case (n)
      'h00: initval = INITVAL_00; 'h01: initval = INITVAL_01;
      'h02: initval = INITVAL_02; 'h03: initval = INITVAL_03;
      'h04: initval = INITVAL_04; 'h05: initval = INITVAL_05;
      'h06: initval = INITVAL_06; 'h07: initval = INITVAL_07;
      'h08: initval = INITVAL_08; 'h09: initval = INITVAL_09;
      'h0A: initval = INITVAL_0A; 'h0B: initval = INITVAL_0B;
      'h0C: initval = INITVAL_0C; 'h0D: initval = INITVAL_0D;
      'h0E: initval = INITVAL_0E; 'h0F: initval = INITVAL_0F;
      'h10: initval = INITVAL_10; 'h11: initval = INITVAL_11;
      'h12: initval = INITVAL_12; 'h13: initval = INITVAL_13;
      'h14: initval = INITVAL_14; 'h15: initval = INITVAL_15;
      'h16: initval = INITVAL_16; 'h17: initval = INITVAL_17;
      'h18: initval = INITVAL_18; 'h19: initval = INITVAL_19;
      'h1A: initval = INITVAL_1A; 'h1B: initval = INITVAL_1B;
      'h1C: initval = INITVAL_1C; 'h1D: initval = INITVAL_1D;
      'h1E: initval = INITVAL_1E; 'h1F: initval = INITVAL_1F;
      'h20: initval = INITVAL_20; 'h21: initval = INITVAL_21;
      'h22: initval = INITVAL_22; 'h23: initval = INITVAL_23;
      'h24: initval = INITVAL_24; 'h25: initval = INITVAL_25;
      'h26: initval = INITVAL_26; 'h27: initval = INITVAL_27;
      'h28: initval = INITVAL_28; 'h29: initval = INITVAL_29;
      'h2A: initval = INITVAL_2A; 'h2B: initval = INITVAL_2B;
      'h2C: initval = INITVAL_2C; 'h2D: initval = INITVAL_2D;
      'h2E: initval = INITVAL_2E; 'h2F: initval = INITVAL_2F;
      'h30: initval = INITVAL_30; 'h31: initval = INITVAL_31;
      'h32: initval = INITVAL_32; 'h33: initval = INITVAL_33;
      'h34: initval = INITVAL_34; 'h35: initval = INITVAL_35;
      'h36: initval = INITVAL_36; 'h37: initval = INITVAL_37;
      'h38: initval = INITVAL_38; 'h39: initval = INITVAL_39;
      'h3A: initval = INITVAL_3A; 'h3B: initval = INITVAL_3B;
      'h3C: initval = INITVAL_3C; 'h3D: initval = INITVAL_3D;
      'h3E: initval = INITVAL_3E; 'h3F: initval = INITVAL_3F;
      default: initval = UNSET;
    endcase
  endfunction

  integer n, i;
  reg [319:0] slice;
  initial begin
    if (DATA_WIDTH_A != 18 && DATA_WIDTH_A != 9 && DATA_WIDTH_A != 4 && DATA_WIDTH_A != 2
        && DATA_WIDTH_A != 1)
      $fatal(1, "DP16KD %m: DATA_WIDTH_A must be one of 18, 9, 4, 2, 1, got %0d",
             DATA_WIDTH_A);
    if (DATA_WIDTH_B != DATA_WIDTH_A)
      $fatal(1, "DP16KD %m: DATA_WIDTH_B must equal DATA_WIDTH_A (%0d), got %0d",
             DATA_WIDTH_A, DATA_WIDTH_B);
    if (REGMODE_A != "NOREG")
      $fatal(1, "DP16KD %m: REGMODE_A must be \"NOREG\", got \"%0s\"", REGMODE_A);
    if (REGMODE_B != "NOREG" && REGMODE_B != "OUTREG")
      $fatal(1, "DP16KD %m: REGMODE_B must be \"NOREG\" or \"OUTREG\", got \"%0s\"",
             REGMODE_B);
    if (WRITEMODE_A != "NORMAL")
      $fatal(1, "DP16KD %m: WRITEMODE_A must be \"NORMAL\", got \"%0s\"", WRITEMODE_A);
    if (WRITEMODE_B != "NORMAL")
      $fatal(1, "DP16KD %m: WRITEMODE_B must be \"NORMAL\", got \"%0s\"", WRITEMODE_B);
    if (RESETMODE != "SYNC")
      $fatal(1, "DP16KD %m: RESETMODE must be \"SYNC\", got \"%0s\"", RESETMODE);
    if (ASYNC_RESET_RELEASE != "SYNC")
      $fatal(1, "DP16KD %m: ASYNC_RESET_RELEASE must be \"SYNC\", got \"%0s\"",
             ASYNC_RESET_RELEASE);
    if (CSDECODE_A != "0b000")
      $fatal(1, "DP16KD %m: CSDECODE_A must be \"0b000\", got \"%0s\"", CSDECODE_A);
    if (CSDECODE_B != "0b000")
      $fatal(1, "DP16KD %m: CSDECODE_B must be \"0b000\", got \"%0s\"", CSDECODE_B);
    if (GSR != "DISABLED")
      $fatal(1, "DP16KD %m: GSR must be \"DISABLED\", got \"%0s\"", GSR);
    for (n = 0; n < 64; n = n + 1) begin
      slice = initval(n);
      if (^slice !== 1'bx) begin
        if (W != 18)
          $fatal(1, "DP16KD %m: INITVAL_%h is modelled at DATA_WIDTH_A 18 only, got %0d",
                 n[7:0], W);
        for (i = 0; i < 16; i = i + 1) mem[16 * n + i] = slice[20 * i +: 18];
      end
    end
  end

  // Port A: the write (byte enables at 18 bits) and, on an edge without one, the read
  // into latch_a (WRITEMODE "NORMAL").
  always @(posedge CLKA) begin
    if (RSTA !== 1'b0) latch_a <= RSTA === 1'b1 ? {W{1'b0}} : {W{1'bx}};
    else if (CEA === 1'b1 && sel_a === 1'b1 && WEA === 1'b0) latch_a <= mem[word_a];
    else if (!(CEA === 1'b0 || sel_a === 1'b0 || WEA === 1'b1)) latch_a <= {W{1'bx}};
    if (CEA === 1'b1 && sel_a === 1'b1 && WEA === 1'b1 && ^word_a !== 1'bx)
      mem[word_a] <= write_word(mem[word_a], byte_en, dia[W-1:0]);
    else if (!(CEA === 1'b0 || sel_a === 1'b0 || WEA === 1'b0)) begin
      if (^word_a === 1'bx) for (i = 0; i < DEPTH; i = i + 1) mem[i] <= {W{1'bx}};
      else mem[word_a] <= {W{1'bx}};
    end
  end

  function [W-1:0] write_word(input [W-1:0] old, input [1:0] enables, input [W-1:0] data);
    integer b;
    begin
      write_word = data;
      if (W == 18)
        for (b = 0; b < 18; b = b + 1)
          write_word[b] = enables[b / 9] === 1'b1 ? data[b]
                          : enables[b / 9] === 1'b0 ? old[b] : 1'bx;
    end
  endfunction

  // Port B: CEB loads latch_b with the addressed word, OCEB loads out_b with latch_b (its
  // value before this edge), both at the same edge.
  wire writing_a = CEA === 1'b1 && sel_a === 1'b1 && WEA !== 1'b0;
  wire collision = writing_a && (word_a === word_b || ^word_a === 1'bx);
  always @(posedge CLKB) begin
    if (CLKA !== CLKB)
      $fatal(1, "DP16KD %m: CLKA and CLKB must be one clock, CLKA = %b at a CLKB edge", CLKA);
    if (CEB === 1'b1 && sel_b === 1'b1 && WEB !== 1'b0)
      $fatal(1, "DP16KD %m: port B writes are not modelled (WEB = %b with CEB = 1)", WEB);
    if (RSTB !== 1'b0) begin
      latch_b <= RSTB === 1'b1 ? {W{1'b0}} : {W{1'bx}};
      out_b <= RSTB === 1'b1 ? {W{1'b0}} : {W{1'bx}};
    end else begin
      if (CEB === 1'b1 && sel_b === 1'b1) latch_b <= collision ? {W{1'bx}} : mem[word_b];
      else if (!(CEB === 1'b0 || sel_b === 1'b0)) latch_b <= {W{1'bx}};
      if (OCEB === 1'b1) out_b <= latch_b;
      else if (OCEB !== 1'b0) out_b <= {W{1'bx}};
    end
  end
endmodule
