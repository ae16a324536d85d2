// SPDX-License-Identifier: MIT
// orb_axi4w_chk: the AXI4 write channels (AW, W, B) of a master, written once and bound to an
// m_axi_<name> port by the formal flow (sw/orb_flow/formal.py, docs/formal.md). Asserted with
// ASSUME = 0 (a master port: what the entity must keep; labels, as docs/formal.md names them):
//   reset_low    in every clock after an edge with rst 1, AWVALID and WVALID are 0;
//   aw_hold      AWVALID, once 1, stays 1 with AWADDR, AWLEN, AWSIZE and AWBURST unchanged until
//                the edge that takes it (AWREADY);
//   w_hold       WVALID likewise with WDATA, WSTRB and WLAST until WREADY;
//   aw_burst     a burst offered is INCR (AWBURST 01) of the bus width (AWSIZE = log2(D / 8));
//   aw_4k        no burst crosses a 4 KiB boundary: AWADDR[11:0] + (AWLEN + 1) * D / 8 <= 4096;
//   w_after_aw   no write data without an address: a W beat is taken only while a burst whose
//                AWVALID has been raised (in that clock or before) still waits for data;
//   w_last       WLAST exactly on beat AWLEN + 1 of its burst (the W beats go to the bursts in the
//                order their AWVALID rose; their AWLENs wait in a queue of MAX_AHEAD entries);
//   aw_ahead     at most MAX_AHEAD bursts whose AWVALID has been raised and whose last W beat has not
//                been taken (1: the next address waits for the last beat of the burst before);
//   outstanding  at most MAX_OUTSTANDING bursts issued (AWVALID raised) and not answered (BVALID and
//                BREADY): the master's BREADY handling keeps its limit.
// Assumed with ASSUME = 0 (the slave keeps AXI4; no fairness: AWREADY, WREADY, BVALID and BRESP are
// otherwise arbitrary in every clock): BVALID only while a burst whose AW and last W beat have both
// been taken (at earlier edges) waits for its response; BVALID held with BRESP until BREADY.
// ASSUME = 1 (a slave port) swaps the two: the master rules above are assumed and the slave's are
// asserted (b_no_req, b_held).
// rst is the bus reset (AXI's ARESETn inverted): an edge with rst 1 clears the counts and ends every
// obligation (synchronous reset of master and slave alike). Responses come in order (one ID).
// Not synthesisable: formal only.
module orb_axi4w_chk #(
  parameter integer A = 32,
  parameter integer D = 64,
  parameter integer MAX_OUTSTANDING = 4,
  parameter integer MAX_AHEAD = 1,
  parameter integer ASSUME = 0
) (
  input wire clk,
  input wire rst,
  input wire [A-1:0] awaddr,
  input wire [7:0] awlen,
  input wire [2:0] awsize,
  input wire [1:0] awburst,
  input wire awvalid,
  input wire awready,
  input wire [D-1:0] wdata,
  input wire [D/8-1:0] wstrb,
  input wire wlast,
  input wire wvalid,
  input wire wready,
  input wire [1:0] bresp,
  input wire bvalid,
  input wire bready
);
  localparam integer BYTES = D / 8;
  localparam [2:0] SIZE = $clog2(BYTES);
  localparam integer QB = MAX_AHEAD > 1 ? $clog2(MAX_AHEAD) : 1;  // queue index bits

  wire aw_hs = awvalid && awready;
  wire w_hs = wvalid && wready;
  wire b_hs = bvalid && bready;

  reg past_ok = 1'b0;
  reg rst_q = 1'b0;  // rst at the last edge
  // the last edge's view, for the hold rules (cleared by rst)
  reg aw_wait = 1'b0, w_wait = 1'b0, b_wait = 1'b0;
  reg [A-1:0] awaddr_p;
  reg [7:0] awlen_p;
  reg [2:0] awsize_p;
  reg [1:0] awburst_p, bresp_p;
  reg [D-1:0] wdata_p;
  reg [D/8-1:0] wstrb_p;
  reg wlast_p;

  // a burst is issued in the clock its AWVALID rises (AWVALID 1 and not a held offer of the last edge)
  wire aw_new = awvalid && !aw_wait;
  // bursts issued whose last W beat has not been taken: their AWLENs in order, q[q_rd] the oldest
  reg [7:0] ahead = 0;
  reg [7:0] q [0:MAX_AHEAD-1];
  reg [QB-1:0] q_rd = 0, q_wr = 0;
  reg [7:0] wb = 0;  // W beats of the oldest such burst taken so far
  wire have = ahead != 0 || aw_new;  // a burst waits for data (issued before, or in this clock)
  wire [7:0] head_len = ahead != 0 ? q[q_rd] : awlen;
  wire w_end = w_hs && have && wb == head_len;  // the burst's beat AWLEN + 1 is taken
  // bursts issued and not answered; AW taken and last W taken, not answered (the slave's view)
  reg [7:0] outst = 0, aw_done = 0, wl_done = 0;

  function [QB-1:0] nxt(input [QB-1:0] i);
    nxt = (i == MAX_AHEAD - 1) ? 0 : i + 1;
  endfunction

  always @(posedge clk) begin
    past_ok <= 1'b1;
    rst_q <= rst;
    aw_wait <= awvalid && !awready && !rst;
    w_wait <= wvalid && !wready && !rst;
    b_wait <= bvalid && !bready && !rst;
    awaddr_p <= awaddr;
    awlen_p <= awlen;
    awsize_p <= awsize;
    awburst_p <= awburst;
    wdata_p <= wdata;
    wstrb_p <= wstrb;
    wlast_p <= wlast;
    bresp_p <= bresp;
    if (rst) begin
      ahead <= 0;
      q_rd <= 0;
      q_wr <= 0;
      wb <= 0;
      outst <= 0;
      aw_done <= 0;
      wl_done <= 0;
    end else begin
      ahead <= ahead + aw_new - w_end;
      if (aw_new) begin
        q[q_wr] <= awlen;
        q_wr <= nxt(q_wr);
      end
      if (w_end) q_rd <= nxt(q_rd);
      if (w_hs && have) wb <= w_end ? 0 : wb + 1;
      outst <= outst + aw_new - b_hs;
      aw_done <= aw_done + aw_hs - b_hs;
      wl_done <= wl_done + w_end - b_hs;
    end
  end

  wire aw_hold_ok = !aw_wait || (awvalid && awaddr == awaddr_p && awlen == awlen_p && awsize == awsize_p &&
                                 awburst == awburst_p);
  wire w_hold_ok = !w_wait || (wvalid && wdata == wdata_p && wstrb == wstrb_p && wlast == wlast_p);
  wire [31:0] aw_top = awaddr[11:0] + (awlen + 32'd1) * BYTES;
  wire b_req_ok = !bvalid || (aw_done != 0 && wl_done != 0);
  wire b_hold_ok = !b_wait || (bvalid && bresp == bresp_p);

  generate
    if (ASSUME) begin : gen_slave
      always @(*) if (past_ok) begin
        assume (!rst_q || (!awvalid && !wvalid));
        assume (aw_hold_ok && w_hold_ok);
        assume (!awvalid || (awburst == 2'b01 && awsize == SIZE && aw_top <= 4096));
        assume (!w_hs || (have && wlast == (wb == head_len)));
        assume (ahead <= MAX_AHEAD && outst <= MAX_OUTSTANDING);
        if (!rst) begin
          b_no_req: assert (b_req_ok);
          b_held: assert (b_hold_ok);
        end
      end
    end else begin : gen_master
      always @(*) if (past_ok) begin
        assume (b_req_ok && b_hold_ok);
        reset_low: assert (!rst_q || (!awvalid && !wvalid));
        if (!rst) begin
          aw_hold: assert (aw_hold_ok);
          w_hold: assert (w_hold_ok);
          aw_burst: assert (!awvalid || (awburst == 2'b01 && awsize == SIZE));
          aw_4k: assert (!awvalid || aw_top <= 4096);
          w_after_aw: assert (!w_hs || have);
          w_last: assert (!w_hs || !have || wlast == (wb == head_len));
          aw_ahead: assert (ahead <= MAX_AHEAD);
          outstanding: assert (outst <= MAX_OUTSTANDING);
        end
      end
    end
  endgenerate
endmodule
