// SPDX-License-Identifier: MIT
// orb_overlay: `feat_ready` (s_axis_feat_tready 1 out of reset, documented).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  always @(*) if (!init && !rst && !rst_q) feat_ready: assert (s_axis_feat_tready);
