# SPDX-License-Identifier: MIT
"""Shared cocotb testbench support: runner, video driver, feature monitor, scoreboard, images."""
