// SPDX-License-Identifier: MIT
// orb_frame_gate: `no_invention` (latency 0: a beat out is the beat in).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  // latency 0, nothing invented: a beat on m_axis_video is the beat on s_axis_video in the same
  // clock, taken exactly when the output takes it
  always @(*) if (!init)
    no_invention: assert (!m_axis_video_tvalid ||
                          (s_axis_video_tvalid && m_axis_video_tdata == s_axis_video_tdata &&
                           m_axis_video_tuser == s_axis_video_tuser && m_axis_video_tlast == s_axis_video_tlast &&
                           s_axis_video_tready == m_axis_video_tready));
