// SPDX-License-Identifier: MIT
// orb_feat_dma (and orb_feat_dma.out1): `aw_aligned` and `aw_in_window`, whatever the
// ring registers do.
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  `include "orb_feat_dma.window.svh"
  // every address 64-byte aligned, every 64-byte burst inside the window, whatever the ring registers do
  always @(*) if (!init && m_axi_feat_awvalid) begin
    aw_aligned: assert (m_axi_feat_awaddr[5:0] == 0);
    aw_in_window: assert (aw_a >= WIN_LO && aw_a + 64 <= WIN_HI);
  end
