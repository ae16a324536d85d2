// SPDX-License-Identifier: MIT
// orb_video_check.live (IDLE_TIMEOUT_g > 0): `frame_shape`, `frame_end_last`,
// `never_held`, `latency` and `idle_timeout` (at most GAP_MAX clocks without an output beat).
// docs/formal.md (sw/orb_flow/formal.py inserts it)
// @NAME@: a value the runner fills in (the check's values in sw/orb_flow/formal_checks.py, or a generic)

  `include "orb_video_check.shape.svh"
  // never held: s_axis_video_tready is 1 from the second clock out of reset on
  always @(*) if (!init && !rst && !rst_q) never_held: assert (s_axis_video_tready);
  // latency 1: a pixel taken at one edge is on m_axis_video (the same value) after it, or counted as
  // discarded (outside a frame, while padding, a start of frame inside an open frame)
  `include "orb_video_check.taken.svh"
  always @(*) if (!init && !rst)
    latency: assert (!t_v || (m_axis_video_tvalid && m_axis_video_tdata == t_d) || discarded_pixels == disc_q + 1);
  // the idle timeout: inside an output frame (its first beat out, its last not yet) at most @GAP_MAX@ clocks in a
  // row without an output beat, whatever the input does (a bound of @GAP_MAX@ - 1 fails)
  reg [7:0] gap = 0;
  always @(posedge clk) gap <= (rst || m_axis_video_tvalid || (ox == 0 && oy == 0)) ? 0 : (gap == 255 ? 255 : gap + 1);
  always @(*) if (!init && !rst) idle_timeout: assert (gap <= @GAP_MAX@);
