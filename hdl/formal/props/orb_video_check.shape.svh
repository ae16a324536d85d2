// SPDX-License-Identifier: MIT
// orb_video_check, the sink assumed ready; the output frame's shape:
// `frame_shape` (tuser at (0, 0), tlast at x = WIDTH_g - 1) and `frame_end_last`.
// docs/formal.md (sw/orb_flow/formal.py inserts it)
// @NAME@: a value the runner fills in (the check's values in sw/orb_flow/formal_checks.py, or a generic)

  // the documented contract: the detector behind orb_video_check never stalls it
  always @(*) if (!init) assume (m_axis_video_tready);
  // the position of the next output beat in its frame, from the output beats alone
  reg [15:0] ox = 0, oy = 0;
  always @(posedge clk)
    if (rst) begin
      ox <= 0;
      oy <= 0;
    end else if (m_axis_video_tvalid && m_axis_video_tready) begin
      ox <= (ox == @WIDTH_g@ - 1) ? 0 : ox + 1;
      if (ox == @WIDTH_g@ - 1) oy <= (oy == @HEIGHT_g@ - 1) ? 0 : oy + 1;
    end
  always @(*) if (!init && !rst) begin
    frame_shape: assert (!m_axis_video_tvalid ||
                         (m_axis_video_tuser == (ox == 0 && oy == 0) && m_axis_video_tlast == (ox == @WIDTH_g@ - 1)));
    frame_end_last: assert (frame_end == (m_axis_video_tvalid && ox == @WIDTH_g@ - 1 && oy == @HEIGHT_g@ - 1));
  end
