// SPDX-License-Identifier: MIT
// orb_feat_dma.ring: `aw_in_ring` (a constant legal ring: every burst inside a buffer
// of it).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  `include "orb_feat_dma.window.svh"
  `include "orb_feat_dma.const_ring.svh"
  always @(*) if (init) assume (legal);
  // every burst inside a buffer of the ring: [base + i stride, + DEPTH_g 64) for some i < count; the
  // buffers' starts computed once, in the first clock (the ring is constant)
  reg [16 * 37 - 1:0] starts;
  integer i;
  always @(posedge clk)
    if (init) for (i = 0; i < 16; i = i + 1) starts[37 * i +: 37] <= {5'd0, c_base} + mul4(i, c_stride);
  reg in_buf;
  integer j;
  always @(*) begin
    in_buf = 1'b0;
    for (j = 0; j < 16; j = j + 1)
      if (j < c_count && aw_a >= starts[37 * j +: 37] && aw_a + 64 <= starts[37 * j +: 37] + BUF) in_buf = 1'b1;
  end
  always @(*) if (!init && m_axi_feat_awvalid) aw_in_ring: assert (in_buf);
