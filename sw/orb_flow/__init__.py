"""The design flow of the ORB accelerator: lint, synthesis, netlist simulation, board build, generators."""
