// SPDX-License-Identifier: MIT
// orb_axis_chk: the AXI4-Stream source rule, written once and bound to every stream port by the
// formal flow (sw/orb_flow/formal.py, docs/formal.md). Once tvalid is 1 it stays 1, with tdata,
// tuser and tlast unchanged, until the clock edge that takes the beat (tvalid and tready both 1);
// a clock edge with rst 1 ends the obligation (synchronous reset of source and sink alike).
// ASSUME = 1: the rule is assumed (an input port: what the upstream source promises);
// ASSUME = 0: it is asserted (an output port: what the entity must keep).
// Ports without tuser or tlast get a constant 0 there. Not synthesisable: formal only.
module orb_axis_chk #(
  parameter integer W = 8,
  parameter integer ASSUME = 0
) (
  input wire clk,
  input wire rst,
  input wire tvalid,
  input wire tready,
  input wire [W-1:0] tdata,
  input wire tuser,
  input wire tlast
);
  reg past_ok = 1'b0;
  reg held_valid = 1'b0;  // a beat was offered at the last edge and not taken, no reset
  reg [W-1:0] held_data;
  reg held_user, held_last;
  always @(posedge clk) begin
    past_ok <= 1'b1;
    held_valid <= tvalid && !tready && !rst;
    held_data <= tdata;
    held_user <= tuser;
    held_last <= tlast;
  end
  wire hold_ok = !held_valid || (tvalid && tdata == held_data && tuser == held_user && tlast == held_last);
  generate
    if (ASSUME) begin : gen_assume
      always @(*) if (past_ok) assume (hold_ok);
    end else begin : gen_assert
      always @(*) if (past_ok) hold: assert (hold_ok);
    end
  endgenerate
endmodule
