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
#include <cstdint>
#include <cstring>
#include <deque>
#include <memory>
#include <vector>

#include "Vorb_accel_top.h"
#include "verilated.h"

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
};

uint64_t xorshift(uint64_t& s) {
  s ^= s << 13;
  s ^= s >> 7;
  s ^= s << 17;
  return s;
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
  if (t->s_axis_video_tvalid && !t->s_axis_video_tready) {
    if (++s.stall > s.stall_max) s.stall_max = s.stall;
  } else {
    s.stall = 0;
  }
  t->clk = 1;
  t->eval();
  s.ctx->timeInc(5);
  s.cycle++;
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

}  // extern "C"
