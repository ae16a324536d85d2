// SPDX-License-Identifier: MIT
// orb_video_check (IDLE_TIMEOUT_g = 0): `frame_shape`, `frame_end_last`, `rate`
// (tready low at most LOW_MAX clocks in a row) and `latency`.
// docs/formal.md (sw/orb_flow/formal.py inserts it)
// @NAME@: a value the runner fills in (the check's values in sw/orb_flow/formal_checks.py, or a generic)

  `include "orb_video_check.shape.svh"
  // rate: s_axis_video_tready is low for at most @LOW_MAX@ clocks in a row out of reset: padding a bad
  // frame, and then the next one when the start of frame held meanwhile is bad itself (its tlast at
  // x = 0), all without taking input (a bound of @LOW_MAX@ - 1 fails)
  reg [7:0] low = 0;
  always @(posedge clk) low <= (rst || s_axis_video_tready) ? 0 : (low == 255 ? 255 : low + 1);
  always @(*) if (!init && !rst) rate: assert (low <= @LOW_MAX@);
  // latency 1: a pixel taken at one edge is on m_axis_video (the same value) after it, or counted as
  // discarded, or held (tready falls: a start of frame inside an open frame waits for its padding)
  `include "orb_video_check.taken.svh"
  always @(*) if (!init && !rst)
    latency: assert (!t_v || (m_axis_video_tvalid && m_axis_video_tdata == t_d) ||
                     discarded_pixels == disc_q + 1 || !s_axis_video_tready);
