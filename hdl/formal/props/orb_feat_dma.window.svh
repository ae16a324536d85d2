// SPDX-License-Identifier: MIT
// orb_feat_dma: the DDR window and buffer size in bytes (from the generics) and
// the registers' contract (RING_COUNT at most 16).
// docs/formal.md (sw/orb_flow/formal.py inserts it)
// @NAME@: a value the runner fills in (the check's values in sw/orb_flow/formal_checks.py, or a generic)

  // the DDR window [WIN_BASE_MB_g, + WIN_SIZE_MB_g) MiB in bytes, one buffer (DEPTH_g 64-byte slots)
  localparam [36:0] WIN_LO = 37'd@WIN_LO@, WIN_HI = 37'd@WIN_HI@, BUF = 37'd@BUF@;
  wire [36:0] aw_a = {5'd0, m_axi_feat_awaddr};
  // the registers' contract: RING_COUNT 0 .. 16 (the register map's maximum; a larger write is refused)
  always @(*) assume (ring_count <= 16);
