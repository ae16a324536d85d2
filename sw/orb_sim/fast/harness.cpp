// SPDX-License-Identifier: MIT
// The fast simulation harness (docs/fast-sim.md): the Verilated netlist of orb_accel_top (GHDL's
// synthesised Verilog) with a video source, an overlay sink and an AXI4-Lite master in C++, so
// that Python is not woken on every clock. Python (orb_sim.fast.sim) calls the C functions below
// through ctypes: it queues frames as beat programs (data, flags, idle clocks after each beat),
// then every bus operation or wait advances the clock while the video source plays the queue, as
// orb_sim.bus_server does with cocotb. One clock period per tick(); the clock starts low.
//
// Per tick: inputs set -> clk 0, eval -> handshakes sampled (valid && ready before the edge) ->
// clk 1, eval -> the sources and sinks advance on what was sampled.
//
// A live source (fs_live; docs/fast-sim.md): the programs play at a pixel clock of num/den of the
// core clock, each beat's gap counted in pixel clocks (blanking), into a FIFO that the accelerator's
// s_axis_video reads and that drops the pixels arriving while it is full, as the board's HDMI input
// bridge (v_vid_in_axi4s) does: a source that cannot be held.
//
// The DDR (docs/fast-sim.md, "The DDR model"): an AXI4 write slave on m_axi_feat_* (the "DDR"
// feature memory, orb_feat_dma; idle in the "BRAM" build, whose master outputs are constant) with
// a memory of its own, a region [base, base + size) set from Python. AW and W are taken in any
// order (W beats before their AW up to a limit), each burst's beats go to its addresses (INCR,
// FIXED, WRAP; the strobed bytes), the write response comes only after its AW and its last W beat,
// in order, after a delay; a burst that leaves the region is not stored and answered DECERR; a
// burst chosen by its index (or drawn with a probability) is answered SLVERR and not stored. Its
// readies are random (a probability each clock) and held low in windows of clocks (AW, W, and the
// B response); the AXI rules the master must keep (valids held with their payload until the
// handshake, WLAST on the burst's last beat only, no 4 KiB crossing, a legal size and burst) are
// checked and violations counted. rst (the AXI reset, aresetn) empties the channels: the bursts
// under way are forgotten, the memory kept.
#include <algorithm>
#include <cstdint>
#include <cstring>
#include <deque>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "Vorb_accel_top.h"
#include "verilated.h"
#if VM_COVERAGE
#include "verilated_cov.h"
#endif

namespace {

struct Beat {
  uint32_t data;
  uint8_t flags;  // bit 0: tuser (start of frame), bit 1: tlast (end of line)
  uint32_t gap;   // idle clocks after this beat is accepted
};

struct Program {
  std::vector<Beat> beats;
};

struct Queued {  // a live source's beat in the FIFO
  uint32_t data;
  uint8_t flags;
  uint32_t prog;
  bool first;  // the first beat of its program
};

// ---- the DDR: an AXI4 write slave on m_axi_feat ----
struct AxiAw {
  uint64_t index;  // bursts accepted before it
  uint64_t cycle;  // cycle of its AW handshake
  uint32_t addr;
  uint8_t len, size, burst;
  uint8_t resp;  // 0 OKAY; 2 SLVERR or 3 DECERR: injected, or DECERR: outside the region
  bool outside = false;  // refused: the burst leaves the region
  uint32_t beats = 0;  // W beats taken so far
  uint64_t data[4] = {0, 0, 0, 0};  // its first four beats (a record's words: the log)
};

struct AxiW {
  uint64_t data;
  uint8_t strb;
  bool last;
};

struct AxiB {
  AxiAw aw;
  uint64_t done_cycle;   // cycle of its last W beat
  uint64_t ready_cycle;  // BVALID from this cycle on
};

// One finished burst, as the log gives it to Python (24 + 8 + 32 + 8 bytes; sim.py's AXI_LOG_DTYPE)
struct AxiLogEntry {
  uint64_t index, aw_cycle, done_cycle, b_cycle;
  uint32_t addr;
  uint32_t resp;  // 0 OKAY, 2 SLVERR, 3 DECERR; 255: forgotten by an AXI reset before its response
  uint64_t data[4];
  uint64_t beats;
};

struct AxiWindow {
  uint64_t start, end;  // cycles [start, end)
  uint32_t mask;        // bit 0: AWREADY low, bit 1: WREADY low, bit 2: no BVALID
  uint64_t period = 0;  // > 0: the window repeats, [start, end) of every period clocks (start < end <= period)
};

struct AxiErrorRule {  // bursts first, first + every, first + 2 every, .. (every 0: first only)
  uint64_t first, every;
  uint8_t resp;
};

enum AxiStat {
  AX_BURSTS,          // AW handshakes
  AX_BEATS,           // W handshakes
  AX_RESPONSES,       // B handshakes
  AX_OKAY,            // ... OKAY
  AX_SLVERR,          // ... SLVERR
  AX_DECERR,          // ... DECERR
  AX_INJECTED,        // bursts answered with an injected error (fs_axi_error*)
  AX_REFUSED,         // bursts that left the region (answered DECERR)
  AX_REFUSED_BEATS,   // their beats (not stored)
  AX_ERROR_BEATS,     // beats of bursts with an injected error (not stored)
  AX_BYTES,           // bytes stored
  AX_PROTOCOL,        // AXI rule violations by the master
  AX_AW_STALL,        // clocks with AWVALID and not AWREADY
  AX_W_STALL,         // clocks with WVALID and not WREADY
  AX_B_WAIT,          // clocks with BVALID and not BREADY
  AX_MAX_OUTSTANDING, // most bursts accepted and not answered at once
  AX_MAX_W_AHEAD,     // most W beats taken before their AW
  AX_RESET_DROPPED,   // bursts forgotten by an AXI reset
  AX_FIRST_PROTOCOL,  // cycle of the first rule violation (0: none)
  AX_N
};

struct Axi {
  // the memory
  uint64_t base = 0x10000000ull;
  std::vector<uint8_t> mem = std::vector<uint8_t>(4u << 20, 0);
  // settings
  uint32_t aw_permille = 1000, w_permille = 1000;
  uint64_t rng = 0x2545F4914F6CDD1Dull;
  uint64_t b_delay = 0, b_jitter = 0;
  uint64_t max_outstanding = 8, max_w_ahead = 64;
  std::vector<AxiWindow> windows;
  std::map<uint64_t, uint8_t> errors;  // burst index -> response
  std::deque<std::pair<uint32_t, uint8_t>> addr_errors;  // the next burst at this address -> response
  std::vector<AxiErrorRule> error_rules;
  uint32_t err_permille = 0;
  uint8_t err_resp = 2;
  bool log_on = false;
  std::vector<AxiLogEntry> log;
  // state
  std::deque<AxiAw> aw_q;  // accepted, data not complete
  std::deque<AxiW> w_q;    // beats accepted, not yet matched to an AW
  std::deque<AxiB> b_q;    // complete, response not given
  bool awready = false, wready = false, bvalid = false;
  // the master's outputs of the last clock (the stability rules)
  bool prev_aw_wait = false, prev_w_wait = false;
  uint32_t prev_awaddr = 0;
  uint8_t prev_awlen = 0, prev_awsize = 0, prev_awburst = 0;
  uint64_t prev_wdata = 0;
  uint8_t prev_wstrb = 0;
  bool prev_wlast = false;
  // handshakes sampled before the edge
  bool aw_fire = false, w_fire = false, b_fire = false;
  AxiAw aw_in;
  AxiW w_in;
  uint64_t st[AX_N] = {};
};

struct Sim {
  std::unique_ptr<VerilatedContext> ctx;
  std::unique_ptr<Vorb_accel_top> top;
  uint64_t cycle = 0;
  // video source
  std::vector<Program> programs;
  size_t prog = 0, pos = 0;
  uint32_t idle = 0;  // idle clocks left before the next beat is offered
  bool loop = false;
  uint64_t frames_started = 0, beats_sent = 0, last_beat_cycle = 0, stall = 0, stall_max = 0;
  std::vector<uint64_t> frame_start_cycles;  // cycle at which each program's first beat was accepted
  std::vector<uint32_t> frame_start_prog;
  // live source: pixel clock = num / den of the clock, into a FIFO of fifo_depth beats
  bool live = false;
  uint64_t live_num = 0, live_den = 1, live_acc = 0;
  size_t fifo_depth = 0;
  std::deque<Queued> fifo;
  uint64_t fifo_dropped = 0, fifo_max = 0;
  // overlay sink
  uint32_t ready_permille = 1000;
  uint64_t rng = 0x9E3779B97F4A7C15ull;
  bool capture = false;
  std::vector<uint32_t> out_data;
  std::vector<uint8_t> out_flags;
  uint64_t out_beats = 0;
  // interrupt
  uint64_t irq_rise_cycle = 0, irq_rises = 0;
  bool irq_last = false;
  // AXI4-Lite handshakes sampled before the last edge
  bool ar_fire = false, r_fire = false, aw_fire = false, w_fire = false, b_fire = false;
  uint32_t rdata = 0;
  int rresp = 0, bresp = 0;
  // the DDR
  Axi axi;
};

uint64_t xorshift(uint64_t& s) {
  s ^= s << 13;
  s ^= s >> 7;
  s ^= s << 17;
  return s;
}

// ---- the DDR ----
uint32_t axi_window_mask(const Axi& a, uint64_t cycle) {
  uint32_t m = 0;
  for (const AxiWindow& w : a.windows) {
    const uint64_t c = w.period ? cycle % w.period : cycle;
    if (c >= w.start && c < w.end) m |= w.mask;
  }
  return m;
}

bool axi_draw(Axi& a, uint32_t permille) {
  return permille >= 1000 || (xorshift(a.rng) % 1000) < permille;
}

void axi_protocol(Axi& a, uint64_t cycle) {
  if (a.st[AX_PROTOCOL]++ == 0) a.st[AX_FIRST_PROTOCOL] = cycle;
}

// The AXI reset (rst high): the channels are emptied, the bursts under way forgotten (logged).
void axi_reset(Sim& s) {
  Axi& a = s.axi;
  auto forget = [&](const AxiAw& aw, uint64_t done) {
    a.st[AX_RESET_DROPPED]++;
    if (a.log_on) {
      AxiLogEntry e{aw.index, aw.cycle, done, 0, aw.addr, 255, {aw.data[0], aw.data[1], aw.data[2], aw.data[3]},
                    aw.beats};
      a.log.push_back(e);
    }
  };
  for (const AxiB& b : a.b_q) forget(b.aw, b.done_cycle);
  for (const AxiAw& aw : a.aw_q) forget(aw, 0);
  a.aw_q.clear();
  a.w_q.clear();
  a.b_q.clear();
  a.awready = a.wready = a.bvalid = false;
  a.prev_aw_wait = a.prev_w_wait = false;
}

// Inputs of the slave for this clock (before the falling half): the readies and the response.
void axi_drive(Sim& s) {
  Axi& a = s.axi;
  Vorb_accel_top* t = s.top.get();
  if (t->rst) {
    axi_reset(s);
  } else {
    const uint32_t m = axi_window_mask(a, s.cycle);
    const uint64_t outstanding = a.aw_q.size() + a.b_q.size();
    // W beats ahead of their AW: those beyond what the accepted AWs still expect
    uint64_t expect = 0;
    for (const AxiAw& aw : a.aw_q) expect += uint64_t(aw.len) + 1 - aw.beats;
    const uint64_t ahead = a.w_q.size() > expect ? a.w_q.size() - expect : 0;
    a.awready = !(m & 1) && outstanding < a.max_outstanding && axi_draw(a, a.aw_permille);
    a.wready = !(m & 2) && (ahead < a.max_w_ahead || a.w_q.size() < expect) && axi_draw(a, a.w_permille);
    // BVALID once up stays up until BREADY (AXI): a window only delays a response not yet shown
    if (!a.bvalid) a.bvalid = !(m & 4) && !a.b_q.empty() && a.b_q.front().ready_cycle <= s.cycle;
  }
  t->m_axi_feat_awready = a.awready;
  t->m_axi_feat_wready = a.wready;
  t->m_axi_feat_bvalid = a.bvalid;
  t->m_axi_feat_bresp = a.bvalid ? a.b_q.front().aw.resp : 0;
}

// The master's outputs after the falling half (before the edge): handshakes and the AXI rules.
void axi_sample(Sim& s) {
  Axi& a = s.axi;
  Vorb_accel_top* t = s.top.get();
  a.aw_fire = a.w_fire = a.b_fire = false;
  if (t->rst) return;
  const bool awvalid = t->m_axi_feat_awvalid, wvalid = t->m_axi_feat_wvalid;
  const uint32_t awaddr = t->m_axi_feat_awaddr;
  const uint8_t awlen = t->m_axi_feat_awlen, awsize = t->m_axi_feat_awsize, awburst = t->m_axi_feat_awburst;
  const uint64_t wdata = t->m_axi_feat_wdata;
  const uint8_t wstrb = t->m_axi_feat_wstrb;
  const bool wlast = t->m_axi_feat_wlast;
  // a valid waiting for its ready must stay up with the same payload
  if (a.prev_aw_wait && (!awvalid || awaddr != a.prev_awaddr || awlen != a.prev_awlen || awsize != a.prev_awsize ||
                         awburst != a.prev_awburst))
    axi_protocol(a, s.cycle);
  if (a.prev_w_wait && (!wvalid || wdata != a.prev_wdata || wstrb != a.prev_wstrb || wlast != a.prev_wlast))
    axi_protocol(a, s.cycle);
  a.prev_aw_wait = awvalid && !a.awready;
  a.prev_w_wait = wvalid && !a.wready;
  a.prev_awaddr = awaddr, a.prev_awlen = awlen, a.prev_awsize = awsize, a.prev_awburst = awburst;
  a.prev_wdata = wdata, a.prev_wstrb = wstrb, a.prev_wlast = wlast;
  if (awvalid && !a.awready) a.st[AX_AW_STALL]++;
  if (wvalid && !a.wready) a.st[AX_W_STALL]++;
  if (a.bvalid && !t->m_axi_feat_bready) a.st[AX_B_WAIT]++;
  a.aw_fire = awvalid && a.awready;
  a.w_fire = wvalid && a.wready;
  a.b_fire = a.bvalid && t->m_axi_feat_bready;
  if (a.aw_fire) {
    a.aw_in = AxiAw{};
    a.aw_in.addr = awaddr, a.aw_in.len = awlen, a.aw_in.size = awsize, a.aw_in.burst = awburst;
  }
  if (a.w_fire) a.w_in = AxiW{wdata, wstrb, wlast};
}

// The address of beat i of a burst (AXI4 A3.4.1).
uint64_t axi_beat_addr(const AxiAw& aw, uint32_t i) {
  const uint64_t n = 1ull << aw.size, start = aw.addr, aligned = start & ~(n - 1);
  if (aw.burst == 0 || i == 0) return start;  // FIXED, or the first beat
  if (aw.burst == 2) {                         // WRAP
    const uint64_t span = n * (uint64_t(aw.len) + 1), lo = start & ~(span - 1);
    return lo + ((aligned + i * n - lo) % span);
  }
  return aligned + i * n;  // INCR
}

// A burst accepted: its response decided now (the region, the injected errors), its rules checked.
void axi_accept(Sim& s, AxiAw aw) {
  Axi& a = s.axi;
  aw.index = a.st[AX_BURSTS]++;
  aw.cycle = s.cycle;
  const uint64_t n = 1ull << aw.size, bytes = n * (uint64_t(aw.len) + 1);
  if (aw.size > 3 || aw.burst == 3) axi_protocol(a, s.cycle);  // wider than the 64-bit bus; reserved burst
  if (aw.burst == 2 && !(aw.len == 1 || aw.len == 3 || aw.len == 7 || aw.len == 15)) axi_protocol(a, s.cycle);
  if (aw.burst == 1 && (aw.addr >> 12) != ((uint64_t(aw.addr & ~uint32_t(n - 1)) + bytes - 1) >> 12))
    axi_protocol(a, s.cycle);  // an INCR burst must not cross 4 KiB
  // the bytes it may touch: [first, first + span)
  const uint64_t lo = aw.burst == 2 ? (uint64_t(aw.addr) & ~(bytes - 1)) : uint64_t(aw.addr & ~uint32_t(n - 1));
  const uint64_t span = aw.burst == 0 ? n : bytes;
  aw.resp = 0;
  if (lo < a.base || lo + span > a.base + a.mem.size()) {
    aw.resp = 3;
    aw.outside = true;
    a.st[AX_REFUSED]++;
  } else {
    auto e = a.errors.find(aw.index);
    auto ae = std::find_if(a.addr_errors.begin(), a.addr_errors.end(),
                           [&](const std::pair<uint32_t, uint8_t>& x) { return x.first == aw.addr; });
    if (e != a.errors.end()) {
      aw.resp = e->second;
      a.errors.erase(e);
    } else if (ae != a.addr_errors.end()) {
      aw.resp = ae->second;
      a.addr_errors.erase(ae);
    } else if (auto r = std::find_if(a.error_rules.begin(), a.error_rules.end(),
                                     [&](const AxiErrorRule& x) {
                                       return aw.index == x.first ||
                                              (x.every && aw.index > x.first && (aw.index - x.first) % x.every == 0);
                                     });
               r != a.error_rules.end()) {
      aw.resp = r->resp;
    } else if (a.err_permille && (xorshift(a.rng) % 1000) < a.err_permille) {
      aw.resp = a.err_resp;
    }
    if (aw.resp) a.st[AX_INJECTED]++;
  }
  a.aw_q.push_back(aw);
  const uint64_t outstanding = a.aw_q.size() + a.b_q.size();
  if (outstanding > a.st[AX_MAX_OUTSTANDING]) a.st[AX_MAX_OUTSTANDING] = outstanding;
}

// Beats matched to their bursts, in order; a burst complete (its last beat) goes to the responses.
void axi_match(Sim& s) {
  Axi& a = s.axi;
  while (!a.aw_q.empty() && !a.w_q.empty()) {
    AxiAw& aw = a.aw_q.front();
    const AxiW w = a.w_q.front();
    a.w_q.pop_front();
    const uint32_t i = aw.beats++;
    if (i < 4) aw.data[i] = w.data;
    const bool last = aw.beats == uint32_t(aw.len) + 1;
    if (w.last != last) axi_protocol(a, s.cycle);
    if (aw.outside) {
      a.st[AX_REFUSED_BEATS]++;
    } else if (aw.resp != 0) {
      a.st[AX_ERROR_BEATS]++;
    } else {
      const uint64_t addr = axi_beat_addr(aw, i), n = 1ull << (aw.size > 3 ? 3 : aw.size);
      const uint64_t word = addr & ~7ull;
      const uint32_t first = uint32_t(addr & 7), end = uint32_t((addr & ~(n - 1)) - word + n);
      for (uint32_t lane = first; lane < end && lane < 8; lane++) {
        if (!(w.strb >> lane & 1)) continue;
        a.mem[word + lane - a.base] = uint8_t(w.data >> (8 * lane));
        a.st[AX_BYTES]++;
      }
    }
    if (last) {
      const uint64_t jitter = a.b_jitter ? xorshift(a.rng) % (a.b_jitter + 1) : 0;
      uint64_t ready = s.cycle + a.b_delay + jitter;
      if (!a.b_q.empty() && a.b_q.back().ready_cycle > ready) ready = a.b_q.back().ready_cycle;
      a.b_q.push_back(AxiB{aw, s.cycle, ready});
      a.aw_q.pop_front();
    }
  }
  uint64_t expect = 0;
  for (const AxiAw& aw : a.aw_q) expect += uint64_t(aw.len) + 1 - aw.beats;
  if (a.w_q.size() > expect && a.w_q.size() - expect > a.st[AX_MAX_W_AHEAD]) a.st[AX_MAX_W_AHEAD] = a.w_q.size() - expect;
}

// After the edge: the handshakes of the clock take effect.
void axi_advance(Sim& s) {
  Axi& a = s.axi;
  if (a.b_fire) {
    const AxiB b = a.b_q.front();
    a.b_q.pop_front();
    a.bvalid = false;
    a.st[AX_RESPONSES]++;
    a.st[b.aw.resp == 0 ? AX_OKAY : b.aw.resp == 3 ? AX_DECERR : AX_SLVERR]++;
    if (a.log_on) {
      AxiLogEntry e{b.aw.index, b.aw.cycle, b.done_cycle, s.cycle, b.aw.addr, b.aw.resp,
                    {b.aw.data[0], b.aw.data[1], b.aw.data[2], b.aw.data[3]}, b.aw.beats};
      a.log.push_back(e);
    }
  }
  if (a.aw_fire) axi_accept(s, a.aw_in);
  if (a.w_fire) {
    a.w_q.push_back(a.w_in);
    a.st[AX_BEATS]++;
  }
  if (a.aw_fire || a.w_fire) axi_match(s);
}

bool source_has_beat(const Sim& s) {
  return s.idle == 0 && s.prog < s.programs.size() && s.pos < s.programs[s.prog].beats.size();
}

void drive(Sim& s) {
  Vorb_accel_top* t = s.top.get();
  if (s.live) {
    t->s_axis_video_tvalid = !s.fifo.empty();
    const Queued q = s.fifo.empty() ? Queued{0, 0, 0, false} : s.fifo.front();
    t->s_axis_video_tdata = q.data;
    t->s_axis_video_tuser = q.flags & 1;
    t->s_axis_video_tlast = (q.flags >> 1) & 1;
  } else if (source_has_beat(s)) {
    const Beat& b = s.programs[s.prog].beats[s.pos];
    t->s_axis_video_tvalid = 1;
    t->s_axis_video_tdata = b.data;
    t->s_axis_video_tuser = b.flags & 1;
    t->s_axis_video_tlast = (b.flags >> 1) & 1;
  } else {
    t->s_axis_video_tvalid = 0;
    t->s_axis_video_tuser = 0;
    t->s_axis_video_tlast = 0;
  }
  t->m_axis_video_tready = (s.ready_permille >= 1000) ? 1 : ((xorshift(s.rng) % 1000) < s.ready_permille);
  axi_drive(s);
}

// The next beat of the programs is sent (both sources): the position advances, idle = its gap.
Beat next_beat(Sim& s) {
  Program& p = s.programs[s.prog];
  const Beat b = p.beats[s.pos];
  s.idle = b.gap;
  s.pos++;
  if (s.pos == p.beats.size()) {
    s.pos = 0;
    // a program sent is not needed again unless the queue loops: its beats are freed (a long
    // campaign queues tens of thousands of frames; set_loop must come before the sending)
    if (!s.loop) std::vector<Beat>().swap(p.beats);
    s.prog++;
    if (s.prog == s.programs.size() && s.loop) s.prog = 0;
  }
  return b;
}

// A live source's pixel clock ticks num/den times per clock: one pixel slot each, blanking (the
// gap after the last beat) or the next beat into the FIFO, dropped when the FIFO is full.
void live_advance(Sim& s) {
  s.live_acc += s.live_num;
  if (s.live_acc < s.live_den) return;
  s.live_acc -= s.live_den;
  if (s.idle > 0) {
    s.idle--;
    return;
  }
  if (s.prog >= s.programs.size()) return;
  const uint32_t prog = uint32_t(s.prog);
  const bool first = s.pos == 0;
  const Beat b = next_beat(s);
  if (s.fifo.size() >= s.fifo_depth) {
    s.fifo_dropped++;
    return;
  }
  s.fifo.push_back(Queued{b.data, b.flags, prog, first});
  if (s.fifo.size() > s.fifo_max) s.fifo_max = s.fifo.size();
}

// One clock: returns after the rising edge. The AXI4-Lite inputs are whatever the caller set.
void tick(Sim& s) {
  Vorb_accel_top* t = s.top.get();
  drive(s);
  t->clk = 0;
  t->eval();
  s.ctx->timeInc(5);
  const bool in_fire = t->s_axis_video_tvalid && t->s_axis_video_tready;
  const bool out_fire = t->m_axis_video_tvalid && t->m_axis_video_tready;
  const uint32_t out_data = t->m_axis_video_tdata;
  const uint8_t out_flags = uint8_t(t->m_axis_video_tuser | (t->m_axis_video_tlast << 1));
  s.ar_fire = t->s_axil_arvalid && t->s_axil_arready;
  s.r_fire = t->s_axil_rvalid && t->s_axil_rready;
  s.aw_fire = t->s_axil_awvalid && t->s_axil_awready;
  s.w_fire = t->s_axil_wvalid && t->s_axil_wready;
  s.b_fire = t->s_axil_bvalid && t->s_axil_bready;
  s.rdata = t->s_axil_rdata;
  s.rresp = t->s_axil_rresp;
  s.bresp = t->s_axil_bresp;
  axi_sample(s);
  if (t->s_axis_video_tvalid && !t->s_axis_video_tready) {
    if (++s.stall > s.stall_max) s.stall_max = s.stall;
  } else {
    s.stall = 0;
  }
  t->clk = 1;
  t->eval();
  s.ctx->timeInc(5);
  s.cycle++;
  axi_advance(s);
  if (s.live) {
    if (in_fire) {
      const Queued q = s.fifo.front();
      s.fifo.pop_front();
      if (q.first) {
        s.frames_started++;
        s.frame_start_cycles.push_back(s.cycle);
        s.frame_start_prog.push_back(q.prog);
      }
      s.beats_sent++;
      s.last_beat_cycle = s.cycle;
    }
    live_advance(s);
  } else if (in_fire) {
    if (s.pos == 0) {
      s.frames_started++;
      s.frame_start_cycles.push_back(s.cycle);
      s.frame_start_prog.push_back(uint32_t(s.prog));
    }
    next_beat(s);
    s.beats_sent++;
    s.last_beat_cycle = s.cycle;
  } else if (s.idle > 0 && !(t->s_axis_video_tvalid)) {
    s.idle--;
  }
  if (out_fire) {
    s.out_beats++;
    if (s.capture) {
      s.out_data.push_back(out_data);
      s.out_flags.push_back(out_flags);
    }
  }
  const bool irq = t->irq;
  if (irq && !s.irq_last) {
    s.irq_rise_cycle = s.cycle;
    s.irq_rises++;
  }
  s.irq_last = irq;
}

}  // namespace

extern "C" {

// Create the model with Verilator's random initial state from `seed` (0: all zero); `args` as on
// a command line (e.g. "+verilator+rand+reset+2"), may be empty.
void* fs_new(uint32_t seed) {
  auto* s = new Sim;
  s->ctx = std::make_unique<VerilatedContext>();
  std::string reset = "+verilator+rand+reset+" + std::string(seed ? "2" : "0");
  std::string seed_arg = "+verilator+seed+" + std::to_string(seed ? seed : 1);
  const char* argv[] = {"fastsim", reset.c_str(), seed_arg.c_str()};
  s->ctx->commandArgs(3, argv);
  s->top = std::make_unique<Vorb_accel_top>(s->ctx.get(), "top");
  Vorb_accel_top* t = s->top.get();
  t->clk = 0;
  t->rst = 1;
  t->s_axil_awvalid = 0;
  t->s_axil_wvalid = 0;
  t->s_axil_bready = 0;
  t->s_axil_arvalid = 0;
  t->s_axil_rready = 0;
  t->s_axil_awprot = 0;
  t->s_axil_arprot = 0;
  t->s_axil_wstrb = 0xF;
  t->m_axi_feat_awready = 0;
  t->m_axi_feat_wready = 0;
  t->m_axi_feat_bvalid = 0;
  t->m_axi_feat_bresp = 0;
  t->eval();
  return s;
}

void fs_free(void* h) {
  auto* s = static_cast<Sim*>(h);
  s->top->final();
  delete s;
}

uint64_t fs_cycle(void* h) { return static_cast<Sim*>(h)->cycle; }

void fs_set_rst(void* h, int value) { static_cast<Sim*>(h)->top->rst = value ? 1 : 0; }

void fs_run(void* h, uint64_t clocks) {
  auto* s = static_cast<Sim*>(h);
  for (uint64_t i = 0; i < clocks; i++) tick(*s);
}

// Queue a beat program (a frame, or any beat sequence) for the video source.
void fs_push(void* h, const uint32_t* data, const uint8_t* flags, const uint32_t* gaps, uint64_t n) {
  auto* s = static_cast<Sim*>(h);
  Program p;
  p.beats.resize(n);
  for (uint64_t i = 0; i < n; i++) p.beats[i] = Beat{data[i], flags[i], gaps[i]};
  s->programs.push_back(std::move(p));
}

void fs_set_loop(void* h, int loop) { static_cast<Sim*>(h)->loop = loop != 0; }

// The source becomes live (see the top): a pixel clock of num/den of the clock (num <= den), a
// FIFO of `depth` beats that drops on overflow.
void fs_live(void* h, uint64_t num, uint64_t den, uint64_t depth) {
  auto* s = static_cast<Sim*>(h);
  s->live = true;
  s->live_num = num;
  s->live_den = den;
  s->live_acc = 0;
  s->fifo_depth = depth;
}

bool video_done(const Sim& s) { return s.prog >= s.programs.size() && s.fifo.empty(); }

// Run until the source has sent everything queued (or `timeout` clocks): 1 when done.
int fs_run_video(void* h, uint64_t timeout) {
  auto* s = static_cast<Sim*>(h);
  for (uint64_t i = 0; i < timeout; i++) {
    if (video_done(*s)) return 1;
    tick(*s);
  }
  return video_done(*s) ? 1 : 0;
}

// stats[0..9]: frames started, beats sent, cycle of the last beat, longest input stall, overlay
// beats out, cycle of the last irq rise, irq rises, cycle, beats a live source's FIFO dropped, its
// highest fill.
void fs_stats(void* h, uint64_t* stats) {
  auto* s = static_cast<Sim*>(h);
  uint64_t v[10] = {s->frames_started, s->beats_sent,     s->last_beat_cycle, s->stall_max,    s->out_beats,
                    s->irq_rise_cycle, s->irq_rises,      s->cycle,           s->fifo_dropped, s->fifo_max};
  std::memcpy(stats, v, sizeof v);
}

// The i-th frame start: its program index and cycle (-1 when there is none).
int64_t fs_frame_start(void* h, uint64_t i, uint64_t* cycle) {
  auto* s = static_cast<Sim*>(h);
  if (i >= s->frame_start_cycles.size()) return -1;
  *cycle = s->frame_start_cycles[i];
  return s->frame_start_prog[i];
}

void fs_set_out_ready(void* h, uint32_t permille, uint64_t seed) {
  auto* s = static_cast<Sim*>(h);
  s->ready_permille = permille;
  s->rng = seed ? seed : 0x9E3779B97F4A7C15ull;
}

void fs_capture(void* h, int on) {
  auto* s = static_cast<Sim*>(h);
  s->capture = on != 0;
  if (!on) {
    s->out_data.clear();
    s->out_flags.clear();
  }
}

// Copy up to `max` captured overlay beats; returns how many there are in all.
uint64_t fs_captured(void* h, uint32_t* data, uint8_t* flags, uint64_t max) {
  auto* s = static_cast<Sim*>(h);
  const uint64_t n = s->out_data.size() < max ? s->out_data.size() : max;
  if (n) {
    std::memcpy(data, s->out_data.data(), n * 4);
    std::memcpy(flags, s->out_flags.data(), n);
  }
  return s->out_data.size();
}

// AXI4-Lite single read: returns the response (0 OKAY .. 3), or -1 when no answer came within
// `timeout` clocks per channel.
int fs_read(void* h, uint32_t addr, uint32_t* data, uint64_t timeout) {
  auto* s = static_cast<Sim*>(h);
  Vorb_accel_top* t = s->top.get();
  t->s_axil_araddr = addr;
  t->s_axil_arvalid = 1;
  t->s_axil_rready = 1;
  bool ar_done = false;
  for (uint64_t i = 0; i < timeout; i++) {
    tick(*s);
    if (s->ar_fire) {
      ar_done = true;
      t->s_axil_arvalid = 0;
    }
    if (s->r_fire && ar_done) {
      t->s_axil_rready = 0;
      *data = s->rdata;
      return s->rresp;
    }
  }
  t->s_axil_arvalid = 0;
  t->s_axil_rready = 0;
  return -1;
}

// `count` consecutive reads from `addr`; returns the first non-OKAY response, or -1 on a timeout,
// else 0.
int fs_read_block(void* h, uint32_t addr, uint32_t* out, uint64_t count, uint64_t timeout) {
  for (uint64_t i = 0; i < count; i++) {
    const int r = fs_read(h, addr + uint32_t(4 * i), &out[i], timeout);
    if (r != 0) return r;
  }
  return 0;
}

// AXI4-Lite single write (all byte lanes): the response, or -1 on a timeout.
int fs_write(void* h, uint32_t addr, uint32_t value, uint64_t timeout) {
  auto* s = static_cast<Sim*>(h);
  Vorb_accel_top* t = s->top.get();
  t->s_axil_awaddr = addr;
  t->s_axil_awvalid = 1;
  t->s_axil_wdata = value;
  t->s_axil_wstrb = 0xF;
  t->s_axil_wvalid = 1;
  t->s_axil_bready = 1;
  bool aw_done = false, w_done = false;
  for (uint64_t i = 0; i < timeout; i++) {
    tick(*s);
    if (s->aw_fire) {
      aw_done = true;
      t->s_axil_awvalid = 0;
    }
    if (s->w_fire) {
      w_done = true;
      t->s_axil_wvalid = 0;
    }
    if (s->b_fire && aw_done && w_done) {
      t->s_axil_bready = 0;
      return s->bresp;
    }
  }
  t->s_axil_awvalid = 0;
  t->s_axil_wvalid = 0;
  t->s_axil_bready = 0;
  return -1;
}

// Run until the interrupt line is high (1) or `timeout` clocks have passed (0).
int fs_wait_irq(void* h, uint64_t timeout) {
  auto* s = static_cast<Sim*>(h);
  Vorb_accel_top* t = s->top.get();
  for (uint64_t i = 0; i <= timeout; i++) {
    if (t->irq) return 1;
    if (i < timeout) tick(*s);
  }
  return t->irq ? 1 : 0;
}

// ---- the DDR (m_axi_feat's slave) ----

// The memory: [base, base + size), zeroed; 0, or -1 when the region is empty, leaves the 32-bit
// address space or is larger than 1 GiB.
int fs_mem_region(void* h, uint64_t base, uint64_t size) {
  auto* s = static_cast<Sim*>(h);
  if (size == 0 || size > (1ull << 30) || base + size > (1ull << 32)) return -1;
  s->axi.base = base;
  std::vector<uint8_t>(size, 0).swap(s->axi.mem);
  return 0;
}

void fs_mem_info(void* h, uint64_t* base, uint64_t* size) {
  auto* s = static_cast<Sim*>(h);
  *base = s->axi.base;
  *size = s->axi.mem.size();
}

// Copy n bytes at address addr out of (read) or into (write) the memory: 0, or -1 outside it.
int fs_mem_read(void* h, uint64_t addr, uint8_t* out, uint64_t n) {
  auto* s = static_cast<Sim*>(h);
  const Axi& a = s->axi;
  if (addr < a.base || addr + n > a.base + a.mem.size()) return -1;
  if (n) std::memcpy(out, a.mem.data() + (addr - a.base), n);
  return 0;
}

int fs_mem_write(void* h, uint64_t addr, const uint8_t* in, uint64_t n) {
  auto* s = static_cast<Sim*>(h);
  Axi& a = s->axi;
  if (addr < a.base || addr + n > a.base + a.mem.size()) return -1;
  if (n) std::memcpy(a.mem.data() + (addr - a.base), in, n);
  return 0;
}

// The slave's timing: AWREADY and WREADY each high with a probability (permille, 1000: always),
// the write response `b_delay` clocks after the last beat plus 0..b_jitter more (in order), at most
// `outstanding` bursts accepted and not answered, at most `w_ahead` W beats taken before their AW;
// `seed` (not 0) restarts the random draws.
void fs_axi_timing(void* h, uint32_t aw_permille, uint32_t w_permille, uint64_t b_delay, uint64_t b_jitter,
                   uint64_t outstanding, uint64_t w_ahead, uint64_t seed) {
  Axi& a = static_cast<Sim*>(h)->axi;
  a.aw_permille = aw_permille;
  a.w_permille = w_permille;
  a.b_delay = b_delay;
  a.b_jitter = b_jitter;
  a.max_outstanding = outstanding ? outstanding : 1;
  a.max_w_ahead = w_ahead;
  if (seed) a.rng = seed;
}

// A stall: cycles [start, end), mask bit 0 AWREADY low, bit 1 WREADY low, bit 2 no new BVALID.
void fs_axi_window(void* h, uint64_t start, uint64_t end, uint32_t mask) {
  Axi& a = static_cast<Sim*>(h)->axi;
  auto& w = a.windows;
  const uint64_t now = static_cast<Sim*>(h)->cycle;
  w.erase(std::remove_if(w.begin(), w.end(), [now](const AxiWindow& x) { return !x.period && x.end <= now; }),
          w.end());
  if (end > start && mask) w.push_back(AxiWindow{start, end, mask});
}

// A stall that repeats: clocks [phase, phase + length) of every `period` clocks (length < period).
void fs_axi_period(void* h, uint64_t period, uint64_t phase, uint64_t length, uint32_t mask) {
  if (!period || !length || !mask) return;
  if (length >= period) length = period - 1;
  phase %= period;
  Axi& a = static_cast<Sim*>(h)->axi;
  // a window that wraps past the period's end is two
  const uint64_t end = phase + length;
  a.windows.push_back(AxiWindow{phase, end < period ? end : period, mask, period});
  if (end > period) a.windows.push_back(AxiWindow{0, end - period, mask, period});
}

void fs_axi_clear_windows(void* h) { static_cast<Sim*>(h)->axi.windows.clear(); }

// The burst of this index (counted from 0 over every AW handshake since the model was made) is
// answered `resp` (2 SLVERR, 3 DECERR) and not stored; `permille` > 0: each burst with that
// probability (fs_axi_error_rate).
void fs_axi_error(void* h, uint64_t index, uint32_t resp) { static_cast<Sim*>(h)->axi.errors[index] = uint8_t(resp); }

// Bursts `first`, first + every, .. (every 0: `first` only) answered `resp` and not stored.
void fs_axi_error_every(void* h, uint64_t first, uint64_t every, uint32_t resp) {
  static_cast<Sim*>(h)->axi.error_rules.push_back(AxiErrorRule{first, every, uint8_t(resp)});
}

// The next burst whose AWADDR is `addr` is answered `resp` and not stored (once).
void fs_axi_error_addr(void* h, uint32_t addr, uint32_t resp) {
  static_cast<Sim*>(h)->axi.addr_errors.emplace_back(addr, uint8_t(resp));
}

void fs_axi_error_rate(void* h, uint32_t permille, uint32_t resp) {
  Axi& a = static_cast<Sim*>(h)->axi;
  a.err_permille = permille;
  a.err_resp = uint8_t(resp);
}

void fs_axi_clear_errors(void* h) {
  Axi& a = static_cast<Sim*>(h)->axi;
  a.errors.clear();
  a.addr_errors.clear();
  a.error_rules.clear();
  a.err_permille = 0;
}

// stats[0..AX_N-1]: the AxiStat counters (sim.py's AXI_STATS), and the bursts in the channels now:
// stats[AX_N] accepted with data missing, stats[AX_N + 1] waiting for their response,
// stats[AX_N + 2] W beats before their AW.
uint64_t fs_axi_stats(void* h, uint64_t* stats, uint64_t max) {
  const Axi& a = static_cast<Sim*>(h)->axi;
  uint64_t v[AX_N + 3];
  std::memcpy(v, a.st, sizeof a.st);
  v[AX_N] = a.aw_q.size();
  v[AX_N + 1] = a.b_q.size();
  uint64_t expect = 0;
  for (const AxiAw& aw : a.aw_q) expect += uint64_t(aw.len) + 1 - aw.beats;
  v[AX_N + 2] = a.w_q.size() > expect ? a.w_q.size() - expect : 0;
  const uint64_t n = max < AX_N + 3 ? max : AX_N + 3;
  std::memcpy(stats, v, n * sizeof(uint64_t));
  return AX_N + 3;
}

// The log of finished bursts (on: from now; off: stop and forget it).
void fs_axi_log(void* h, int on) {
  Axi& a = static_cast<Sim*>(h)->axi;
  a.log_on = on != 0;
  if (!on) std::vector<AxiLogEntry>().swap(a.log);
}

// Move up to `max` entries of the log out (the oldest first); returns how many there were in all.
uint64_t fs_axi_log_take(void* h, AxiLogEntry* out, uint64_t max) {
  Axi& a = static_cast<Sim*>(h)->axi;
  const uint64_t all = a.log.size(), n = all < max ? all : max;
  if (n) {
    std::memcpy(out, a.log.data(), n * sizeof(AxiLogEntry));
    a.log.erase(a.log.begin(), a.log.begin() + long(n));
  }
  return all;
}

uint64_t fs_axi_log_entry_bytes() { return sizeof(AxiLogEntry); }

// Toggle coverage (a build with --coverage-toggle: orb_sim.fast.activity, orb_flow.power): zero the
// counters, or write them to `path` (Verilator's coverage.dat). 0: the build has no coverage.
int fs_coverage_zero(void* h) {
#if VM_COVERAGE
  static_cast<Sim*>(h)->ctx->coveragep()->zero();
  return 1;
#else
  (void)h;
  return 0;
#endif
}

int fs_coverage_write(void* h, const char* path) {
#if VM_COVERAGE
  static_cast<Sim*>(h)->ctx->coveragep()->write(path);
  return 1;
#else
  (void)h;
  (void)path;
  return 0;
#endif
}

}  // extern "C"
