# SPDX-License-Identifier: MIT
"""The board's device, once: the XC7Z020's resources (Xilinx DS190, Zynq-7000 SoC data sheet,
table 1: 53,200 LUTs, 106,400 flip-flops, 140 36-kb block RAMs, 220 DSP48E1 slices), which the
synthesis estimate, the generated results tables and the Vivado report summary take their
percentages of."""

from __future__ import annotations

NAME = "XC7Z020"
RESOURCES = {"lut": 53200, "ff": 106400, "bram36": 140, "dsp": 220}
DEVICE = {"name": NAME, **RESOURCES}
