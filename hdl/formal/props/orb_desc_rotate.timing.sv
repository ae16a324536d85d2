// SPDX-License-Identifier: MIT
// orb_desc_rotate.timing: `rate` and `latency` (DESC_ROTATE_LAT_c = 1, the
// descriptor's orbits rotated by the sector), the sink always ready.
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  always @(*) if (!init) assume (m_axis_feat_tready);
  always @(*) if (!init && !rst && !rst_q) rate: assert (s_axis_feat_tready);
  function [255:0] rot16(input [255:0] d, input [3:0] sh);
    integer j;
    reg [31:0] two;
    begin
      for (j = 0; j < 16; j = j + 1) begin
        two = {d[16 * j +: 16], d[16 * j +: 16]} >> sh;
        rot16[16 * j +: 16] = two[15:0];
      end
    end
  endfunction
  wire [255:0] want_desc = m_axis_feat_tlast ? t_data[319:64] : rot16(t_data[319:64], t_data[43:40]);
  reg [1:1] t_v = 0, t_u = 0, t_l = 0;  // the input taken 1 .. 1 edges ago
  reg [351:0] t_d [1:1];
  integer i;
  always @(posedge clk) begin
    for (i = 1; i > 1; i = i - 1) begin
      t_v[i] <= t_v[i - 1]; t_u[i] <= t_u[i - 1]; t_l[i] <= t_l[i - 1]; t_d[i] <= t_d[i - 1];
    end
    t_v[1] <= s_axis_feat_tvalid && s_axis_feat_tready && !rst;
    t_u[1] <= 1'b0; t_l[1] <= s_axis_feat_tlast; t_d[1] <= s_axis_feat_tdata;
    if (rst) t_v <= 0;
  end
  wire [351:0] t_data = t_d[1];
  always @(*) if (!init && !rst)
    latency: assert (m_axis_feat_tvalid == t_v[1] && (!m_axis_feat_tvalid || (1'b0 == t_u[1] && m_axis_feat_tlast == t_l[1] && (m_axis_feat_tdata[351:320] == t_data[351:320] && m_axis_feat_tdata[63:0] == t_data[63:0] && m_axis_feat_tdata[319:64] == want_desc))));
