// SPDX-License-Identifier: MIT
// orb_frame_gate.rate: `rate` (the sink always ready: s_axis_video_tready 1).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  always @(*) if (!init) assume (m_axis_video_tready);
  always @(*) if (!init && !rst && !rst_q) rate: assert (s_axis_video_tready);
