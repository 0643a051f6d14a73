"""RTL simulation: generated Verilog, cocotb testbenches on Icarus."""
