// SPDX-License-Identifier: MIT
// orb_accel_zynq.timing: `rate` and `latency` (OVERLAY_VIDEO_LAT_c = 3) with the
// sink always ready and no soft reset, under orb_accel_zynq.sv's reset rule.
// docs/formal.md (sw/orb_flow/formal.py inserts it)
// @NAME@: a value the runner fills in (the check's values in sw/orb_flow/formal_checks.py, or a generic)

  `include "orb_accel_zynq.sv"
  always @(*) if (!init) assume (m_axis_video_tready);
  // no soft reset: no write data with a 1 in CTRL.soft_reset's bit (any register: W names none)
  always @(*) if (!init) assume (!(s_axi_ctrl_wvalid && s_axi_ctrl_wstrb[@SOFT_BYTE@] &&
                                   s_axi_ctrl_wdata[@SOFT_BIT@]));
  reg [3:0] since = 0;  // clocks out of reset (saturating)
  always @(posedge clk) since <= rst ? 0 : (since == 15 ? 15 : since + 1);
  always @(*) if (!init && since >= @RATE_FROM@) rate: assert (s_axis_video_tready);
  `include "latency_video_3.svh"
