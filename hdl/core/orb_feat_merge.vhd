-- SPDX-License-Identifier: MIT
-- orb_feat_merge: merges the feature streams of SCALES_g scales into one AXI4-Stream. Each scale
-- has an orb_feat_fifo of FIFO_DEPTH_g features (first word fall through, RAM-based); a
-- round-robin arbiter moves one feature per clock to the output register. With DESC_g each
-- feature carries its orientation sector (in_sector) and descriptor (in_desc) through the FIFO
-- into the word; without, the FIFOs hold only x, y and score and those output bits are 0. A
-- scale's frame end (in_done) is not stored in its FIFO but remembered as the number of FIFO
-- entries that still belong to the ending frame, so a frame end can never be overtaken or
-- dropped. When every scale has delivered its whole frame, one end-of-frame beat (tlast = 1,
-- layout in orb_feat_pkg) follows the frame's features. Up to two frame ends per scale can wait
-- for their beat (the output stalled for a whole frame); a third merges into the newest waiting
-- one. A feature that finds its FIFO full (and no feature leaving it in that clock) is dropped
-- and counted: in total on `dropped`, and per frame (the frame the feature belongs to) in the
-- end-of-frame beat, saturating at 65535. The counts are pipelined: a loss is registered, counted
-- per waiting frame one clock later and added to its frame's count the clock after. An
-- end-of-frame beat never misses a loss of its own frame: a scale whose FIFO is full still holds
-- at least FIFO_DEPTH_g >= 2 features of that frame, so the beat goes at the third clock after the
-- loss at the earliest (docs/synthesis.md, "Timing"). Latency FEAT_MERGE_LAT_c = 3 clocks
-- (orb_latency_pkg, docs/latency.md): a feature sampled at one edge leaves the output register
-- after the second edge after it (FIFO write, FIFO output register, output).
-- Per-scale input vectors are flat, scale s in bits (s + 1) * W - 1 downto s * W (W = COORD_BITS_c,
-- SCORE_BITS_c, FEAT_SECTOR_BITS_c or DESC_BITS_c); in_sector and in_desc are ignored without
-- DESC_g.
-- Ports and generics: docs/entities/orb_feat_merge.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_feat_pkg.all;
use work.orb_limits_pkg.all;

entity orb_feat_merge is
  generic (
    SCALES_g     : scales_t                := 1;
    FIFO_DEPTH_g : positive range 2 to 512 := 32;
    DESC_g       : boolean                 := true
  );
  port (
    clk                : in    std_logic;
    rst                : in    std_logic;
    in_valid           : in    std_logic_vector(SCALES_g - 1 downto 0);
    in_x               : in    std_logic_vector(SCALES_g * COORD_BITS_c - 1 downto 0);
    in_y               : in    std_logic_vector(SCALES_g * COORD_BITS_c - 1 downto 0);
    in_score           : in    std_logic_vector(SCALES_g * SCORE_BITS_c - 1 downto 0);
    in_low             : in    std_logic_vector(SCALES_g - 1 downto 0);
    in_code            : in    std_logic_vector(SCALES_g * FEAT_RESPONSE_BITS_c - 1 downto 0);
    in_slot            : in    std_logic_vector(SCALES_g * FEAT_SEL_SLOT_BITS_c - 1 downto 0);
    in_replace         : in    std_logic_vector(SCALES_g - 1 downto 0);
    in_sector          : in    std_logic_vector(SCALES_g * FEAT_SECTOR_BITS_c - 1 downto 0);
    in_desc            : in    std_logic_vector(SCALES_g * DESC_BITS_c - 1 downto 0);
    in_done            : in    std_logic_vector(SCALES_g - 1 downto 0);
    m_axis_feat_tdata  : out   std_logic_vector(FEAT_BITS_c - 1 downto 0);
    m_axis_feat_tvalid : out   std_logic;
    m_axis_feat_tready : in    std_logic;
    m_axis_feat_tlast  : out   std_logic;
    dropped            : out   std_logic_vector(31 downto 0)
  );
end entity orb_feat_merge;

architecture rtl of orb_feat_merge is

  -- FIFO entry: [11:0] score, [23:12] x, [35:24] y, then the selection's fields (low, response
  -- code, slot, replace: SEL_BITS_c), then with DESC_g the sector and the descriptor.
  constant BASE_BITS_c   : positive := 2 * COORD_BITS_c + SCORE_BITS_c;
  constant SEL_BITS_c    : positive := 2 + FEAT_RESPONSE_BITS_c + FEAT_SEL_SLOT_BITS_c;
  constant SECTOR_LO_c   : natural  := BASE_BITS_c + SEL_BITS_c;
  constant SECTOR_BITS_c : positive := FEAT_SECTOR_BITS_c;
  constant DESC_LO_c     : natural  := SECTOR_LO_c + FEAT_SECTOR_BITS_c;

  function entry_bits (desc : boolean) return positive is
  begin
    if desc then
      return SECTOR_LO_c + FEAT_SECTOR_BITS_c + DESC_BITS_c;
    end if;
    return SECTOR_LO_c;
  end function entry_bits;

  constant ENTRY_BITS_c : positive := entry_bits(DESC_g);
  constant PTR_BITS_c   : positive := clog2(FIFO_DEPTH_g);
  constant SAT_c        : natural  := 2 ** 16 - 1;
  constant GAP_ZERO_c   : std_logic_vector(FEAT_DESC_LO_c - 1 downto FEAT_LOW_BIT_c + 1) := (others => '0');
  constant TOP_ZERO_c   : std_logic_vector(FEAT_BITS_c - 1 downto FEAT_SEL_REPLACE_BIT_c + 1) := (others => '0');

  subtype count_t is natural range 0 to FIFO_DEPTH_g;
  subtype drops_t is natural range 0 to SAT_c;
  subtype entry_t is std_logic_vector(ENTRY_BITS_c - 1 downto 0);

  type entry_arr_t is array (0 to SCALES_g - 1) of entry_t;
  type cnt_arr_t is array (0 to SCALES_g - 1) of count_t;
  type marks_t is array (0 to SCALES_g - 1) of natural range 0 to 2;
  type frame_drops_t is array (0 to 2) of drops_t;  -- oldest waiting frame first
  type frame_cnt_t is array (0 to 2) of natural range 0 to SCALES_g;

  -- FIFO outputs
  signal f_data  : entry_arr_t;
  signal f_valid : std_logic_vector(SCALES_g - 1 downto 0);
  signal f_level : cnt_arr_t;

  -- arbiter (combinational, from the registers below)
  signal pop_v   : std_logic_vector(SCALES_g - 1 downto 0);  -- one-hot: the FIFO read this clock
  signal pop_any : boolean;
  signal pop_idx : natural range 0 to SCALES_g - 1;
  signal eof_go  : boolean;                                  -- the end-of-frame beat goes out

  signal marks  : marks_t := (others => 0);     -- frame ends waiting, per scale
  signal ahead0 : cnt_arr_t := (others => 0);   -- entries of the oldest waiting frame
  -- ahead0 /= 0, kept beside it from compares of registers only, so that the arbiter has no
  -- counter compare in front of it (docs/synthesis.md, "Timing")
  signal a0_nz     : std_logic_vector(SCALES_g - 1 downto 0) := (others => '0');
  signal ahead1    : cnt_arr_t := (others => 0);   -- entries up to the second waiting frame end
  signal frame_drp : frame_drops_t := (others => 0);
  signal drop_r    : std_logic_vector(SCALES_g - 1 downto 0) := (others => '0');  -- lost last clock
  signal drop_fr   : marks_t := (others => 0);     -- ... in that waiting frame (index of frame_drp)
  signal drop_n    : frame_cnt_t := (others => 0);  -- losses counted per waiting frame, not yet added
  signal rr        : natural range 0 to SCALES_g - 1 := 0;
  signal o_valid   : std_logic := '0';
  signal o_last    : std_logic := '0';
  signal o_data    : std_logic_vector(FEAT_SECTOR_LO_c - 1 downto 0) := (others => '0');
  -- sector (low bits) and descriptor of the output word
  signal o_pay : std_logic_vector(FEAT_SECTOR_BITS_c + DESC_BITS_c - 1 downto 0) := (others => '0');
  -- the selection's fields of the output word: low, code, slot, replace (the FIFO entry's order)
  signal o_sel     : std_logic_vector(SEL_BITS_c - 1 downto 0) := (others => '0');
  signal frame_no  : unsigned(EOF_FRAME_BITS_c - 1 downto 0) := (others => '0');
  signal total_drp : unsigned(31 downto 0) := (others => '0');

  function sat_add (a : drops_t; b : natural) return drops_t is
  begin
    if a + b > SAT_c then
      return SAT_c;
    end if;
    return a + b;
  end function sat_add;

  -- (i) mod SCALES_g for 0 <= i < 2 SCALES_g, without a divider: `mod` by a constant that is not a
  -- power of two synthesises as a full 32-bit division (about 2,500 LUTs each at 6 scales).
  function wrap (i : natural) return natural is
  begin
    if i >= SCALES_g then
      return i - SCALES_g;
    end if;
    return i;
  end function wrap;

begin

  assert FIFO_DEPTH_g = 2 ** PTR_BITS_c
    report "orb_feat_merge: FIFO_DEPTH_g must be a power of two"
    severity failure;

  fifos : for k in 0 to SCALES_g - 1 generate
    signal wr_data : entry_t;
    signal level   : std_logic_vector(PTR_BITS_c downto 0);
  begin

    wr_data(BASE_BITS_c - 1 downto 0)           <= in_y((k + 1) * COORD_BITS_c - 1 downto k * COORD_BITS_c) &
                                                   in_x((k + 1) * COORD_BITS_c - 1 downto k * COORD_BITS_c) &
                                                   in_score((k + 1) * SCORE_BITS_c - 1 downto k * SCORE_BITS_c);
    wr_data(SECTOR_LO_c - 1 downto BASE_BITS_c) <= in_replace(k) &
                                                   in_slot((k + 1) * FEAT_SEL_SLOT_BITS_c - 1 downto k * FEAT_SEL_SLOT_BITS_c) &
                                                   in_code((k + 1) * FEAT_RESPONSE_BITS_c - 1 downto k * FEAT_RESPONSE_BITS_c) &
                                                   in_low(k);

    fifo_desc : if DESC_g generate
      wr_data(ENTRY_BITS_c - 1 downto DESC_LO_c) <= in_desc((k + 1) * DESC_BITS_c - 1 downto k * DESC_BITS_c);
      wr_data(DESC_LO_c - 1 downto SECTOR_LO_c)  <= in_sector((k + 1) * SECTOR_BITS_c - 1 downto k * SECTOR_BITS_c);
    end generate fifo_desc;

    -- A write it cannot take (full, no read in this clock) is ignored by the FIFO, and counted
    -- as a loss below with the same condition.
    fifo : entity work.orb_feat_fifo
      generic map (
        DATA_BITS_g => ENTRY_BITS_c,
        DEPTH_g     => FIFO_DEPTH_g
      )
      port map (
        clk      => clk,
        rst      => rst,
        wr_en    => in_valid(k),
        wr_data  => wr_data,
        rd_en    => pop_v(k),
        rd_data  => f_data(k),
        rd_valid => f_valid(k),
        level    => level
      );

    f_level(k) <= to_integer(unsigned(level));

  end generate fifos;

  -- Output side. A scale is eligible when its FIFO shows a feature of the oldest waiting frame;
  -- the end-of-frame beat goes when every scale has delivered that frame (none is eligible then).
  arbiter : process (all) is
    variable req     : std_logic_vector(SCALES_g - 1 downto 0);
    variable blocked : boolean;
    variable all_at  : boolean;
    variable go      : boolean;
  begin
    -- requests, and per scale the requests of the scales before it in the round-robin order that
    -- starts at rr: each grant is a function of the requests and rr alone, no chain through the
    -- scales (docs/synthesis.md, "Timing")
    all_at := true;
    for k in 0 to SCALES_g - 1 loop
      req(k) := '0';
      if marks(k) = 0 or a0_nz(k) = '1' then
        all_at := false;
        req(k) := f_valid(k);
      end if;
    end loop;
    go      := o_valid = '0' or m_axis_feat_tready = '1';
    pop_v   <= (others => '0');
    pop_idx <= 0;
    for k in 0 to SCALES_g - 1 loop
      blocked := false;
      for r in 0 to SCALES_g - 1 loop
        for t in 0 to SCALES_g - 1 loop
          -- t comes before k when the order starts at r
          if rr = r and wrap(t + SCALES_g - r) < wrap(k + SCALES_g - r) and req(t) = '1' then
            blocked := true;
          end if;
        end loop;
      end loop;
      if go and req(k) = '1' and not blocked then
        pop_v(k) <= '1';
        pop_idx  <= k;
      end if;
    end loop;
    pop_any <= go and req /= (req'range => '0');
    eof_go  <= go and all_at;
  end process arbiter;

  merge : process (clk) is
    variable p       : natural range 0 to SCALES_g - 1;
    variable entry   : entry_t;
    variable cnt     : count_t;
    variable room    : boolean;
    variable push    : boolean;
    variable cnt_nz  : boolean;
    variable lvl_up  : cnt_arr_t;
    variable lvl_dn  : cnt_arr_t;
    variable a0, a1  : cnt_arr_t;
    variable nz      : std_logic_vector(SCALES_g - 1 downto 0);
    variable mk      : marks_t;
    variable fd      : frame_drops_t;
    variable n       : natural range 0 to SCALES_g;
    variable cnt_j   : frame_cnt_t;
    variable fd_stay : frame_drops_t;
    variable fd_next : frame_drops_t;
    variable drops   : natural range 0 to SCALES_g;
  begin
    if rising_edge(clk) then
      for k in 0 to SCALES_g - 1 loop
        lvl_up(k) := 0;
        lvl_dn(k) := 0;
        if f_level(k) < FIFO_DEPTH_g then
          lvl_up(k) := f_level(k) + 1;
        end if;
        if f_level(k) > 0 then
          lvl_dn(k) := f_level(k) - 1;
        end if;
      end loop;
      a0 := ahead0;
      nz := a0_nz;
      a1 := ahead1;
      mk := marks;
      fd := frame_drp;

      if o_valid = '0' or m_axis_feat_tready = '1' then
        o_valid <= '0';
        o_last  <= '0';
      end if;
      if pop_any then
        p       := pop_idx;
        entry   := f_data(p);
        o_valid <= '1';
        o_data  <= (others => '0');
        o_data(FEAT_SCORE_LO_c + SCORE_BITS_c - 1 downto FEAT_SCORE_LO_c) <= entry(SCORE_BITS_c - 1 downto 0);
        o_data(FEAT_X_LO_c + COORD_BITS_c - 1 downto FEAT_X_LO_c) <=
          entry(SCORE_BITS_c + COORD_BITS_c - 1 downto SCORE_BITS_c);
        o_data(FEAT_Y_LO_c + COORD_BITS_c - 1 downto FEAT_Y_LO_c) <=
          entry(SCORE_BITS_c + 2 * COORD_BITS_c - 1 downto SCORE_BITS_c + COORD_BITS_c);
        o_data(FEAT_SCALE_LO_c + FEAT_SCALE_BITS_c - 1 downto FEAT_SCALE_LO_c) <=
          std_logic_vector(to_unsigned(p, FEAT_SCALE_BITS_c));
        o_sel   <= entry(SECTOR_LO_c - 1 downto BASE_BITS_c);
        if mk(p) >= 1 then
          a0(p) := a0(p) - 1;
          nz(p) := '1' when ahead0(p) /= 1 else '0';
        end if;
        if mk(p) = 2 then
          a1(p) := a1(p) - 1;
        end if;
        rr <= wrap(p + 1);
      elsif eof_go then
        o_valid <= '1';
        o_last  <= '1';
        o_data  <= (others => '0');
        o_sel   <= (others => '0');
        o_data(FEAT_EOF_BIT_c) <= '1';
        o_data(EOF_FRAME_LO_c + EOF_FRAME_BITS_c - 1 downto EOF_FRAME_LO_c) <= std_logic_vector(frame_no);
        o_data(EOF_DROPS_LO_c + EOF_DROPS_BITS_c - 1 downto EOF_DROPS_LO_c) <=
          std_logic_vector(to_unsigned(fd(0), EOF_DROPS_BITS_c));
        frame_no <= frame_no + 1;
        for k in 0 to SCALES_g - 1 loop
          mk(k) := mk(k) - 1;
          a0(k) := a1(k);
          nz(k) := '1' when ahead1(k) /= 0 else '0';
        end loop;
      end if;

      -- Losses, in three clocks so that neither the count nor the saturating add is a long path
      -- (docs/synthesis.md, "Timing"): registered in drop_r/drop_fr (drop_fr: the index of their
      -- frame among the waiting ones), counted per index into drop_n, added to frame_drp. Both
      -- steps shift the index down by one when the end-of-frame beat goes out in their clock
      -- (both outcomes formed beside the arbiter, which only picks one); that beat is never the
      -- one of a frame with a loss still in the pipeline, since such a frame's beat goes out at
      -- the third clock after the loss at the earliest (a full FIFO holds at least 2 of its
      -- features, and the frame end counts them, one leaves per clock).
      for j in 0 to 2 loop
        n := 0;
        for k in 0 to SCALES_g - 1 loop
          if drop_r(k) = '1' and drop_fr(k) = j then
            n := n + 1;
          end if;
        end loop;
        cnt_j(j) := n;
        fd_stay(j) := sat_add(frame_drp(j), drop_n(j));
        if j < 2 then
          fd_next(j) := sat_add(frame_drp(j + 1), drop_n(j + 1));
        else
          fd_next(j) := 0;  -- the frame after the third waiting one: no losses yet
        end if;
      end loop;
      if eof_go then
        fd     := fd_next;
        drop_n <= (cnt_j(1), cnt_j(2), 0);
      else
        fd     := fd_stay;
        drop_n <= cnt_j;
      end if;
      drops := 0;
      for k in 0 to SCALES_g - 1 loop
        if drop_r(k) = '1' then
          drops := drops + 1;
        end if;
      end loop;
      if drops > 0 then
        total_drp <= total_drp + drops;
      end if;

      -- Input side: a feature joins its FIFO (even a full one if a feature leaves it in this
      -- clock) or is lost (counted next clock, for its own frame: the frame after this scale's
      -- waiting frame ends); a frame end records the entries ahead of it.
      for k in 0 to SCALES_g - 1 loop
        -- the FIFO's new level: one of three values formed beside the arbiter, chosen by its
        -- decision (no adder behind the round robin: docs/synthesis.md, "Timing")
        room := f_level(k) < FIFO_DEPTH_g or pop_v(k) = '1';
        push := in_valid(k) = '1' and room;
        if pop_v(k) = '1' and not push then
          cnt    := lvl_dn(k);
          cnt_nz := f_level(k) /= 1;
        elsif push and pop_v(k) = '0' then
          cnt    := lvl_up(k);
          cnt_nz := true;
        else
          cnt    := f_level(k);
          cnt_nz := f_level(k) /= 0;
        end if;
        drop_r(k)  <= '0';
        drop_fr(k) <= mk(k);
        if in_valid(k) = '1' and not room then
          drop_r(k) <= '1';
        end if;
        if in_done(k) = '1' then
          if mk(k) = 0 then
            a0(k) := cnt;
            nz(k) := '1' when cnt_nz else '0';
            mk(k) := 1;
          else
            a1(k) := cnt;
            mk(k) := 2;
          end if;
        end if;
      end loop;

      ahead0    <= a0;
      a0_nz     <= nz;
      ahead1    <= a1;
      marks     <= mk;
      frame_drp <= fd;

      if rst = '1' then
        ahead0    <= (others => 0);
        a0_nz     <= (others => '0');
        ahead1    <= (others => 0);
        marks     <= (others => 0);
        frame_drp <= (others => 0);
        drop_r    <= (others => '0');
        drop_n    <= (others => 0);
        rr        <= 0;
        o_valid   <= '0';
        o_last    <= '0';
        frame_no  <= (others => '0');
        total_drp <= (others => '0');
      end if;
    end if;
  end process merge;

  -- pragma translate_off
  -- a0_nz is derived state: every assignment of ahead0 has its own for a0_nz; this checks that
  -- they never part in simulation.
  flag_check : process (clk) is
  begin
    if rising_edge(clk) then
      for k in 0 to SCALES_g - 1 loop
        assert (a0_nz(k) = '1') = (ahead0(k) /= 0)
          report "orb_feat_merge: a0_nz(" & integer'image(k) & ") disagrees with ahead0 = " &
                 integer'image(ahead0(k))
          severity failure;
      end loop;
    end if;
  end process flag_check;
  -- pragma translate_on

  -- Sector and descriptor of the output word: loaded with a feature, cleared by an end-of-frame
  -- beat (written as a clear over a load, which maps on the flip-flops' reset and enable pins).
  out_desc : if DESC_g generate

    payload : process (clk) is
    begin
      if rising_edge(clk) then
        if eof_go then
          o_pay <= (others => '0');
        elsif pop_any then
          o_pay <= f_data(pop_idx)(ENTRY_BITS_c - 1 downto SECTOR_LO_c);
        end if;
      end if;
    end process payload;

  else generate

    o_pay <= (others => '0');

  end generate out_desc;

  -- the word: sel_replace, sel_slot above the descriptor; low, response between sector and descriptor
  m_axis_feat_tdata  <= TOP_ZERO_c & o_sel(SEL_BITS_c - 1) & o_sel(SEL_BITS_c - 2 downto FEAT_RESPONSE_BITS_c + 1) &
                        o_pay(o_pay'high downto FEAT_SECTOR_BITS_c) & GAP_ZERO_c & o_sel(0) &
                        o_sel(FEAT_RESPONSE_BITS_c downto 1) & o_pay(FEAT_SECTOR_BITS_c - 1 downto 0) & o_data;
  m_axis_feat_tvalid <= o_valid;
  m_axis_feat_tlast  <= o_last;
  dropped            <= std_logic_vector(total_drp);

end architecture rtl;
