// SPDX-License-Identifier: MIT
// orb_overlay.timing: `rate` and `latency` (OVERLAY_VIDEO_LAT_c = 3), the sink always
// ready.
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  always @(*) if (!init) assume (m_axis_video_tready);
  always @(*) if (!init && !rst && !rst_q) rate: assert (s_axis_video_tready);
  `include "latency_video_3.svh"
