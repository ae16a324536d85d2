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

  -- A FIFO entry: a record here, a vector in the FIFO (entry_vec_t, to_vec and to_entry), from
  -- bit 0: score, x, y, the selection's fields (low, response code, slot, replace), then with
  -- DESC_g the sector and the descriptor.
  type sel_fields_t is record
    low     : std_logic;
    code    : std_logic_vector(FEAT_RESPONSE_BITS_c - 1 downto 0);
    slot    : std_logic_vector(FEAT_SEL_SLOT_BITS_c - 1 downto 0);
    replace : std_logic;
  end record sel_fields_t;

  type entry_t is record
    score  : std_logic_vector(SCORE_BITS_c - 1 downto 0);
    x      : std_logic_vector(COORD_BITS_c - 1 downto 0);
    y      : std_logic_vector(COORD_BITS_c - 1 downto 0);
    sel    : sel_fields_t;
    sector : std_logic_vector(FEAT_SECTOR_BITS_c - 1 downto 0);
    desc   : std_logic_vector(DESC_BITS_c - 1 downto 0);
  end record entry_t;

  constant SEL_ZERO_c : sel_fields_t := ('0', (others => '0'), (others => '0'), '0');

  -- the fields' lowest bits in entry_vec_t
  constant X_LO_c      : natural  := SCORE_BITS_c;
  constant Y_LO_c      : natural  := X_LO_c + COORD_BITS_c;
  constant LOW_BIT_c   : natural  := Y_LO_c + COORD_BITS_c;
  constant CODE_LO_c   : natural  := LOW_BIT_c + 1;
  constant SLOT_LO_c   : natural  := CODE_LO_c + FEAT_RESPONSE_BITS_c;
  constant REPLACE_c   : natural  := SLOT_LO_c + FEAT_SEL_SLOT_BITS_c;
  constant SECTOR_LO_c : natural  := REPLACE_c + 1;
  constant DESC_LO_c   : natural  := SECTOR_LO_c + FEAT_SECTOR_BITS_c;
  constant FULL_BITS_c : positive := DESC_LO_c + DESC_BITS_c;

  function entry_bits (desc : boolean) return positive is
  begin
    if desc then
      return FULL_BITS_c;
    end if;
    return SECTOR_LO_c;
  end function entry_bits;

  constant ENTRY_BITS_c : positive := entry_bits(DESC_g);

  subtype entry_vec_t is std_logic_vector(ENTRY_BITS_c - 1 downto 0);

  function to_vec (e : entry_t) return entry_vec_t is
    variable full_v : std_logic_vector(FULL_BITS_c - 1 downto 0);
  begin
    full_v := e.desc & e.sector & e.sel.replace & e.sel.slot & e.sel.code & e.sel.low & e.y & e.x & e.score;
    return full_v(ENTRY_BITS_c - 1 downto 0);
  end function to_vec;

  -- without DESC_g the sector and the descriptor are 0
  function to_entry (vec : entry_vec_t) return entry_t is
    variable full_v : std_logic_vector(FULL_BITS_c - 1 downto 0) := (others => '0');
  begin
    full_v(ENTRY_BITS_c - 1 downto 0) := vec;
    return (score  => full_v(X_LO_c - 1 downto 0),
            x      => full_v(Y_LO_c - 1 downto X_LO_c),
            y      => full_v(LOW_BIT_c - 1 downto Y_LO_c),
            sel    => (low     => full_v(LOW_BIT_c),
                       code    => full_v(SLOT_LO_c - 1 downto CODE_LO_c),
                       slot    => full_v(REPLACE_c - 1 downto SLOT_LO_c),
                       replace => full_v(REPLACE_c)),
            sector => full_v(DESC_LO_c - 1 downto SECTOR_LO_c),
            desc   => full_v(FULL_BITS_c - 1 downto DESC_LO_c));
  end function to_entry;

  constant PTR_BITS_c  : positive := clog2(FIFO_DEPTH_g);
  constant DROPS_MAX_c : natural  := 2 ** EOF_DROPS_BITS_c - 1;  -- a frame's loss count saturates here
  -- frame ends that can wait per scale; the loss counts cover them and the frame after the last
  constant ENDS_MAX_c : natural  := 2;

  subtype level_t is natural range 0 to FIFO_DEPTH_g;
  subtype drops_t is natural range 0 to DROPS_MAX_c;
  subtype ends_t is natural range 0 to ENDS_MAX_c;  -- frame ends waiting; also a frame's index among them

  type entry_arr_t is array (0 to SCALES_g - 1) of entry_vec_t;
  type level_arr_t is array (0 to SCALES_g - 1) of level_t;
  type ends_arr_t is array (0 to SCALES_g - 1) of ends_t;
  type frame_drops_t is array (0 to ENDS_MAX_c) of drops_t;                 -- oldest waiting frame first
  type frame_losses_t is array (0 to ENDS_MAX_c) of natural range 0 to SCALES_g;

  -- FIFO outputs, and whether a FIFO takes a write this clock (not full, or a feature leaves it)
  signal fifo_data  : entry_arr_t;
  signal fifo_valid : std_logic_vector(SCALES_g - 1 downto 0);
  signal fifo_level : level_arr_t;
  signal fifo_room  : std_logic_vector(SCALES_g - 1 downto 0);

  -- arbiter (combinational, from the registers below)
  signal grant   : std_logic_vector(SCALES_g - 1 downto 0);  -- one-hot: the FIFO read this clock
  signal pop_any : boolean;
  signal pop_idx : natural range 0 to SCALES_g - 1;
  signal eof_go  : boolean;                                  -- the end-of-frame beat goes out

  -- frame ends (process frame_ends)
  signal ends_waiting : ends_arr_t := (others => 0);       -- frame ends waiting, per scale
  signal ahead0       : level_arr_t := (others => 0);      -- entries of the oldest waiting frame
  -- ahead0 /= 0, kept beside it from compares of registers only, so that the arbiter has no
  -- counter compare in front of it (docs/synthesis.md, "Timing")
  signal ahead0_nz : std_logic_vector(SCALES_g - 1 downto 0) := (others => '0');
  signal ahead1    : level_arr_t := (others => 0);      -- entries up to the second waiting frame end

  -- losses (process losses)
  signal lost_r       : std_logic_vector(SCALES_g - 1 downto 0) := (others => '0');  -- lost last clock
  signal lost_frame   : ends_arr_t := (others => 0);        -- ... in that waiting frame (frame_drops index)
  signal frame_losses : frame_losses_t := (others => 0);    -- losses counted per waiting frame, not yet added
  signal frame_drops  : frame_drops_t := (others => 0);
  signal total_drops  : unsigned(dropped'range) := (others => '0');

  -- output register (process output): the word's bits below the sector (a feature's score, x, y
  -- and scale, or the end-of-frame beat's fields), its selection fields, and (process payload) its
  -- sector and descriptor
  signal rr       : natural range 0 to SCALES_g - 1 := 0;
  signal o_valid  : std_logic := '0';
  signal o_last   : std_logic := '0';
  signal o_head   : std_logic_vector(FEAT_SECTOR_LO_c - 1 downto 0) := (others => '0');
  signal o_sel    : sel_fields_t := SEL_ZERO_c;
  signal o_sector : std_logic_vector(FEAT_SECTOR_BITS_c - 1 downto 0) := (others => '0');
  signal o_desc   : std_logic_vector(DESC_BITS_c - 1 downto 0) := (others => '0');
  signal frame_no : unsigned(EOF_FRAME_BITS_c - 1 downto 0) := (others => '0');

  function sat_add (a : drops_t; b : natural) return drops_t is
  begin
    if a + b > DROPS_MAX_c then
      return DROPS_MAX_c;
    end if;
    return a + b;
  end function sat_add;

  -- the frame ends waiting once this clock's end-of-frame beat (if any) has gone (it goes only
  -- when every scale has one waiting)
  function ends_after (ends : ends_arr_t; beat : boolean) return ends_arr_t is
    variable ends_v : ends_arr_t := ends;
  begin
    if beat then
      for k in ends_v'range loop
        ends_v(k) := ends_v(k) - 1;
      end loop;
    end if;
    return ends_v;
  end function ends_after;

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
    signal wr_entry : entry_t;
    signal wr_vec   : entry_vec_t;  -- a signal, not to_vec() in the port map: GHDL 2.0 synth crashes on that
    signal level    : std_logic_vector(PTR_BITS_c downto 0);
  begin

    wr_entry.score       <= in_score((k + 1) * SCORE_BITS_c - 1 downto k * SCORE_BITS_c);
    wr_entry.x           <= in_x((k + 1) * COORD_BITS_c - 1 downto k * COORD_BITS_c);
    wr_entry.y           <= in_y((k + 1) * COORD_BITS_c - 1 downto k * COORD_BITS_c);
    wr_entry.sel.low     <= in_low(k);
    wr_entry.sel.code    <= in_code((k + 1) * FEAT_RESPONSE_BITS_c - 1 downto k * FEAT_RESPONSE_BITS_c);
    wr_entry.sel.slot    <= in_slot((k + 1) * FEAT_SEL_SLOT_BITS_c - 1 downto k * FEAT_SEL_SLOT_BITS_c);
    wr_entry.sel.replace <= in_replace(k);
    wr_entry.sector      <= in_sector((k + 1) * FEAT_SECTOR_BITS_c - 1 downto k * FEAT_SECTOR_BITS_c);
    wr_entry.desc        <= in_desc((k + 1) * DESC_BITS_c - 1 downto k * DESC_BITS_c);
    wr_vec               <= to_vec(wr_entry);

    -- A write it cannot take (fifo_room low: full, no read in this clock) is ignored by the FIFO,
    -- and counted as a loss by the process losses.
    fifo : entity work.orb_feat_fifo
      generic map (
        DATA_BITS_g => ENTRY_BITS_c,
        DEPTH_g     => FIFO_DEPTH_g
      )
      port map (
        clk      => clk,
        rst      => rst,
        wr_en    => in_valid(k),
        wr_data  => wr_vec,
        rd_en    => grant(k),
        rd_data  => fifo_data(k),
        rd_valid => fifo_valid(k),
        level    => level
      );

    fifo_level(k) <= to_integer(unsigned(level));
    fifo_room(k)  <= '1' when fifo_level(k) < FIFO_DEPTH_g or grant(k) = '1' else
                     '0';

  end generate fifos;

  -- Output side. A scale is eligible when its FIFO shows a feature of the oldest waiting frame;
  -- the end-of-frame beat goes when every scale has delivered that frame (none is eligible then).
  arbiter : process (all) is
    variable request_v : std_logic_vector(SCALES_g - 1 downto 0);
    variable blocked_v : boolean;
    variable all_at_v  : boolean; -- every scale is at a frame end with nothing of the frame left
    variable go_v      : boolean; -- the output register can load
  begin
    -- requests, and per scale the requests of the scales before it in the round-robin order that
    -- starts at rr: each grant is a function of the requests and rr alone, no chain through the
    -- scales (docs/synthesis.md, "Timing")
    all_at_v := true;
    for k in 0 to SCALES_g - 1 loop
      request_v(k) := '0';
      if ends_waiting(k) = 0 or ahead0_nz(k) = '1' then
        all_at_v     := false;
        request_v(k) := fifo_valid(k);
      end if;
    end loop;
    go_v    := o_valid = '0' or m_axis_feat_tready = '1';
    grant   <= (others => '0');
    pop_idx <= 0;
    for k in 0 to SCALES_g - 1 loop
      blocked_v := false;
      for r in 0 to SCALES_g - 1 loop
        for t in 0 to SCALES_g - 1 loop
          -- t comes before k when the order starts at r
          if rr = r and wrap(t + SCALES_g - r) < wrap(k + SCALES_g - r) and request_v(t) = '1' then
            blocked_v := true;
          end if;
        end loop;
      end loop;
      if go_v and request_v(k) = '1' and not blocked_v then
        grant(k) <= '1';
        pop_idx  <= k;
      end if;
    end loop;
    pop_any <= go_v and request_v /= (request_v'range => '0');
    eof_go  <= go_v and all_at_v;
  end process arbiter;

  -- The output register and the round-robin pointer: a feature from the granted FIFO, or the
  -- end-of-frame beat with its frame number and its frame's loss count.
  output : process (clk) is
    variable scale_v : natural range 0 to SCALES_g - 1;  -- a natural copy of pop_idx (GHDL 2.0 synth, SCALES_g = 1)
    variable entry_v : entry_t;
  begin
    if rising_edge(clk) then
      if o_valid = '0' or m_axis_feat_tready = '1' then
        o_valid <= '0';
        o_last  <= '0';
      end if;
      if pop_any then
        scale_v := pop_idx;
        entry_v := to_entry(fifo_data(scale_v));
        o_valid <= '1';
        o_head  <= (others => '0');
        o_head(FEAT_SCORE_LO_c + FEAT_SCORE_BITS_c - 1 downto FEAT_SCORE_LO_c) <= entry_v.score;
        o_head(FEAT_X_LO_c + FEAT_X_BITS_c - 1 downto FEAT_X_LO_c)             <= entry_v.x;
        o_head(FEAT_Y_LO_c + FEAT_Y_BITS_c - 1 downto FEAT_Y_LO_c)             <= entry_v.y;
        o_head(FEAT_SCALE_LO_c + FEAT_SCALE_BITS_c - 1 downto FEAT_SCALE_LO_c) <=
          std_logic_vector(to_unsigned(scale_v, FEAT_SCALE_BITS_c));
        o_sel   <= entry_v.sel;
        rr      <= wrap(scale_v + 1);
      elsif eof_go then
        o_valid <= '1';
        o_last  <= '1';
        o_head  <= (others => '0');
        o_sel   <= SEL_ZERO_c;
        o_head(FEAT_EOF_BIT_c) <= '1';
        o_head(EOF_FRAME_LO_c + EOF_FRAME_BITS_c - 1 downto EOF_FRAME_LO_c) <= std_logic_vector(frame_no);
        o_head(EOF_DROPS_LO_c + EOF_DROPS_BITS_c - 1 downto EOF_DROPS_LO_c) <=
          std_logic_vector(to_unsigned(frame_drops(0), EOF_DROPS_BITS_c));
        frame_no <= frame_no + 1;
      end if;
      if rst = '1' then
        rr       <= 0;
        o_valid  <= '0';
        o_last   <= '0';
        frame_no <= (others => '0');
      end if;
    end if;
  end process output;

  -- Sector and descriptor of the output word: loaded with a feature, cleared by an end-of-frame
  -- beat (written as a clear over a load, which maps on the flip-flops' reset and enable pins).
  out_desc : if DESC_g generate

    payload : process (clk) is
      variable entry_v : entry_t;
    begin
      if rising_edge(clk) then
        entry_v := to_entry(fifo_data(pop_idx));
        if eof_go then
          o_sector <= (others => '0');
          o_desc   <= (others => '0');
        elsif pop_any then
          o_sector <= entry_v.sector;
          o_desc   <= entry_v.desc;
        end if;
      end if;
    end process payload;

  else generate

    o_sector <= (others => '0');
    o_desc   <= (others => '0');

  end generate out_desc;

  -- Frame ends. A scale's frame end records the FIFO entries still ahead of it: ahead0 for the
  -- oldest waiting one (counted down as they leave), ahead1 for a second; the end-of-frame beat
  -- retires the oldest (ahead1 moves up); a third merges into the second.
  frame_ends : process (clk) is
    variable scale_v     : natural range 0 to SCALES_g - 1; -- a natural copy of pop_idx (GHDL 2.0 synth)
    variable ahead0_v    : level_arr_t;
    variable ahead0_nz_v : std_logic_vector(SCALES_g - 1 downto 0);
    variable ahead1_v    : level_arr_t;
    variable ends_v      : ends_arr_t;
    variable push_v      : boolean;
    variable level_up_v  : level_t;                         -- the FIFO's level + 1 and - 1
    variable level_dn_v  : level_t;
    variable level_v     : level_t;                         -- the FIFO's level after this clock
    variable level_nz_v  : boolean;
  begin
    if rising_edge(clk) then
      ahead0_v    := ahead0;
      ahead0_nz_v := ahead0_nz;
      ahead1_v    := ahead1;
      ends_v      := ends_after(ends_waiting, eof_go);

      if pop_any then
        scale_v := pop_idx;
        if ends_waiting(scale_v) >= 1 then
          ahead0_v(scale_v)    := ahead0_v(scale_v) - 1;
          ahead0_nz_v(scale_v) := '1' when ahead0(scale_v) /= 1 else '0';
        end if;
        if ends_waiting(scale_v) = 2 then
          ahead1_v(scale_v) := ahead1_v(scale_v) - 1;
        end if;
      elsif eof_go then
        for k in 0 to SCALES_g - 1 loop
          ahead0_v(k)    := ahead1_v(k);
          ahead0_nz_v(k) := '1' when ahead1(k) /= 0 else '0';
        end loop;
      end if;

      for k in 0 to SCALES_g - 1 loop
        -- the FIFO's new level: one of three values formed beside the arbiter, chosen by its
        -- decision (no adder behind the round robin: docs/synthesis.md, "Timing")
        level_up_v := 0;
        level_dn_v := 0;
        if fifo_level(k) < FIFO_DEPTH_g then
          level_up_v := fifo_level(k) + 1;
        end if;
        if fifo_level(k) > 0 then
          level_dn_v := fifo_level(k) - 1;
        end if;
        push_v := in_valid(k) = '1' and fifo_room(k) = '1';
        if grant(k) = '1' and not push_v then
          level_v    := level_dn_v;
          level_nz_v := fifo_level(k) /= 1;
        elsif push_v and grant(k) = '0' then
          level_v    := level_up_v;
          level_nz_v := true;
        else
          level_v    := fifo_level(k);
          level_nz_v := fifo_level(k) /= 0;
        end if;
        if in_done(k) = '1' then
          if ends_v(k) = 0 then
            ahead0_v(k)    := level_v;
            ahead0_nz_v(k) := '1' when level_nz_v else '0';
            ends_v(k)      := 1;
          else
            ahead1_v(k) := level_v;
            ends_v(k)   := 2;
          end if;
        end if;
      end loop;

      ahead0       <= ahead0_v;
      ahead0_nz    <= ahead0_nz_v;
      ahead1       <= ahead1_v;
      ends_waiting <= ends_v;

      if rst = '1' then
        ahead0       <= (others => 0);
        ahead0_nz    <= (others => '0');
        ahead1       <= (others => 0);
        ends_waiting <= (others => 0);
      end if;
    end if;
  end process frame_ends;

  -- pragma translate_off
  -- ahead0_nz is derived state: every assignment of ahead0 has its own for ahead0_nz; this checks
  -- that they never part in simulation.
  flag_check : process (clk) is
  begin
    if rising_edge(clk) then
      for k in 0 to SCALES_g - 1 loop
        assert (ahead0_nz(k) = '1') = (ahead0(k) /= 0)
          report "orb_feat_merge: ahead0_nz(" & integer'image(k) & ") disagrees with ahead0 = " &
                 integer'image(ahead0(k))
          severity failure;
      end loop;
    end if;
  end process flag_check;
  -- pragma translate_on

  -- Losses, in three clocks so that neither the count nor the saturating add is a long path
  -- (docs/synthesis.md, "Timing"): registered in lost_r / lost_frame (the index of their frame
  -- among the waiting ones: a feature lost belongs to the frame after its scale's waiting frame
  -- ends), counted per index into frame_losses, added to frame_drops. Both steps shift the index
  -- down by one when the end-of-frame beat goes out in their clock (both outcomes formed beside
  -- the arbiter, which only picks one); that beat is never the one of a frame with a loss still in
  -- the pipeline, since such a frame's beat goes out at the third clock after the loss at the
  -- earliest (a full FIFO holds at least 2 of its features, and the frame end counts them, one
  -- leaves per clock). The total on `dropped` counts lost_r.
  losses : process (clk) is
    variable count_v : natural range 0 to SCALES_g;
    variable new_v   : frame_losses_t; -- lost_r counted per waiting frame
    variable stay_v  : frame_drops_t;  -- frame_drops with frame_losses added, no beat
    variable shift_v : frame_drops_t;  -- the same, shifted down by the beat
    variable total_v : natural range 0 to SCALES_g;
    variable ends_v  : ends_arr_t;
  begin
    if rising_edge(clk) then
      for j in 0 to ENDS_MAX_c loop
        count_v := 0;
        for k in 0 to SCALES_g - 1 loop
          if lost_r(k) = '1' and lost_frame(k) = j then
            count_v := count_v + 1;
          end if;
        end loop;
        new_v(j)  := count_v;
        stay_v(j) := sat_add(frame_drops(j), frame_losses(j));
        if j < ENDS_MAX_c then
          shift_v(j) := sat_add(frame_drops(j + 1), frame_losses(j + 1));
        else
          shift_v(j) := 0;  -- the frame after the last waiting one: no losses yet
        end if;
      end loop;
      if eof_go then
        frame_drops  <= shift_v;
        frame_losses <= new_v(1 to ENDS_MAX_c) & 0;
      else
        frame_drops  <= stay_v;
        frame_losses <= new_v;
      end if;
      total_v := 0;
      for k in 0 to SCALES_g - 1 loop
        if lost_r(k) = '1' then
          total_v := total_v + 1;
        end if;
      end loop;
      if total_v > 0 then
        total_drops <= total_drops + total_v;
      end if;

      ends_v := ends_after(ends_waiting, eof_go);
      for k in 0 to SCALES_g - 1 loop
        lost_r(k)     <= in_valid(k) and not fifo_room(k);
        lost_frame(k) <= ends_v(k);
      end loop;

      if rst = '1' then
        frame_drops  <= (others => 0);
        lost_r       <= (others => '0');
        frame_losses <= (others => 0);
        total_drops  <= (others => '0');
      end if;
    end if;
  end process losses;

  -- the word: every field at its place in orb_feat_pkg, the other bits 0
  word : process (all) is
    variable word_v : std_logic_vector(FEAT_BITS_c - 1 downto 0);
  begin
    word_v                                     := (others => '0');
    word_v(FEAT_SECTOR_LO_c - 1 downto 0)      := o_head;
    word_v(FEAT_SECTOR_LO_c + FEAT_SECTOR_BITS_c - 1 downto FEAT_SECTOR_LO_c) := o_sector;
    word_v(FEAT_RESPONSE_LO_c + FEAT_RESPONSE_BITS_c - 1 downto FEAT_RESPONSE_LO_c) := o_sel.code;
    word_v(FEAT_LOW_BIT_c)                     := o_sel.low;
    word_v(FEAT_DESC_LO_c + FEAT_DESC_BITS_c - 1 downto FEAT_DESC_LO_c) := o_desc;
    word_v(FEAT_SEL_SLOT_LO_c + FEAT_SEL_SLOT_BITS_c - 1 downto FEAT_SEL_SLOT_LO_c) := o_sel.slot;
    word_v(FEAT_SEL_REPLACE_BIT_c)             := o_sel.replace;
    m_axis_feat_tdata <= word_v;
  end process word;

  m_axis_feat_tvalid <= o_valid;
  m_axis_feat_tlast  <= o_last;
  dropped            <= std_logic_vector(total_drops);

end architecture rtl;
