// SPDX-License-Identifier: MIT
// orb_feat_dma: the ring registers constant from the first clock and
// `legal`, the four checks of docs/feature-dma.md computed on them.
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  // the ring registers constant from the first clock; legal by the four checks of feature-dma.md
  (* anyconst *) reg [31:0] c_base, c_stride;
  (* anyconst *) reg [4:0] c_count;
  always @(*) assume (ring_base == c_base && ring_stride == c_stride && ring_count == c_count);
  function [36:0] mul4(input [3:0] k, input [31:0] v);  // k * v
    mul4 = (k[0] ? {5'd0, v} : 37'd0) + (k[1] ? {4'd0, v, 1'b0} : 37'd0) + (k[2] ? {3'd0, v, 2'b0} : 37'd0) +
           (k[3] ? {2'd0, v, 3'b0} : 37'd0);
  endfunction
  wire [3:0] c_last = c_count[3:0] - 4'd1;  // count - 1 (count 1 .. 16)
  wire [36:0] ring_end = {5'd0, c_base} + mul4(c_last, c_stride) + BUF;
  wire legal = c_base[5:0] == 0 && c_stride[5:0] == 0 && c_count != 0 && (c_count <= 1 || c_stride >= BUF) &&
               {5'd0, c_base} >= WIN_LO && ring_end <= WIN_HI;
