// SPDX-License-Identifier: MIT
// orb_video_check: the pixel taken at the last edge (t_v, its value t_d) and
// discarded_pixels then, for the latency properties.
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  reg t_v = 0;
  reg [7:0] t_d;
  reg [31:0] disc_q = 0;
  always @(posedge clk) begin
    t_v <= s_axis_video_tvalid && s_axis_video_tready && !rst;
    t_d <= s_axis_video_tdata;
    disc_q <= discarded_pixels;
  end
