// SPDX-License-Identifier: MIT
// orb_axil_chk: the AXI4-Lite slave checker, written once and bound to an s_axil port by the
// formal flow (sw/orb_flow/formal.py, docs/formal.md). Assumed (the master keeps AXI4-Lite):
// AW, W and AR held with their payload until taken. Asserted (labels, as docs/formal.md names
// them):
//   b_held, r_held   a response stays valid with its bresp / rdata and rresp until taken;
//   b_no_req         bvalid only while a write (AW and W both taken) waits for its response;
//   r_no_req         rvalid only while a read (AR taken) waits for its response;
//   w_outstanding    at most MAXW writes (AW, and W) taken and not answered;
//   r_outstanding    at most MAXR reads taken and not answered;
//   b_bound          a write whose AW and W are taken is answered within BOUND clocks of the
//                    previous response being taken;
//   r_bound          likewise a read, within RBOUND clocks;
//   aw_live, w_live, ar_live  a request offered while none of its channel is outstanding is taken
//                    within BOUND clocks;
//   b_slverr, r_slverr  (REGMAP = 1) bresp / rresp is SLVERR exactly where the register map says:
//                    orb_axil_regmap_ref, generated from golden_model/data/regmap.json by the flow,
//                    decides from the address, data and strobes (and, for rw registers, the value
//                    the map's earlier OKAY writes left).
// A clock edge with rst 1 clears the counts (synchronous reset of master and slave alike).
// Writes are answered in order (AXI4-Lite has no IDs); MAXW is at most 2. Formal only.
module orb_axil_chk #(
  parameter integer A = 18,
  parameter integer MAXW = 1,
  parameter integer MAXR = 1,
  parameter integer BOUND = 8,
  parameter integer RBOUND = 8,
  parameter integer REGMAP = 0,
  parameter integer MEM_DEPTH = 1024
) (
  input wire clk,
  input wire rst,
  input wire [A-1:0] awaddr,
  input wire awvalid,
  input wire awready,
  input wire [31:0] wdata,
  input wire [3:0] wstrb,
  input wire wvalid,
  input wire wready,
  input wire [1:0] bresp,
  input wire bvalid,
  input wire bready,
  input wire [A-1:0] araddr,
  input wire arvalid,
  input wire arready,
  input wire [31:0] rdata,
  input wire [1:0] rresp,
  input wire rvalid,
  input wire rready
);
  localparam [1:0] OKAY = 2'b00, SLVERR = 2'b10;
  wire aw_hs = awvalid && awready;
  wire w_hs = wvalid && wready;
  wire b_hs = bvalid && bready;
  wire ar_hs = arvalid && arready;
  wire r_hs = rvalid && rready;

  reg past_ok = 1'b0;
  // the last edge's view, for the hold rules (cleared by rst)
  reg aw_wait = 1'b0, w_wait = 1'b0, ar_wait = 1'b0, b_wait = 1'b0, r_wait = 1'b0;
  reg [A-1:0] awaddr_p, araddr_p;
  reg [31:0] wdata_p, rdata_p;
  reg [3:0] wstrb_p;
  reg [1:0] bresp_p, rresp_p;
  // requests taken and not answered, and their payloads in order (entry 0: the oldest)
  reg [2:0] aw_cnt = 0, w_cnt = 0, ar_cnt = 0;
  reg [A-1:0] aw_q0, aw_q1, ar_q0;
  reg [31:0] w_d0, w_d1;
  reg [3:0] w_s0, w_s1;
  // clocks a complete request has waited for its response, a request for its ready
  reg [7:0] bw = 0, rw = 0, awl = 0, wl = 0, arl = 0;

  always @(posedge clk) begin
    past_ok <= 1'b1;
    aw_wait <= awvalid && !awready && !rst;
    w_wait <= wvalid && !wready && !rst;
    ar_wait <= arvalid && !arready && !rst;
    b_wait <= bvalid && !bready && !rst;
    r_wait <= rvalid && !rready && !rst;
    awaddr_p <= awaddr;
    araddr_p <= araddr;
    wdata_p <= wdata;
    wstrb_p <= wstrb;
    rdata_p <= rdata;
    bresp_p <= bresp;
    rresp_p <= rresp;
    if (rst) begin
      aw_cnt <= 0;
      w_cnt <= 0;
      ar_cnt <= 0;
      bw <= 0;
      rw <= 0;
      awl <= 0;
      wl <= 0;
      arl <= 0;
    end else begin
      aw_cnt <= aw_cnt + aw_hs - b_hs;
      w_cnt <= w_cnt + w_hs - b_hs;
      ar_cnt <= ar_cnt + ar_hs - r_hs;
      // the queues: shift out the answered entry, append the new one behind the others
      if (b_hs) begin
        aw_q0 <= aw_q1;
        w_d0 <= w_d1;
        w_s0 <= w_s1;
      end
      if (aw_hs) begin
        if (aw_cnt - b_hs == 0) aw_q0 <= awaddr;
        else aw_q1 <= awaddr;
      end
      if (w_hs) begin
        if (w_cnt - b_hs == 0) begin
          w_d0 <= wdata;
          w_s0 <= wstrb;
        end else begin
          w_d1 <= wdata;
          w_s1 <= wstrb;
        end
      end
      if (ar_hs && ar_cnt - r_hs == 0) ar_q0 <= araddr;
      bw <= (aw_cnt != 0 && w_cnt != 0 && !bvalid) ? bw + 1 : 0;
      rw <= (ar_cnt != 0 && !rvalid) ? rw + 1 : 0;
      awl <= (awvalid && !awready && aw_cnt == 0) ? awl + 1 : 0;
      wl <= (wvalid && !wready && w_cnt == 0) ? wl + 1 : 0;
      arl <= (arvalid && !arready && ar_cnt == 0) ? arl + 1 : 0;
    end
  end

  // the master
  always @(*) begin
    if (past_ok) begin
      if (aw_wait) assume (awvalid && awaddr == awaddr_p);
      if (w_wait) assume (wvalid && wdata == wdata_p && wstrb == wstrb_p);
      if (ar_wait) assume (arvalid && araddr == araddr_p);
    end
  end

  // the register map's answer for the oldest write and read
  wire wr_err, rd_err;
  generate
    if (REGMAP) begin : gen_regmap
      orb_axil_regmap_ref #(.A(A), .MEM_DEPTH(MEM_DEPTH)) ref_map (
        .clk(clk), .rst(rst), .waddr(aw_q0), .wdata(w_d0), .wstrb(w_s0), .commit(b_hs && bresp == OKAY),
        .raddr(ar_q0), .wr_err(wr_err), .rd_err(rd_err)
      );
    end else begin : gen_no_regmap
      assign wr_err = 1'b0;
      assign rd_err = 1'b0;
    end
  endgenerate

  // the slave
  always @(*) begin
    if (past_ok && !rst) begin
      b_held: assert (!b_wait || (bvalid && bresp == bresp_p));
      r_held: assert (!r_wait || (rvalid && rdata == rdata_p && rresp == rresp_p));
      b_no_req: assert (!bvalid || (aw_cnt != 0 && w_cnt != 0));
      r_no_req: assert (!rvalid || ar_cnt != 0);
      w_outstanding: assert (aw_cnt <= MAXW && w_cnt <= MAXW);
      r_outstanding: assert (ar_cnt <= MAXR);
      b_bound: assert (bw <= BOUND);
      r_bound: assert (rw <= RBOUND);
      aw_live: assert (awl <= BOUND);
      w_live: assert (wl <= BOUND);
      ar_live: assert (arl <= BOUND);
      if (REGMAP && bvalid && aw_cnt != 0 && w_cnt != 0) b_slverr: assert (bresp == (wr_err ? SLVERR : OKAY));
      if (REGMAP && rvalid && ar_cnt != 0) r_slverr: assert (rresp == (rd_err ? SLVERR : OKAY));
    end
  end
endmodule
