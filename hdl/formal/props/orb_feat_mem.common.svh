// SPDX-License-Identifier: MIT
// orb_feat_mem: the entity's registered inputs (release, stream, abort) and
// `held`, the banks held in this clock.
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  // the entity registers every input once; these are its registered release, stream (tready is 1)
  // and abort
  reg rel_q = 0, relb_q = 0, beat_q = 0, last_q = 0, abort_q = 0;
  always @(posedge clk) begin
    rel_q <= release_valid && !rst;
    relb_q <= release_bank;
    beat_q <= s_axis_feat_tvalid && !rst;
    last_q <= s_axis_feat_tlast;
    abort_q <= frame_abort && !rst;
  end
  // bank k is held in this clock: READY and not released by the registered release (a release in the
  // clock frees the bank for a write at the same edge: "a release in that very clock counts")
  wire [1:0] held = bank_ready & ~{rel_q && relb_q, rel_q && !relb_q};
