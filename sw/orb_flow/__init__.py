"""The design flow: lint, synthesis estimate, netlist simulation, board build, generators of the views."""
