// SPDX-License-Identifier: MIT
// orb_accel_zynq: AXI's reset rule for the masters and the video source (assumed; the
// checkers' properties are bound by the wrapper).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  reg arn1 = 1'b0;  // aresetn a clock ago
  always @(posedge clk) arn1 <= aresetn;
  // AXI's reset rule for the masters and the video source: valids low while aresetn is low, raised only after
  // an edge that sampled it high (orb_accel_top, reset a clock longer, is still in reset at that edge)
  always @(*) if (!init && (!aresetn || !arn1))
    assume (!s_axi_ctrl_awvalid && !s_axi_ctrl_wvalid && !s_axi_ctrl_arvalid && !s_axis_video_tvalid);
