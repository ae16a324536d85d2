// SPDX-License-Identifier: MIT
// orb_feat_dma.off: `no_write` (a constant ring in error: no AWVALID, ever).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  `include "orb_feat_dma.window.svh"
  `include "orb_feat_dma.const_ring.svh"
  always @(*) if (init) assume (!legal);
  // a ring in error: nothing is written (no AWVALID, ever)
  always @(*) if (!init) no_write: assert (!m_axi_feat_awvalid);
