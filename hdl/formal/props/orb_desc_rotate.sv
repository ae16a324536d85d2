// SPDX-License-Identifier: MIT
// orb_desc_rotate: `no_invention` (the beat inside is the one on the output).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  reg [3:0] inside = 0;  // beats taken on the input and not yet given on the output
  always @(posedge clk)
    if (rst) inside <= 0;
    else inside <= inside + (s_axis_feat_tvalid && s_axis_feat_tready) - (m_axis_feat_tvalid && m_axis_feat_tready);
  always @(*) if (!init && !rst)
    no_invention: assert (inside == m_axis_feat_tvalid);
