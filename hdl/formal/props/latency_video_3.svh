// SPDX-License-Identifier: MIT
// Fixed latency 3 of a 24-bit video stream with the sink always ready (`latency`):
// every beat taken on s_axis_video is on m_axis_video 3 clocks later, in order, with its tuser and tlast.
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  reg [3:1] t_v = 0, t_u = 0, t_l = 0;  // the input taken 1 .. 3 edges ago
  reg [23:0] t_d [1:3];
  integer i;
  always @(posedge clk) begin
    for (i = 3; i > 1; i = i - 1) begin
      t_v[i] <= t_v[i - 1]; t_u[i] <= t_u[i - 1]; t_l[i] <= t_l[i - 1]; t_d[i] <= t_d[i - 1];
    end
    t_v[1] <= s_axis_video_tvalid && s_axis_video_tready && !rst;
    t_u[1] <= s_axis_video_tuser; t_l[1] <= s_axis_video_tlast; t_d[1] <= s_axis_video_tdata;
    if (rst) t_v <= 0;
  end
  wire [23:0] t_data = t_d[3];
  always @(*) if (!init && !rst)
    latency: assert (m_axis_video_tvalid == t_v[3] && (!m_axis_video_tvalid || (m_axis_video_tuser == t_u[3] && m_axis_video_tlast == t_l[3] && (1'b1))));
