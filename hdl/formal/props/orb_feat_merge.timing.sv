// SPDX-License-Identifier: MIT
// orb_feat_merge.timing: `rate` (no loss at one feature a clock) and `latency`
// (FEAT_MERGE_LAT_c = 3), the sink always ready.
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  always @(*) if (!init) assume (m_axis_feat_tready);
  `include "orb_feat_merge.counts.svh"
  // rate: with the sink always ready and at most one feature a clock in all (no frame end), none is lost
  always @(*) if (!init) assume (!(in_valid[0] && in_valid[1]) && in_done == 0);
  always @(*) if (!init && !rst) rate: assert (dropped == 0);
  // latency FEAT_MERGE_LAT_c = 3 when nothing waits (no feature inside, every frame end's beat out): a lone
  // feature given at edge e is on m_axis_feat after edge e + 2, with its x, y, score and scale
  wire idle = inside == 0 && !m_axis_feat_tvalid;
  reg [3:1] l_v = 0;
  reg l_s;
  reg [35:0] l_w;
  always @(posedge clk) begin
    l_v <= {l_v[2:1], idle && (in_valid == 2'b01 || in_valid == 2'b10) && !rst};
    if (l_v == 0) begin
      l_s <= in_valid[1];
      l_w <= in_valid[1] ? {in_y[23:12], in_x[23:12], in_score[23:12]} : {in_y[11:0], in_x[11:0], in_score[11:0]};
    end
    if (rst) l_v <= 0;
  end
  always @(*) if (!init && !rst && l_v[3])
    latency: assert (m_axis_feat_tvalid && !m_axis_feat_tlast && m_axis_feat_tdata[35:0] == l_w &&
                     m_axis_feat_tdata[38:36] == l_s);
