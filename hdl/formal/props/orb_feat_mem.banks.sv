// SPDX-License-Identifier: MIT
// orb_feat_mem.banks: the bank protocol at the ports and inside (the RAM's write
// port, probed): `held_header_stable`, `ready_until_release`, `held_not_written`, `count_record`,
// `banks_alternate`, `bank_choice`, and the induction's lemmas.
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  // the bank protocol at the ports (docs/feature-memory.md): a READY bank keeps its header until
  // the CPU releases it, and stops being READY only after a release of it (registered: 1 or 2
  // clocks) or rst; a release lets the next frame be published into the bank at once
  reg [1:0] ready_q = 0, rel_q1 = 0, rel_q2 = 0;
  reg [63:0] hdr0_q, hdr1_q;
  wire [63:0] hdr0 = {bank0_count, bank0_frame, bank0_trunc[15:0], bank0_dropped};
  wire [63:0] hdr1 = {bank1_count, bank1_frame, bank1_trunc[15:0], bank1_dropped};
  always @(posedge clk) begin
    ready_q <= bank_ready;
    hdr0_q <= hdr0;
    hdr1_q <= hdr1;
    rel_q1 <= {release_valid && release_bank, release_valid && !release_bank};
    rel_q2 <= rel_q1;
  end
  always @(*) if (!init && !rst && !rst_q) begin
    held_header_stable: assert ((!(ready_q[0] && bank_ready[0]) || hdr0 == hdr0_q || rel_q1[0] || rel_q2[0]) &&
                                (!(ready_q[1] && bank_ready[1]) || hdr1 == hdr1_q || rel_q1[1] || rel_q2[1]));
    ready_until_release: assert ((!ready_q[0] || bank_ready[0] || rel_q1[0] || rel_q2[0]) &&
                                 (!ready_q[1] || bank_ready[1] || rel_q1[1] || rel_q2[1]));
  end
  `include "orb_feat_mem.common.svh"
  always @(*) if (!init)
    held_not_written: assert (!(probe_wr_en && held[probe_wr_addr[4]]));

  // what the RAM's writes leave in each bank (the RAM is not reset, nor are these): which slots hold a
  // record (flag: bit 63 of the word, bit 31 of CPU word 1), the slot of the last record written and its CPU
  // words 0..4 (count, flags, frame, dropped, truncated count)
  reg [15:0] recs0 = 0, recs1 = 0;
  reg [3:0] rslot0 = 0, rslot1 = 0;
  reg [159:0] rword0 = 0, rword1 = 0;
  wire wrec = probe_wr_data[63];
  always @(posedge clk) if (probe_wr_en) begin
    if (probe_wr_addr[4]) begin
      recs1[probe_wr_addr[3:0]] <= wrec;
      if (wrec) begin rslot1 <= probe_wr_addr[3:0]; rword1 <= probe_wr_data[159:0]; end
    end else begin
      recs0[probe_wr_addr[3:0]] <= wrec;
      if (wrec) begin rslot0 <= probe_wr_addr[3:0]; rword0 <= probe_wr_data[159:0]; end
    end
  end
  // a READY bank: slot count holds the last record written into the bank, with the header's count,
  // truncated flag, frame, dropped and truncated counts; no slot below count holds a record
  function rec_ok(input [15:0] recs, input [3:0] rslot, input [159:0] rw, input [15:0] c, input [15:0] f,
                  input [15:0] d, input [31:0] t);
    rec_ok = c < 16 && rslot == c[3:0] && recs[c[3:0]] && (recs & ~(16'hffff << c)) == 0 &&
             rw[31:0] == {16'd0, c} && rw[62] == (t != 0) && rw[79:64] == f && rw[111:96] == d &&
             rw[159:128] == t;
  endfunction
  always @(*) if (!init)
    count_record: assert ((!bank_ready[0] || rec_ok(recs0, rslot0, rword0, bank0_count, bank0_frame, bank0_dropped,
                                                    bank0_trunc)) &&
                          (!bank_ready[1] || rec_ok(recs1, rslot1, rword1, bank1_count, bank1_frame, bank1_dropped,
                                                    bank1_trunc)));

  // banks alternate: the frames are published into bank 0, 1, 0, ... from reset (frame_done, last_bank)
  reg exp_bank = 0;
  always @(posedge clk) if (rst) exp_bank <= 0; else if (frame_done) exp_bank <= !exp_bank;
  always @(*) if (!init && !rst_q)
    banks_alternate: assert (!frame_done || last_bank == exp_bank);

  // the bank choice (docs/feature-memory.md "Protocol"): a frame is published if its bank (the one after the
  // last published) was free at its first beat (not READY, or released in that clock) and it was not
  // aborted; skipped (overrun + 1) if the bank was held; discarded (aborted + 1) if a frame_abort pulse came
  // in it (or between it and the frame before); the outcome shows in the clock after its end-of-frame beat
  wire w_now = exp_bank ^ frame_done;  // the bank the next frame goes to
  wire free_now = !held[w_now];
  reg in_f = 0, dec = 0, ab = 0, e_pub = 0, e_ovr = 0, e_abt = 0;
  reg [31:0] ovr_q = 0, abt_q = 0;
  wire dec_now = in_f ? dec : free_now;
  wire ab_now = ab || abort_q;
  always @(posedge clk) begin
    ovr_q <= overrun;
    abt_q <= aborted;
    e_pub <= 0; e_ovr <= 0; e_abt <= 0;
    if (abort_q) ab <= 1;
    if (beat_q && !last_q) begin
      in_f <= 1;
      dec <= dec_now;
    end else if (beat_q) begin
      in_f <= 0;
      ab <= 0;
      e_abt <= ab_now;
      e_ovr <= !ab_now && !dec_now;
      e_pub <= !ab_now && dec_now;
    end
    if (rst) begin
      in_f <= 0; ab <= 0; e_pub <= 0; e_ovr <= 0; e_abt <= 0;
    end
  end
  always @(*) if (!init && !rst_q)
    bank_choice: assert (frame_done == e_pub && overrun == ovr_q + e_ovr && aborted == abt_q + e_abt);

  // lemmas for the induction (not properties of their own): the monitors above track the entity's state
  // (probed), and the bank being written holds no record below the count
  wire [15:0] recs_w = probe_wbank ? recs1 : recs0;
  always @(*) if (!init && !rst_q) begin
    lemma_state: assert (probe_wbank == w_now && in_f == probe_in_frame && ab == probe_abort_f &&
                         (!in_f || dec == probe_storing) && (e_pub + e_ovr + e_abt <= 1) &&
                         rel_q == probe_in_rel && relb_q == probe_in_relb && beat_q == probe_in_beat &&
                         last_q == probe_in_last && abort_q == probe_in_abort);
    lemma_writing: assert ((probe_in_frame || !probe_storing) && (probe_storing || probe_cnt == 0) &&
                           (!(probe_in_frame && probe_storing) ||
                            (!bank_ready[probe_wbank] && (recs_w & ~(16'hffff << probe_cnt)) == 0)));
  end
