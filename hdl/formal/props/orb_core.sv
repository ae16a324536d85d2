// SPDX-License-Identifier: MIT
// orb_core: `video_ready` (s_axis_video_tready 1 out of reset, documented).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  always @(*) if (!init && !rst && !rst_q) video_ready: assert (s_axis_video_tready);
