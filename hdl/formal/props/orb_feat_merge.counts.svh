// SPDX-License-Identifier: MIT
// orb_feat_merge (SCALES_g = 2, FIFO_DEPTH_g = 2): features and frame ends
// counted at the ports; `inside` = given - out - dropped.
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  reg [7:0] f_in = 0, f_out = 0;  // features given on in_valid, features given on m_axis_feat
  reg [3:0] d0 = 0, d1 = 0, e_out = 0;  // frame ends given per scale (in_done), end-of-frame beats out
  wire m_take = m_axis_feat_tvalid && m_axis_feat_tready;
  always @(posedge clk)
    if (rst) begin
      f_in <= 0; f_out <= 0; d0 <= 0; d1 <= 0; e_out <= 0;
    end else begin
      f_in <= f_in + in_valid[0] + in_valid[1];
      f_out <= f_out + (m_take && !m_axis_feat_tlast);
      d0 <= d0 + in_done[0];
      d1 <= d1 + in_done[1];
      e_out <= e_out + (m_take && m_axis_feat_tlast);
    end
  // features inside: given, minus those out, minus those counted as dropped (which the merge counts a clock
  // or two after the loss); 8-bit arithmetic, no wrap within the depth
  wire [7:0] inside = f_in - f_out - dropped[7:0];
