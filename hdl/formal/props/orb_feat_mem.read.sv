// SPDX-License-Identifier: MIT
// orb_feat_mem.read: `published_stable` (a published bank never changes, seen at the
// CPU port).
// docs/formal.md (sw/orb_flow/formal.py inserts it)

  `include "orb_feat_mem.common.svh"
  (* anyconst *) reg [10:2] pa;  // a CPU word: [10] bank, [9:6] slot, [5:2] word
  always @(*) if (mem_rd_en) assume (mem_rd_addr[10:2] == pa);
  // an interval of the bank's holding ends with a clock in which it is not held; reads carry the interval's
  // number from their issue (a clock in which the bank is READY: the RAM is read-first) to their data,
  // FEAT_MEM_READ_LAT_c = 3 clocks later
  reg [2:0] ivn = 0;
  always @(posedge clk) if (!held[pa[10]]) ivn <= ivn + 1;
  reg [2:0] p_v = 0;
  reg [2:0] p_iv [1:3];
  always @(posedge clk) begin
    p_v <= {p_v[1:0], mem_rd_en && bank_ready[pa[10]] && !rst};
    p_iv[1] <= ivn; p_iv[2] <= p_iv[1]; p_iv[3] <= p_iv[2];
    if (rst) p_v <= 0;
  end
  wire same = p_v[2] && p_iv[3] == ivn;  // the word on mem_rd_data, read in this holding interval
  reg have = 0;
  reg [31:0] val;
  always @(posedge clk)
    if (rst || !held[pa[10]]) have <= 0;
    else if (same && !have) begin
      have <= 1;
      val <= mem_rd_data;
    end
  always @(*) if (!init && !rst && same && have)
    published_stable: assert (mem_rd_data == val);
