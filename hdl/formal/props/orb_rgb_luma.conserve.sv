// SPDX-License-Identifier: MIT
// orb_rgb_luma.conserve: `no_invention` (the beats inside are exactly those of
// its 4 registers, valid bits probed).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  reg [3:0] inside = 0;  // beats taken on the input and not yet given on the output
  always @(posedge clk)
    if (rst) inside <= 0;
    else inside <= inside + (s_axis_video_tvalid && s_axis_video_tready) - (m_axis_video_tvalid && m_axis_video_tready);
  always @(*) if (!init && !rst)
    no_invention: assert (inside == probe_a_valid + probe_b_valid + probe_p_valid + m_axis_video_tvalid);
