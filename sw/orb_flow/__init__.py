"""The design flow: synthesis estimate, timing, HDL lint, netlist simulation, board build, generators."""
