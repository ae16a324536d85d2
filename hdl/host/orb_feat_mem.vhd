-- SPDX-License-Identifier: MIT
-- orb_feat_mem: the feature memory the CPU reads, double-buffered per frame. It takes the feature
-- stream of orb_core (s_axis_feat, layout in orb_feat_pkg; tready is always 1: one beat per clock
-- is stored, nothing ever stalls the stream) and writes each frame into one of two banks of
-- DEPTH_g 64-byte slots: the features in the order their slots first appear, then an end-of-frame
-- record (so at most DEPTH_g - 1 features per frame are kept; further ones are counted as
-- truncated). A feature beat with sel_replace = 0 takes the next slot (in all mode every beat
-- does: arrival order); one with sel_replace = 1 (the grid selection replacing a feature it
-- evicted) is written over the slot that the frame's beat with the same sel_slot took, through a
-- map of SEL_SLOTS_g entries (docs/selection.md), so a frame of the grid selection fills slots
-- 0 .. count - 1 with the selection. Every input (stream, frame_abort, release) is registered
-- once before the rules below apply (the map's read takes that clock). At the frame's end-of-frame beat (tlast = 1) the bank's header (feature count,
-- frame number, dropped-upstream count, truncated count and flag) is stored, the end-of-frame
-- record also carries the parameters the frame was processed with (from the beat), the bank becomes
-- READY, frame_done pulses for one clock, and the next frame goes to the other bank. The CPU
-- reads a READY bank at leisure and releases it (release_valid with release_bank). A frame whose
-- bank is still READY at the frame's first beat (not released, a release in that very clock
-- counts) is skipped as a whole and counted in `overrun`; a frame_abort pulse discards the frame
-- in progress (the one whose end-of-frame beat is not yet accepted, ending in this clock
-- included), counted in `aborted` at its end-of-frame beat. So the CPU only ever sees complete
-- frames, in order. One RAM word (320 bits) holds CPU words 0..9 of a slot, written in one clock;
-- the RAM is a simple dual-port block RAM with a registered read. Reads: mem_rd_en with the byte
-- address mem_rd_addr ([5:2] word, [clog2(DEPTH_g) + 5:6] slot, [clog2(DEPTH_g) + 6] bank) gives
-- mem_rd_data FEAT_MEM_READ_LAT_c = 3 clocks later (orb_latency_pkg, docs/latency.md; orb_accel_top
-- gives it orb_axil_regs as MEM_LATENCY_g: RAM read register, its output register, then the word mux
-- register: no logic behind the block RAM's clock-to-output time, docs/synthesis.md "Timing"),
-- held until the next read. The layout and the protocol are in docs/feature-memory.md. rst resets the control
-- state (banks free, bank 0 next, counters 0, no read pending); RAM contents and bank headers are
-- kept.
-- Ports and generics: docs/entities/orb_feat_mem.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_feat_pkg.all;
use work.orb_limits_pkg.all;
use work.orb_slot_pkg.all;

entity orb_feat_mem is
  generic (
    DEPTH_g     : mem_depth_t              := 1024; -- slots per bank (MEM_DEPTH_g of orb_accel_top)
    SEL_SLOTS_g : positive range 2 to 8192 := 1024  -- the selection's slots (sel_slot < SEL_SLOTS_g)
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic;
    -- feature stream
    s_axis_feat_tdata  : in    std_logic_vector(FEAT_BITS_c - 1 downto 0);
    s_axis_feat_tvalid : in    std_logic;
    s_axis_feat_tready : out   std_logic;
    s_axis_feat_tlast  : in    std_logic;
    frame_abort        : in    std_logic;
    -- bank hand-over to the CPU
    release_valid  : in    std_logic;
    release_bank   : in    std_logic;
    frame_done     : out   std_logic;
    bank_ready     : out   std_logic_vector(1 downto 0);
    bank_truncated : out   std_logic_vector(1 downto 0);
    last_bank      : out   std_logic;
    bank0_count    : out   std_logic_vector(15 downto 0);
    bank0_frame    : out   std_logic_vector(15 downto 0);
    bank0_dropped  : out   std_logic_vector(15 downto 0);
    bank0_trunc    : out   std_logic_vector(31 downto 0);
    bank1_count    : out   std_logic_vector(15 downto 0);
    bank1_frame    : out   std_logic_vector(15 downto 0);
    bank1_dropped  : out   std_logic_vector(15 downto 0);
    bank1_trunc    : out   std_logic_vector(31 downto 0);
    overrun        : out   std_logic_vector(31 downto 0);
    overflow       : out   std_logic_vector(31 downto 0);
    aborted        : out   std_logic_vector(31 downto 0);
    -- CPU read port (latency FEAT_MEM_READ_LAT_c)
    mem_rd_en   : in    std_logic;
    mem_rd_addr : in    std_logic_vector(clog2(DEPTH_g) + 6 downto 0);
    mem_rd_data : out   std_logic_vector(31 downto 0)
  );
end entity orb_feat_mem;

architecture rtl of orb_feat_mem is

  constant SLOT_BITS_c : positive := clog2(DEPTH_g);
  constant WORDS_c     : positive := SLOT_WORDS_USED_c; -- CPU words 0..9 of a slot are stored
  constant WORD_BITS_c : positive := 32 * WORDS_c;
  constant LAST_SLOT_c : natural  := DEPTH_g - 1; -- the slot only an end-of-frame record may use
  constant BANK_c      : std_logic_vector(0 to 1) := "01";

  type mem_t is array (0 to 2 * DEPTH_g - 1) of std_logic_vector(WORD_BITS_c - 1 downto 0);
  constant MAP_BITS_c : positive := clog2(SEL_SLOTS_g);  -- (a power of two: no range check)
  type map_t is array (0 to 2 ** MAP_BITS_c - 1) of unsigned(SLOT_BITS_c - 1 downto 0);
  type u16_pair_t is array (0 to 1) of unsigned(15 downto 0);
  type u32_pair_t is array (0 to 1) of unsigned(31 downto 0);


  -- the inputs, registered (the rules below apply to these)
  signal in_data  : std_logic_vector(FEAT_BITS_c - 1 downto 0) := (others => '0');
  signal in_beat  : std_logic := '0';
  signal in_last  : std_logic := '0';
  signal in_abort : std_logic := '0';
  signal in_rel   : std_logic := '0';
  signal in_relb  : std_logic := '0';

  -- the selection's slot map: read with the input register, written when a new slot is taken
  signal smap     : map_t := (others => (others => '0'));
  signal map_q    : unsigned(SLOT_BITS_c - 1 downto 0) := (others => '0');
  signal fwd_ok   : std_logic := '0';                                      -- the last clock took a new slot ...
  signal fwd_sel  : std_logic_vector(FEAT_SEL_SLOT_BITS_c - 1 downto 0) := (others => '0');  -- for this sel_slot
  signal fwd_phys : unsigned(SLOT_BITS_c - 1 downto 0) := (others => '0');  -- ... this slot
  signal repl     : std_logic;                                             -- the beat replaces
  signal phys     : unsigned(SLOT_BITS_c - 1 downto 0);                    -- the slot it goes to

  -- write side
  signal wr_en    : std_logic;
  signal wr_addr  : unsigned(SLOT_BITS_c downto 0);
  signal wr_data  : std_logic_vector(WORD_BITS_c - 1 downto 0);
  signal beat     : std_logic;
  signal store_nw : std_logic;                   -- the current frame goes into bank wbank
  signal abort_nw : std_logic;                   -- the current frame is aborted
  signal full     : std_logic;                   -- DEPTH_g - 1 features stored

  signal wbank    : std_logic := '0';
  signal in_frame : std_logic := '0';
  signal storing  : std_logic := '0';
  signal abort_f  : std_logic := '0';
  signal cnt      : unsigned(SLOT_BITS_c - 1 downto 0) := (others => '0');
  signal trunc    : unsigned(31 downto 0) := (others => '0');
  signal ready    : std_logic_vector(1 downto 0) := (others => '0');
  signal done_r   : std_logic := '0';
  signal last_r   : std_logic := '0';
  signal ovr_cnt  : unsigned(31 downto 0) := (others => '0');
  signal ovf_cnt  : unsigned(31 downto 0) := (others => '0');
  signal abt_cnt  : unsigned(31 downto 0) := (others => '0');

  -- bank headers
  signal h_count : u16_pair_t := (others => (others => '0'));
  signal h_frame : u16_pair_t := (others => (others => '0'));
  signal h_drop  : u16_pair_t := (others => (others => '0'));
  signal h_trunc : u32_pair_t := (others => (others => '0'));

  -- read side
  signal q       : std_logic_vector(WORD_BITS_c - 1 downto 0) := (others => '0');
  signal q2      : std_logic_vector(WORD_BITS_c - 1 downto 0) := (others => '0');
  signal rd_widx : unsigned(3 downto 0) := (others => '0');
  signal rd_wsel : unsigned(3 downto 0) := (others => '0');
  signal rd_pend : std_logic_vector(1 to 2) := (others => '0');
  signal rd_word : std_logic_vector(31 downto 0) := (others => '0');

  function bank_index (b : std_logic) return natural is
  begin
    if b = '1' then
      return 1;
    end if;
    return 0;
  end function bank_index;

begin

  -- the registers from input to output: RAM read register, its output register, the word mux register
  assert FEAT_MEM_READ_LAT_c = 3
    report "orb_feat_mem: FEAT_MEM_READ_LAT_c (orb_latency_pkg) must be this pipeline's 3 clocks"
    severity failure;

  assert mem_depth_legal(DEPTH_g)
    report "orb_feat_mem: DEPTH_g must be " & MEM_DEPTH_TEXT_c
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
      in_relb  <= release_bank;
      map_q    <= smap(to_integer(unsigned(s_axis_feat_tdata(FEAT_SEL_SLOT_LO_c + MAP_BITS_c - 1 downto
                                                             FEAT_SEL_SLOT_LO_c))));
      if rst = '1' then
        in_beat  <= '0';
        in_abort <= '0';
        in_rel   <= '0';
      end if;
    end if;
  end process inputs;

  beat <= in_beat;
  repl <= in_data(FEAT_SEL_REPLACE_BIT_c) and not in_last;
  -- a replacing beat's slot: the map's, or the slot the beat of the clock before took for it
  phys <= cnt when repl = '0' else
          fwd_phys when fwd_ok = '1' and fwd_sel = in_data(FEAT_SEL_SLOT_LO_c + FEAT_SEL_SLOT_BITS_c - 1 downto
                                                            FEAT_SEL_SLOT_LO_c) else
          map_q;

  -- the map: the slot each of the frame's sel_slots took
  slot_map : process (clk) is
    variable sel : natural range 0 to 2 ** MAP_BITS_c - 1;
  begin
    if rising_edge(clk) then
      sel    := to_integer(unsigned(in_data(FEAT_SEL_SLOT_LO_c + MAP_BITS_c - 1 downto FEAT_SEL_SLOT_LO_c)));
      fwd_ok <= '0';
      if wr_en = '1' and in_last = '0' and repl = '0' then
        smap(sel) <= cnt;
        fwd_ok    <= '1';
        fwd_sel   <= in_data(FEAT_SEL_SLOT_LO_c + FEAT_SEL_SLOT_BITS_c - 1 downto FEAT_SEL_SLOT_LO_c);
        fwd_phys  <= cnt;
      end if;
    end if;
  end process slot_map;

  -- A frame's first beat decides whether the frame is stored: bank wbank must not be READY (a
  -- release of it in the same clock frees it). The decision holds for the whole frame.
  decide : process (all) is
    variable free_w : std_logic;
  begin
    free_w := '0';
    if ready(bank_index(wbank)) = '0' or (in_rel = '1' and in_relb = wbank) then
      free_w := '1';
    end if;
    if in_frame = '1' then
      store_nw <= storing;
    else
      store_nw <= free_w;
    end if;
  end process decide;

  abort_nw <= abort_f or in_abort;
  full     <= '1' when cnt = LAST_SLOT_c else
              '0';
  wr_en    <= beat and store_nw and not abort_nw and (in_last or repl or not full);
  wr_addr  <= wbank & cnt when in_last = '1' else
              wbank & phys;

  -- The RAM word: CPU words 0..9 of the slot (word k at bits 32 * k + 31 downto 32 * k), fields at
  -- orb_feat_pkg's SLOT_/REC_ positions (docs/feature-word.md), made as orb_feat_dma makes its slots
  wr_data <= slot_word(in_data, in_last, cnt, trunc);

  -- Simple dual-port RAM: one write port (the stream), one registered read port (the CPU),
  -- read-first. A process variable: one value per word for the simulator instead of a signal
  -- per bit (2 * DEPTH_g * 320 of them).
  ram : process (clk) is
    variable mem : mem_t := (others => (others => '0'));
  begin
    if rising_edge(clk) then
      if mem_rd_en = '1' then
        q <= mem(to_integer(unsigned(mem_rd_addr(SLOT_BITS_c + 6 downto 6))));
      end if;
      if wr_en = '1' then
        mem(to_integer(wr_addr)) := wr_data;
      end if;
    end if;
  end process ram;

  ctrl : process (clk) is
  begin
    if rising_edge(clk) then
      done_r <= '0';
      for k in 0 to 1 loop
        if in_rel = '1' and in_relb = BANK_c(k) then
          ready(k) <= '0';
        end if;
      end loop;
      if in_abort = '1' then
        abort_f <= '1';
      end if;
      if beat = '1' and in_last = '0' then
        in_frame <= '1';
        storing  <= store_nw;
        if store_nw = '1' and abort_nw = '0' and repl = '0' then
          if full = '0' then
            cnt <= cnt + 1;
          else
            trunc <= trunc + 1;
          end if;
        end if;
      elsif beat = '1' then
        -- end of the frame: published, skipped (overrun) or discarded (aborted)
        in_frame <= '0';
        storing  <= '0';
        abort_f  <= '0';
        cnt      <= (others => '0');
        trunc    <= (others => '0');
        if abort_nw = '1' then
          abt_cnt <= abt_cnt + 1;
        elsif store_nw = '0' then
          ovr_cnt <= ovr_cnt + 1;
        else
          -- constant indices only: GHDL 2.0 synth drops writes to a signal array element
          -- indexed by a variable in this process (the headers came out as constants)
          for k in 0 to 1 loop
            if wbank = BANK_c(k) then
              ready(k)   <= '1';
              h_count(k) <= resize(cnt, 16);
              h_frame(k) <= unsigned(in_data(EOF_FRAME_LO_c + 15 downto EOF_FRAME_LO_c));
              h_drop(k)  <= unsigned(in_data(EOF_DROPS_LO_c + 15 downto EOF_DROPS_LO_c));
              h_trunc(k) <= trunc;
            end if;
          end loop;
          ovf_cnt    <= ovf_cnt + trunc;
          last_r     <= wbank;
          wbank      <= not wbank;
          done_r     <= '1';
        end if;
      end if;
      if rst = '1' then
        wbank    <= '0';
        in_frame <= '0';
        storing  <= '0';
        abort_f  <= '0';
        cnt      <= (others => '0');
        trunc    <= (others => '0');
        ready    <= (others => '0');
        done_r   <= '0';
        last_r   <= '0';
        ovr_cnt  <= (others => '0');
        ovf_cnt  <= (others => '0');
        abt_cnt  <= (others => '0');
      end if;
    end if;
  end process ctrl;

  -- Read pipeline, second and third stages: the RAM word registered, then its addressed 32-bit
  -- word (words 10..15 are 0).
  rd_mux : process (clk) is
    variable k : natural range 0 to 15;
  begin
    if rising_edge(clk) then
      if mem_rd_en = '1' then
        rd_widx <= unsigned(mem_rd_addr(5 downto 2));
      end if;
      rd_pend <= mem_rd_en & rd_pend(1);
      if rd_pend(1) = '1' then
        q2      <= q;
        rd_wsel <= rd_widx;
      end if;
      if rd_pend(2) = '1' then
        k := to_integer(rd_wsel);
        if k < WORDS_c then
          rd_word <= q2(32 * k + 31 downto 32 * k);
        else
          rd_word <= (others => '0');
        end if;
      end if;
      if rst = '1' then
        rd_pend <= (others => '0');
      end if;
    end if;
  end process rd_mux;

  s_axis_feat_tready <= '1';
  frame_done         <= done_r;
  bank_ready         <= ready;
  bank_truncated(0)  <= '1' when h_trunc(0) /= 0 else
                        '0';
  bank_truncated(1)  <= '1' when h_trunc(1) /= 0 else
                        '0';
  last_bank          <= last_r;
  bank0_count        <= std_logic_vector(h_count(0));
  bank0_frame        <= std_logic_vector(h_frame(0));
  bank0_dropped      <= std_logic_vector(h_drop(0));
  bank0_trunc        <= std_logic_vector(h_trunc(0));
  bank1_count        <= std_logic_vector(h_count(1));
  bank1_frame        <= std_logic_vector(h_frame(1));
  bank1_dropped      <= std_logic_vector(h_drop(1));
  bank1_trunc        <= std_logic_vector(h_trunc(1));
  overrun            <= std_logic_vector(ovr_cnt);
  overflow           <= std_logic_vector(ovf_cnt);
  aborted            <= std_logic_vector(abt_cnt);
  mem_rd_data        <= rd_word;

end architecture rtl;
