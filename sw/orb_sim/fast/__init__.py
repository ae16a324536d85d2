# SPDX-License-Identifier: MIT
"""The fast simulation path (docs/fast-sim.md): GHDL's synthesised netlist of orb_accel_top in
Verilator with a C++ harness, driven from Python a frame or a bus operation at a time."""
