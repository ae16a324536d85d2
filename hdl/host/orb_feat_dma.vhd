-- SPDX-License-Identifier: MIT
-- orb_feat_dma: the feature memory of the DDR builds. It takes the feature stream of orb_core
-- (s_axis_feat, orb_feat_pkg; tready is always 1) with orb_feat_mem's rules for which beat goes to
-- which slot (a sel_replace beat over its sel_slot's slot, through a map of SEL_SLOTS_g entries;
-- at most DEPTH_g - 1 features, further ones truncated and counted), and writes each frame into a
-- ring of ring_count frame buffers in DDR (buffer i at ring_base + i * ring_stride, DEPTH_g slots
-- of 64 bytes: the end-of-frame record in slot 0, the features in slots 1 .. count) through an
-- AXI4 write master, m_axi_feat: one INCR burst of 8 beats of 64 bits per slot, AWVALID and WVALID
-- raised together, at most OUTSTANDING_g bursts waiting for their response, BREADY 1. Slots wait
-- in a burst FIFO of FIFO_DEPTH_g entries (orb_feat_fifo); a frame that finds it full is dropped
-- and counted (dma_dropped), never written in part and published. A frame is published (READY in
-- ring_ready, frame_done for one clock) when the write response of its record, its last burst,
-- arrives, if none of its bursts was answered with an error; error responses are counted. The CPU
-- releases a buffer with release_valid and release_index. ring_error checks the ring registers
-- (alignment, overlap, the DDR window of WIN_BASE_MB_g and WIN_SIZE_MB_g MiB, count 0) 5 clocks
-- after they change; a frame that starts while it is not 0, or within 5 clocks of a change of the
-- registers, is dropped and nothing is written. The
-- master writes with a copy of the ring loaded at a frame's first beat when nothing is queued or in
-- flight, so every address it issues lies in a buffer of a checked ring. rst (soft reset) resets
-- the frames, the FIFO, the buffers and the counters but finishes a burst whose valids are up and
-- takes (ignores) the responses of bursts issued before it: the bus stays legal. bus_rst resets
-- the master at once (the AXI reset). Every input is registered once before the rules apply; a
-- slot reaches AWVALID at the earliest 7 clocks after its beat (input register, FIFO write
-- register, FIFO, the master's load and three address stages). Protocol, layout and decisions:
-- docs/feature-dma.md.
-- Ports and generics: docs/entities/orb_feat_dma.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_feat_pkg.all;
use work.orb_limits_pkg.all;
use work.orb_slot_pkg.all;

entity orb_feat_dma is
  generic (
    DEPTH_g       : mem_depth_t               := 1024; -- slots per buffer (one for the record)
    SEL_SLOTS_g   : positive range 2 to 8192  := 1024; -- the selection's slots (sel_slot < SEL_SLOTS_g)
    FIFO_DEPTH_g  : positive range 16 to 4096 := 256;  -- slots the burst FIFO holds (a power of two)
    OUTSTANDING_g : positive range 1 to 8     := 4;    -- bursts waiting for their response, at most
    WIN_BASE_MB_g : natural range 0 to 4095   := 0;    -- the DDR window the ring must lie in, MiB
    WIN_SIZE_MB_g : positive range 1 to 4096  := 4096
  );
  port (
    clk     : in    std_logic;
    rst     : in    std_logic;
    bus_rst : in    std_logic;
    -- feature stream
    s_axis_feat_tdata  : in    std_logic_vector(FEAT_BITS_c - 1 downto 0);
    s_axis_feat_tvalid : in    std_logic;
    s_axis_feat_tready : out   std_logic;
    s_axis_feat_tlast  : in    std_logic;
    frame_abort        : in    std_logic;
    -- the ring (RING_BASE, RING_STRIDE, RING_COUNT) and its hand-over to the CPU
    ring_base     : in    std_logic_vector(31 downto 0);
    ring_stride   : in    std_logic_vector(31 downto 0);
    ring_count    : in    std_logic_vector(4 downto 0);
    release_valid : in    std_logic;
    release_index : in    std_logic_vector(3 downto 0);
    frame_done    : out   std_logic;
    dma_error     : out   std_logic;
    ring_ready    : out   std_logic_vector(15 downto 0);
    ring_last     : out   std_logic_vector(3 downto 0);
    ring_error    : out   std_logic_vector(3 downto 0);
    busy          : out   std_logic;
    last_count    : out   std_logic_vector(15 downto 0);
    last_frame    : out   std_logic_vector(15 downto 0);
    overrun       : out   std_logic_vector(31 downto 0);
    overflow      : out   std_logic_vector(31 downto 0);
    aborted       : out   std_logic_vector(31 downto 0);
    dma_dropped   : out   std_logic_vector(31 downto 0);
    bus_errors    : out   std_logic_vector(31 downto 0);
    beats         : out   std_logic_vector(31 downto 0);
    -- AXI4 write master
    m_axi_feat_awid    : out   std_logic_vector(0 downto 0);
    m_axi_feat_awaddr  : out   std_logic_vector(31 downto 0);
    m_axi_feat_awlen   : out   std_logic_vector(7 downto 0);
    m_axi_feat_awsize  : out   std_logic_vector(2 downto 0);
    m_axi_feat_awburst : out   std_logic_vector(1 downto 0);
    m_axi_feat_awcache : out   std_logic_vector(3 downto 0);
    m_axi_feat_awprot  : out   std_logic_vector(2 downto 0);
    m_axi_feat_awvalid : out   std_logic;
    m_axi_feat_awready : in    std_logic;
    m_axi_feat_wdata   : out   std_logic_vector(63 downto 0);
    m_axi_feat_wstrb   : out   std_logic_vector(7 downto 0);
    m_axi_feat_wlast   : out   std_logic;
    m_axi_feat_wvalid  : out   std_logic;
    m_axi_feat_wready  : in    std_logic;
    m_axi_feat_bid     : in    std_logic_vector(0 downto 0);
    m_axi_feat_bresp   : in    std_logic_vector(1 downto 0);
    m_axi_feat_bvalid  : in    std_logic;
    m_axi_feat_bready  : out   std_logic
  );
end entity orb_feat_dma;

architecture rtl of orb_feat_dma is

  constant SLOT_BITS_c : positive := clog2(DEPTH_g);
  constant LAST_SLOT_c : natural  := DEPTH_g - 1;   -- cnt at this value: the buffer is full
  constant MAP_BITS_c  : positive := clog2(SEL_SLOTS_g);
  constant BUF_BYTES_c : natural  := DEPTH_g * 64;  -- one buffer
  constant BEATS_c     : positive := 8;             -- 64-bit beats a 64-byte slot
  constant DATA_BITS_c : positive := SLOT_DATA_BITS_c;
  constant OUT_BITS_c  : positive := clog2(OUTSTANDING_g + 1);
  constant FIFO_BITS_c : positive := clog2(FIFO_DEPTH_g);
  constant SETTLE_c    : positive := 4;             -- edges from cfg_* to ring_err
  -- a FIFO entry: the slot's data, its slot number in the buffer, the buffer, the record flag and
  -- the first flag (the frame's first slot: the write responses of a frame begin with it)
  constant E_SLOT_LO_c  : natural  := DATA_BITS_c;
  constant E_INDEX_LO_c : natural  := E_SLOT_LO_c + SLOT_BITS_c;
  constant E_REC_BIT_c  : natural  := E_INDEX_LO_c + 4;
  constant E_FIRST_c    : natural  := E_REC_BIT_c + 1;
  constant ENTRY_BITS_c : positive := E_FIRST_c + 1;
  -- the window, in bytes, 37 bits (no wrap at 2^32)
  constant WIN_LO_c : unsigned(36 downto 0) := shift_left(to_unsigned(WIN_BASE_MB_g, 37), 20);
  constant WIN_HI_c : unsigned(36 downto 0) := shift_left(to_unsigned(WIN_BASE_MB_g + WIN_SIZE_MB_g, 37), 20);

  type map_t is array (0 to 2 ** MAP_BITS_c - 1) of unsigned(SLOT_BITS_c - 1 downto 0);

  -- what the frame side needs of a burst when its response comes
  type meta_t is record
    rec   : std_logic;                        -- the burst is a frame's record
    first : std_logic;                        -- ... its frame's first
    index : unsigned(3 downto 0);             -- its buffer
    count : unsigned(SLOT_BITS_c - 1 downto 0);
    frame : std_logic_vector(15 downto 0);
  end record meta_t;

  constant META_ZERO_c : meta_t :=
  (
    rec   => '0',
    first => '0',
    index => (others => '0'),
    count => (others => '0'),
    frame => (others => '0')
  );

  type meta_array_t is array (0 to OUTSTANDING_g - 1) of meta_t;
  type engine_t is (idle_s, addr1_s, addr2_s, addr3_s, burst_s);

  -- k(1 downto 0) * v, 36 bits (one adder; k * v for 4 bits is two of these, the second << 2)
  function times2 (k : unsigned(1 downto 0); v : unsigned(31 downto 0)) return unsigned is
    variable a_v : unsigned(35 downto 0) := (others => '0');
    variable b_v : unsigned(35 downto 0) := (others => '0');
  begin
    if k(0) = '1' then
      a_v := resize(v, 36);
    end if;
    if k(1) = '1' then
      b_v := shift_left(resize(v, 36), 1);
    end if;
    return a_v + b_v;
  end function times2;

  -- the inputs, registered (the rules below apply to these)
  signal in_data  : std_logic_vector(FEAT_BITS_c - 1 downto 0) := (others => '0');
  signal in_beat  : std_logic := '0';
  signal in_last  : std_logic := '0';
  signal in_abort : std_logic := '0';
  signal in_rel   : std_logic := '0';
  signal in_reli  : unsigned(3 downto 0) := (others => '0');

  -- the selection's slot map (as orb_feat_mem); it holds a feature's buffer slot (its index + 1),
  -- so that no adder sits between the map's output and the FIFO entry (the timing path)
  signal smap     : map_t := (others => (others => '0'));
  signal map_q    : unsigned(SLOT_BITS_c - 1 downto 0) := (others => '0');
  signal fwd_ok   : std_logic := '0';
  signal fwd_eq   : std_logic := '0';  -- the beat's selection slot is the one of the beat before
  signal fwd_slot : unsigned(SLOT_BITS_c - 1 downto 0) := (others => '0');
  signal repl     : std_logic;
  signal slot     : unsigned(SLOT_BITS_c - 1 downto 0);

  -- the ring registers (registered), their checks and the active ring
  signal cfg_base    : unsigned(31 downto 0) := (others => '0');
  signal cfg_stride  : unsigned(31 downto 0) := (others => '0');
  signal cfg_count   : unsigned(4 downto 0) := (others => '0');
  signal cfg_last    : unsigned(3 downto 0) := (others => '0');  -- count - 1 (0 for count 0), beside cfg_count
  signal settle      : unsigned(2 downto 0) := to_unsigned(SETTLE_c, 3);  -- clocks until ring_err is theirs
  signal chk_lo      : unsigned(35 downto 0) := (others => '0');  -- (count - 1) * stride, bits 1..0
  signal chk_hi      : unsigned(35 downto 0) := (others => '0');  -- ... bits 3..2
  signal chk_end     : unsigned(36 downto 0) := (others => '0');  -- base + one buffer
  signal chk_below   : std_logic := '0';                          -- base below the window
  signal chk_prod    : unsigned(36 downto 0) := (others => '0');
  signal chk_top     : unsigned(36 downto 0) := (others => '0');  -- the ring's end
  signal chk_err1    : std_logic_vector(3 downto 0) := "1000";    -- unaligned, overlap, outside, off
  signal chk_err2    : std_logic_vector(3 downto 0) := "1000";
  signal ring_err    : std_logic_vector(3 downto 0) := "1000";
  signal ring_ok     : std_logic := '0';                          -- checked and no error (registered)
  signal ring_ok_now : std_logic;                                -- ... and the registers unchanged since
  signal act_base    : unsigned(31 downto 0) := (others => '0');
  signal act_stride  : unsigned(31 downto 0) := (others => '0');
  signal act_count   : unsigned(4 downto 0) := (others => '0');
  signal act_same    : std_logic := '0';                          -- the active ring is cfg_* (a clock ago)

  -- the frames (input side)
  signal pos      : unsigned(3 downto 0) := (others => '0');  -- the ring position
  signal in_frame : std_logic := '0';
  signal storing  : std_logic := '0';  -- the frame goes into buffer wbuf
  signal refused  : std_logic := '0';  -- ... is dropped: the ring was in error at its first beat
  signal lost     : std_logic := '0';  -- ... is dropped: the FIFO was full for one of its slots
  signal abort_f  : std_logic := '0';
  signal wbuf     : unsigned(3 downto 0) := (others => '0');
  signal queued   : std_logic := '0';  -- a slot of the frame has entered the FIFO
  signal cnt      : unsigned(SLOT_BITS_c - 1 downto 0) := (others => '0');
  signal cnt_p1   : unsigned(SLOT_BITS_c - 1 downto 0) := to_unsigned(1, SLOT_BITS_c);  -- cnt + 1, kept
  signal trunc    : unsigned(31 downto 0) := (others => '0');
  signal ready    : std_logic_vector(15 downto 0) := (others => '0');
  signal claimed  : std_logic_vector(15 downto 0) := (others => '0');  -- written, record unanswered
  signal last_r   : unsigned(3 downto 0) := (others => '0');
  signal lcount_r : unsigned(15 downto 0) := (others => '0');
  signal lframe_r : std_logic_vector(15 downto 0) := (others => '0');
  signal done_r   : std_logic := '0';
  signal error_r  : std_logic := '0';
  signal err_f    : std_logic := '0';  -- an error response came for a burst of the frame answered now
  signal ovr_cnt  : unsigned(31 downto 0) := (others => '0');
  signal ovf_cnt  : unsigned(31 downto 0) := (others => '0');
  signal abt_cnt  : unsigned(31 downto 0) := (others => '0');
  signal drp_cnt  : unsigned(31 downto 0) := (others => '0');
  signal err_cnt  : unsigned(31 downto 0) := (others => '0');

  -- this clock's decisions
  signal first_q   : std_logic;               -- the beat is its frame's first
  signal load_act  : std_logic;               -- the active ring is loaded (at a first beat) ...
  signal restart   : std_logic;               -- ... with other values: the position restarts at 0
  signal wsel      : unsigned(3 downto 0);    -- the buffer a first beat would choose
  signal store_nw  : std_logic;               -- the beat's frame goes into a buffer, cur_buf
  signal refuse_nw : std_logic;               -- ... is refused (ring in error)
  signal cur_buf   : unsigned(3 downto 0);
  signal eff_count : unsigned(4 downto 0);    -- the ring count the frame's buffer belongs to
  signal abort_nw  : std_logic;
  signal full      : std_logic;
  signal new_slot  : std_logic;               -- a feature takes a new slot
  signal push      : std_logic;               -- a slot of an intact frame is to enter the FIFO ...
  signal room      : std_logic;               -- ... which has room

  -- the burst FIFO
  signal fifo_wr    : std_logic := '0';
  signal fifo_din   : std_logic_vector(ENTRY_BITS_c - 1 downto 0) := (others => '0');
  signal fifo_rd    : std_logic;
  signal fifo_dout  : std_logic_vector(ENTRY_BITS_c - 1 downto 0);
  signal fifo_valid : std_logic;
  signal fifo_level : std_logic_vector(FIFO_BITS_c downto 0);

  -- the master (its bus state reset by bus_rst only)
  signal state     : engine_t := idle_s;
  signal b_data    : std_logic_vector(DATA_BITS_c - 1 downto 0) := (others => '0');  -- shifts out
  signal b_slot    : unsigned(SLOT_BITS_c - 1 downto 0) := (others => '0');
  signal b_meta    : meta_t := META_ZERO_c;
  signal b_lo      : unsigned(35 downto 0) := (others => '0');  -- index * stride, bits 1..0
  signal b_hi      : unsigned(35 downto 0) := (others => '0');  -- ... bits 3..2
  signal b_start   : unsigned(31 downto 0) := (others => '0');  -- base + slot * 64
  signal b_prod    : unsigned(31 downto 0) := (others => '0');
  signal awaddr_r  : std_logic_vector(31 downto 0) := (others => '0');
  signal awvalid_r : std_logic := '0';
  signal wvalid_r  : std_logic := '0';
  signal wbeat     : unsigned(2 downto 0) := (others => '0');
  signal inflight  : unsigned(OUT_BITS_c - 1 downto 0) := (others => '0');  -- launched, unanswered
  signal stale     : unsigned(OUT_BITS_c - 1 downto 0) := (others => '0');  -- ... of before a rst
  signal meta_q    : meta_array_t := (others => META_ZERO_c);
  signal meta_wr   : natural range 0 to OUTSTANDING_g - 1 := 0;
  signal meta_rd   : natural range 0 to OUTSTANDING_g - 1 := 0;
  signal beat_cnt  : unsigned(31 downto 0) := (others => '0');
  -- a write response passed to the frame side: of a burst issued since the last rst (b_take),
  -- an error (b_err); b_err_any: an error response of any burst
  signal b_take    : std_logic := '0';
  signal b_err     : std_logic := '0';
  signal b_err_any : std_logic := '0';
  signal b_info    : meta_t := META_ZERO_c;
  signal idle_w    : std_logic;         -- nothing queued, in the master or unanswered
  signal idle_r    : std_logic := '1';  -- ... a clock ago, and no slot pushed then

begin

  assert mem_depth_legal(DEPTH_g)
    report "orb_feat_dma: DEPTH_g must be " & MEM_DEPTH_TEXT_c
    severity failure;

  assert FIFO_DEPTH_g = 2 ** FIFO_BITS_c
    report "orb_feat_dma: FIFO_DEPTH_g must be a power of two"
    severity failure;

  assert WIN_BASE_MB_g + WIN_SIZE_MB_g <= 4096
    report "orb_feat_dma: the DDR window (WIN_BASE_MB_g + WIN_SIZE_MB_g MiB) must end at 4 GiB at the latest"
    severity failure;

  -- the inputs, registered; the map read of the beat's slot beside them
  inputs : process (clk) is
  begin
    if rising_edge(clk) then
      in_data  <= s_axis_feat_tdata;
      in_beat  <= s_axis_feat_tvalid;
      in_last  <= s_axis_feat_tlast;
      in_abort <= frame_abort;
      in_rel   <= release_valid;
      in_reli  <= unsigned(release_index);
      map_q    <= smap(to_integer(unsigned(s_axis_feat_tdata(FEAT_SEL_SLOT_LO_c + MAP_BITS_c - 1 downto
                                                             FEAT_SEL_SLOT_LO_c))));
      fwd_eq   <= '0';
      if s_axis_feat_tdata(FEAT_SEL_SLOT_LO_c + FEAT_SEL_SLOT_BITS_c - 1 downto FEAT_SEL_SLOT_LO_c) =
         in_data(FEAT_SEL_SLOT_LO_c + FEAT_SEL_SLOT_BITS_c - 1 downto FEAT_SEL_SLOT_LO_c) then
        fwd_eq <= '1';
      end if;
      if rst = '1' or bus_rst = '1' then
        in_beat  <= '0';
        in_abort <= '0';
        in_rel   <= '0';
      end if;
    end if;
  end process inputs;

  -- a beat's buffer slot: a new feature's the next (cnt + 1); a replacing beat's the map's, or the
  -- slot the beat of the clock before took for it (fwd_ok: it took one; fwd_eq: the same selection slot)
  repl <= in_data(FEAT_SEL_REPLACE_BIT_c) and not in_last;
  slot <= cnt_p1 when repl = '0' else
          fwd_slot when fwd_ok = '1' and fwd_eq = '1' else
          map_q;

  slot_map : process (clk) is
    variable sel : natural range 0 to 2 ** MAP_BITS_c - 1;
  begin
    if rising_edge(clk) then
      sel    := to_integer(unsigned(in_data(FEAT_SEL_SLOT_LO_c + MAP_BITS_c - 1 downto FEAT_SEL_SLOT_LO_c)));
      fwd_ok <= '0';
      if new_slot = '1' then
        smap(sel) <= cnt_p1;
        fwd_ok    <= '1';
        fwd_slot  <= cnt_p1;
      end if;
    end if;
  end process slot_map;

  -- The ring registers' checks: registered, then four stages (one adder each) to ring_err and a
  -- fifth to ring_ok; settle counts the clocks until ring_ok belongs to the registered values
  -- (ring_err is theirs 4 edges after they were registered, ring_ok one later, when settle has
  -- been 0 for a clock: a frame whose first beat is registered by the edge that registers a change
  -- or by one of the 4 after it is refused, one registered by the 5th edge uses the new ring).
  checks : process (clk) is
  begin
    if rising_edge(clk) then
      cfg_base   <= unsigned(ring_base);
      cfg_stride <= unsigned(ring_stride);
      cfg_count  <= unsigned(ring_count);
      -- count - 1, registered with the count so that stage 1 starts at a register (the timing path)
      cfg_last   <= (others => '0');
      if unsigned(ring_count) /= 0 then
        cfg_last <= resize(unsigned(ring_count) - 1, 4);
      end if;
      if unsigned(ring_base) /= cfg_base or unsigned(ring_stride) /= cfg_stride or
         unsigned(ring_count) /= cfg_count then
        settle <= to_unsigned(SETTLE_c, 3);
      elsif settle /= 0 then
        settle <= settle - 1;
      end if;
      -- 1: the partial products of (count - 1) * stride, base + one buffer, the plain flags
      chk_lo    <= times2(cfg_last(1 downto 0), cfg_stride);
      chk_hi    <= shift_left(times2(cfg_last(3 downto 2), cfg_stride), 2);
      chk_end   <= resize(cfg_base, 37) + to_unsigned(BUF_BYTES_c, 37);
      chk_below <= '1' when resize(cfg_base, 37) < WIN_LO_c else '0';
      chk_err1  <= (others => '0');
      if cfg_base(5 downto 0) /= 0 or cfg_stride(5 downto 0) /= 0 then
        chk_err1(0) <= '1';
      end if;
      if cfg_count > 1 and cfg_stride < BUF_BYTES_c then
        chk_err1(1) <= '1';
      end if;
      if cfg_count = 0 then
        chk_err1(3) <= '1';
      end if;
      -- 2: the product
      chk_prod <= resize(chk_lo, 37) + resize(chk_hi, 37);
      chk_err2 <= chk_err1;
      chk_err2(2) <= chk_below;
      -- 3: the ring's end
      chk_top  <= chk_end + chk_prod;
      -- 4: against the window
      ring_err <= chk_err2;
      if chk_err2(2) = '1' or chk_top > WIN_HI_c then
        ring_err(2) <= '1';
      end if;
      -- 5: the verdict on the values of cfg_* five edges ago, once they have been there that long
      ring_ok <= '1' when settle = 0 and ring_err = "0000" else '0';
    end if;
  end process checks;


  ring_ok_now <= '1' when ring_ok = '1' and settle = 0 else
                 '0';

  -- A frame's first beat chooses its buffer: the ring position, or 0 when the active ring is
  -- (re)loaded with other values; the active ring is loaded only when nothing is queued, in the
  -- master or unanswered.
  first_q  <= in_beat and not in_frame;
  load_act <= first_q and idle_r and ring_ok_now;
  restart  <= load_act and not act_same;
  wsel     <= (others => '0') when restart = '1' else
              pos;

  decide : process (all) is
    variable free_v : boolean;
  begin
    free_v := (ready(to_integer(wsel)) = '0' or (in_rel = '1' and in_reli = wsel)) and
              claimed(to_integer(wsel)) = '0';
    if in_frame = '1' then
      store_nw  <= storing;
      refuse_nw <= refused;
      cur_buf   <= wbuf;
    else
      store_nw  <= '1' when ring_ok_now = '1' and free_v else '0';
      refuse_nw <= not ring_ok_now;
      cur_buf   <= wsel;
    end if;
  end process decide;

  eff_count <= cfg_count when load_act = '1' else
               act_count;
  abort_nw  <= abort_f or in_abort;
  full      <= '1' when cnt = LAST_SLOT_c else
               '0';
  new_slot  <= in_beat and store_nw and not abort_nw and not in_last and not repl and not full;
  push      <= in_beat and store_nw and not abort_nw and not lost and (in_last or repl or not full);
  -- the FIFO is written a clock later (fifo_wr, fifo_din registered): room leaves a place for it
  room <= '1' when unsigned(fifo_level) < FIFO_DEPTH_g - 1 else
          '0';

  -- the FIFO entry: the slot's data, its slot (the record in slot 0, feature k in slot k + 1),
  -- the buffer, the record flag, whether it is the first slot its frame queued
  entry : process (clk) is
    variable e_v : std_logic_vector(ENTRY_BITS_c - 1 downto 0);
  begin
    if rising_edge(clk) then
      e_v                                                := (others => '0');
      e_v(DATA_BITS_c - 1 downto 0)                      := slot_word(in_data, in_last, cnt, trunc);
      if in_last = '0' then
        e_v(E_INDEX_LO_c - 1 downto E_SLOT_LO_c) := std_logic_vector(slot);
      end if;
      e_v(E_INDEX_LO_c + 3 downto E_INDEX_LO_c)          := std_logic_vector(cur_buf);
      e_v(E_REC_BIT_c)                                   := in_last;
      e_v(E_FIRST_c)                                     := not queued;
      fifo_din                                           <= e_v;
      fifo_wr                                            <= push and room and not (rst or bus_rst);
    end if;
  end process entry;

  fifo : entity work.orb_feat_fifo
    generic map (
      DATA_BITS_g => ENTRY_BITS_c,
      DEPTH_g     => FIFO_DEPTH_g
    )
    port map (
      clk      => clk,
      rst      => rst or bus_rst,
      wr_en    => fifo_wr,
      wr_data  => fifo_din,
      rd_en    => fifo_rd,
      rd_data  => fifo_dout,
      rd_valid => fifo_valid,
      level    => fifo_level
    );

  -- The frames: the buffer choice, the counts, the end of a frame; the publication at the
  -- response to its record. Arrays are written with constant indices only (GHDL 2.0 synth drops
  -- writes to a signal array element indexed by a variable: orb_feat_mem).
  ctrl : process (clk) is
  begin
    if rising_edge(clk) then
      done_r  <= '0';
      error_r <= '0';
      for k in 0 to 15 loop
        if in_rel = '1' and in_reli = k then
          ready(k) <= '0';
        end if;
      end loop;
      if in_abort = '1' then
        abort_f <= '1';
      end if;
      act_same <= '1' when act_base = cfg_base and act_stride = cfg_stride and act_count = cfg_count else '0';
      if load_act = '1' then
        act_base   <= cfg_base;
        act_stride <= cfg_stride;
        act_count  <= cfg_count;
      end if;
      if push = '1' and room = '0' then
        lost <= '1';
      end if;
      if push = '1' and room = '1' and in_last = '0' then
        queued <= '1';
      end if;
      if first_q = '1' then
        wbuf    <= cur_buf;
        storing <= store_nw;
        refused <= refuse_nw;
        for k in 0 to 15 loop
          if store_nw = '1' and cur_buf = k then
            claimed(k) <= '1';
          end if;
        end loop;
        if restart = '1' then
          pos <= (others => '0');
        end if;
      end if;
      if in_beat = '1' and in_last = '0' then
        in_frame <= '1';
        if store_nw = '1' and abort_nw = '0' and repl = '0' then
          if full = '0' then
            cnt    <= cnt + 1;
            cnt_p1 <= cnt_p1 + 1;
          else
            trunc <= trunc + 1;
          end if;
        end if;
      elsif in_beat = '1' then
        -- end of the frame: its record queued, or skipped, aborted, dropped
        in_frame <= '0';
        storing  <= '0';
        refused  <= '0';
        abort_f  <= '0';
        lost     <= '0';
        cnt      <= (others => '0');
        cnt_p1   <= to_unsigned(1, SLOT_BITS_c);
        trunc    <= (others => '0');
        if abort_nw = '1' then
          abt_cnt <= abt_cnt + 1;
        elsif store_nw = '0' and refuse_nw = '1' then
          drp_cnt <= drp_cnt + 1;
        elsif store_nw = '0' then
          ovr_cnt <= ovr_cnt + 1;
        elsif lost = '1' or room = '0' then
          drp_cnt <= drp_cnt + 1;
          error_r <= '1';
        else
          ovf_cnt <= ovf_cnt + trunc;
          if resize(cur_buf, 5) + 1 >= eff_count then
            pos <= (others => '0');
          else
            pos <= cur_buf + 1;
          end if;
        end if;
        queued <= '0';
        -- a buffer whose frame will not be published is free again (its queued slots still go there)
        for k in 0 to 15 loop
          if cur_buf = k and store_nw = '1' and (abort_nw = '1' or lost = '1' or room = '0') then
            claimed(k) <= '0';
          end if;
        end loop;
      end if;
      -- the write responses
      if b_err_any = '1' then
        err_cnt <= err_cnt + 1;
        error_r <= '1';
      end if;
      -- The responses come in the order of the bursts, and a frame's bursts follow one another,
      -- the first flagged: err_f is whether one of the frame answered now had an error (a frame
      -- with no record, aborted or dropped, leaves no trace for the next).
      if b_take = '1' then
        err_f <= b_err or (err_f and not b_info.first);
        if b_info.rec = '1' then
          err_f <= '0';
          if b_err = '1' or (err_f = '1' and b_info.first = '0') then
            drp_cnt <= drp_cnt + 1;
          else
            last_r   <= b_info.index;
            lcount_r <= resize(b_info.count, 16);
            lframe_r <= b_info.frame;
            done_r   <= '1';
          end if;
          for k in 0 to 15 loop
            if b_info.index = k then
              claimed(k) <= '0';
              if b_err = '0' and not (err_f = '1' and b_info.first = '0') then
                ready(k) <= '1';
              end if;
            end if;
          end loop;
        end if;
      end if;
      if rst = '1' or bus_rst = '1' then
        pos      <= (others => '0');
        in_frame <= '0';
        storing  <= '0';
        refused  <= '0';
        lost     <= '0';
        abort_f  <= '0';
        queued   <= '0';
        cnt      <= (others => '0');
        cnt_p1   <= to_unsigned(1, SLOT_BITS_c);
        trunc    <= (others => '0');
        ready    <= (others => '0');
        claimed  <= (others => '0');
        last_r   <= (others => '0');
        lcount_r <= (others => '0');
        lframe_r <= (others => '0');
        done_r   <= '0';
        error_r  <= '0';
        err_f    <= '0';
        ovr_cnt  <= (others => '0');
        ovf_cnt  <= (others => '0');
        abt_cnt  <= (others => '0');
        drp_cnt  <= (others => '0');
        err_cnt  <= (others => '0');
      end if;
      if bus_rst = '1' then
        act_base   <= (others => '0');
        act_stride <= (others => '0');
        act_count  <= (others => '0');
      end if;
    end if;
  end process ctrl;

  -- The master. idle_s: take the FIFO's head when fewer than OUTSTANDING_g bursts are
  -- unanswered; addr1_s, addr2_s, addr3_s: the address, one adder a clock (buffer * stride in two
  -- halves, their sum, + base + slot * 64); burst_s: AWVALID and WVALID up, the 8 beats shifted
  -- out of the burst register. A rst drops a burst not yet launched and marks the unanswered ones
  -- stale; a launched burst is always finished. The active ring does not change while the master
  -- holds a slot (it is loaded only when idle_w).
  fifo_rd <= '1' when state = idle_s and fifo_valid = '1' and inflight < OUTSTANDING_g and rst = '0' else
             '0';
  idle_w  <= '1' when state = idle_s and fifo_wr = '0' and unsigned(fifo_level) = 0 and inflight = 0 else
             '0';

  engine : process (clk) is
    variable inflight_v : unsigned(OUT_BITS_c - 1 downto 0);
    variable launch_v   : boolean;
  begin
    if rising_edge(clk) then
      inflight_v := inflight;
      launch_v   := false;
      b_take     <= '0';
      b_err      <= '0';
      b_err_any  <= '0';
      -- the write response (BREADY is 1): one for each launched burst, in order
      if m_axi_feat_bvalid = '1' and inflight /= 0 then
        inflight_v := inflight_v - 1;
        b_info     <= meta_q(meta_rd);
        b_err_any  <= m_axi_feat_bresp(1);
        if meta_rd = OUTSTANDING_g - 1 then
          meta_rd <= 0;
        else
          meta_rd <= meta_rd + 1;
        end if;
        if stale /= 0 then
          stale <= stale - 1;
        else
          b_take <= '1';
          b_err  <= m_axi_feat_bresp(1);
        end if;
      end if;
      -- (an if chain, not a case: GHDL's Verilog of a case over the states is a one-hot case that
      -- yosys turns into latches)
      if state = idle_s then
        if fifo_rd = '1' then
          b_data       <= fifo_dout(DATA_BITS_c - 1 downto 0);
          b_slot       <= unsigned(fifo_dout(E_INDEX_LO_c - 1 downto E_SLOT_LO_c));
          b_meta.rec   <= fifo_dout(E_REC_BIT_c);
          b_meta.first <= fifo_dout(E_FIRST_c);
          b_meta.index <= unsigned(fifo_dout(E_INDEX_LO_c + 3 downto E_INDEX_LO_c));
          b_meta.count <= unsigned(fifo_dout(REC_COUNT_LO_c + SLOT_BITS_c - 1 downto REC_COUNT_LO_c));
          b_meta.frame <= fifo_dout(REC_FRAME_LO_c + 15 downto REC_FRAME_LO_c);
          state        <= addr1_s;
        end if;
      elsif state = addr1_s then
        b_lo    <= times2(b_meta.index(1 downto 0), act_stride);
        b_hi    <= shift_left(times2(b_meta.index(3 downto 2), act_stride), 2);
        b_start <= act_base + shift_left(resize(b_slot, 32), 6);
        state   <= addr2_s;
      elsif state = addr2_s then
        b_prod <= resize(b_lo + b_hi, 32);
        state  <= addr3_s;
      elsif state = addr3_s then
        if rst = '0' then
          launch_v := true;
          awaddr_r  <= std_logic_vector(b_start + b_prod);
          awvalid_r <= '1';
          wvalid_r  <= '1';
          wbeat     <= (others => '0');
          state     <= burst_s;
        end if;
      else
        if awvalid_r = '1' and m_axi_feat_awready = '1' then
          awvalid_r <= '0';
        end if;
        if wvalid_r = '1' and m_axi_feat_wready = '1' then
          b_data   <= std_logic_vector(shift_right(unsigned(b_data), 64));
          wbeat    <= wbeat + 1;
          beat_cnt <= beat_cnt + 1;
          if wbeat = BEATS_c - 1 then
            wvalid_r <= '0';
          end if;
        end if;
        if (awvalid_r = '0' or m_axi_feat_awready = '1') and
           (wvalid_r = '0' or (m_axi_feat_wready = '1' and wbeat = BEATS_c - 1)) then
          state <= idle_s;
        end if;
      end if;
      if launch_v then
        inflight_v := inflight_v + 1;
        meta_q(meta_wr) <= b_meta;
        if meta_wr = OUTSTANDING_g - 1 then
          meta_wr <= 0;
        else
          meta_wr <= meta_wr + 1;
        end if;
      end if;
      inflight <= inflight_v;
      idle_r   <= idle_w and not push;
      if rst = '1' then
        -- a slot not yet launched is dropped; the responses still due are for bursts of before
        if state = addr1_s or state = addr2_s or state = addr3_s then
          state <= idle_s;
        end if;
        stale    <= inflight_v;
        b_take   <= '0';
        b_err    <= '0';
        beat_cnt <= (others => '0');
      end if;
      if bus_rst = '1' then
        state     <= idle_s;
        awvalid_r <= '0';
        wvalid_r  <= '0';
        wbeat     <= (others => '0');
        inflight  <= (others => '0');
        stale     <= (others => '0');
        meta_wr   <= 0;
        meta_rd   <= 0;
        beat_cnt  <= (others => '0');
        b_take    <= '0';
        b_err     <= '0';
        b_err_any <= '0';
      end if;
    end if;
  end process engine;

  s_axis_feat_tready <= '1';
  frame_done         <= done_r;
  dma_error          <= error_r;
  ring_ready         <= ready;
  ring_last          <= std_logic_vector(last_r);
  ring_error         <= ring_err;
  busy               <= not idle_w;
  last_count         <= std_logic_vector(lcount_r);
  last_frame         <= lframe_r;
  overrun            <= std_logic_vector(ovr_cnt);
  overflow           <= std_logic_vector(ovf_cnt);
  aborted            <= std_logic_vector(abt_cnt);
  dma_dropped        <= std_logic_vector(drp_cnt);
  bus_errors         <= std_logic_vector(err_cnt);
  beats              <= std_logic_vector(beat_cnt);

  m_axi_feat_awid    <= "0"; -- one ID: the bursts complete in order (bid is not used)
  m_axi_feat_awaddr  <= awaddr_r;
  m_axi_feat_awlen   <= std_logic_vector(to_unsigned(BEATS_c - 1, 8));
  m_axi_feat_awsize  <= "011";
  m_axi_feat_awburst <= "01";
  m_axi_feat_awcache <= "0011";
  m_axi_feat_awprot  <= "000";
  m_axi_feat_awvalid <= awvalid_r;
  m_axi_feat_wdata   <= b_data(63 downto 0);
  m_axi_feat_wstrb   <= (others => '1');
  m_axi_feat_wlast   <= '1' when wbeat = BEATS_c - 1 else
                        '0';
  m_axi_feat_wvalid  <= wvalid_r;
  m_axi_feat_bready  <= '1';

end architecture rtl;
