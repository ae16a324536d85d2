-- SPDX-License-Identifier: MIT
-- orb_feat_merge: merges the feature streams of SCALES_g scales into one AXI4-Stream. Each scale
-- has a FIFO of FIFO_DEPTH_g features; a round-robin arbiter moves one feature per clock to the
-- output register. A scale's frame end (in_done) is not stored in its FIFO but remembered as the
-- number of FIFO entries that still belong to the ending frame, so a frame end can never be
-- overtaken or dropped. When every scale has delivered its whole frame, one end-of-frame beat
-- (tlast = 1, layout in orb_feat_pkg) follows the frame's features. Up to two frame ends per
-- scale can wait for their beat (the output stalled for a whole frame); a third merges into the
-- newest waiting one. A feature that finds its FIFO full is dropped and counted: in total on
-- `dropped`, and per frame (the frame the feature belongs to) in the end-of-frame beat,
-- saturating at 65535.

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_feat_pkg.all;

entity orb_feat_merge is
  generic (
    SCALES_g     : positive range 1 to 4   := 1;
    FIFO_DEPTH_g : positive range 2 to 512 := 32
  );
  port (
    clk                : in    std_logic;
    rst                : in    std_logic;
    in_valid           : in    std_logic_vector(SCALES_g - 1 downto 0);
    in_x               : in    std_logic_vector(SCALES_g * COORD_BITS_c - 1 downto 0);
    in_y               : in    std_logic_vector(SCALES_g * COORD_BITS_c - 1 downto 0);
    in_score           : in    std_logic_vector(SCALES_g * SCORE_BITS_c - 1 downto 0);
    in_done            : in    std_logic_vector(SCALES_g - 1 downto 0);
    m_axis_feat_tdata  : out   std_logic_vector(FEAT_BITS_c - 1 downto 0);
    m_axis_feat_tvalid : out   std_logic;
    m_axis_feat_tready : in    std_logic;
    m_axis_feat_tlast  : out   std_logic;
    dropped            : out   std_logic_vector(31 downto 0)
  );
end entity orb_feat_merge;

architecture rtl of orb_feat_merge is

  constant ENTRY_BITS_c : positive := 2 * COORD_BITS_c + SCORE_BITS_c;  -- y, x, score
  constant PTR_BITS_c   : positive := clog2(FIFO_DEPTH_g);
  constant SAT_c        : natural  := 2 ** 16 - 1;

  subtype count_t is natural range 0 to FIFO_DEPTH_g;
  subtype ptr_t is natural range 0 to FIFO_DEPTH_g - 1;
  subtype drops_t is natural range 0 to SAT_c;

  type fifo_mem_t is array (0 to FIFO_DEPTH_g - 1) of std_logic_vector(ENTRY_BITS_c - 1 downto 0);
  type fifo_arr_t is array (0 to SCALES_g - 1) of fifo_mem_t;
  type ptr_arr_t is array (0 to SCALES_g - 1) of ptr_t;
  type cnt_arr_t is array (0 to SCALES_g - 1) of count_t;
  type marks_t is array (0 to SCALES_g - 1) of natural range 0 to 2;
  type frame_drops_t is array (0 to 2) of drops_t;  -- oldest waiting frame first

  signal fifo      : fifo_arr_t;
  signal head      : ptr_arr_t := (others => 0);
  signal tail      : ptr_arr_t := (others => 0);
  signal count     : cnt_arr_t := (others => 0);
  signal marks     : marks_t := (others => 0);     -- frame ends waiting, per scale
  signal ahead0    : cnt_arr_t := (others => 0);   -- entries of the oldest waiting frame
  signal ahead1    : cnt_arr_t := (others => 0);   -- entries up to the second waiting frame end
  signal frame_drp : frame_drops_t := (others => 0);
  signal rr        : natural range 0 to SCALES_g - 1 := 0;
  signal o_valid   : std_logic := '0';
  signal o_last    : std_logic := '0';
  signal o_data    : std_logic_vector(FEAT_BITS_c - 1 downto 0) := (others => '0');
  signal frame_no  : unsigned(15 downto 0) := (others => '0');
  signal total_drp : unsigned(31 downto 0) := (others => '0');

  function sat_add (a : drops_t; b : natural) return drops_t is
  begin
    if a + b > SAT_c then
      return SAT_c;
    end if;
    return a + b;
  end function sat_add;

begin

  assert FIFO_DEPTH_g = 2 ** PTR_BITS_c
    report "orb_feat_merge: FIFO_DEPTH_g must be a power of two"
    severity failure;

  merge : process (clk) is
    variable entry  : std_logic_vector(ENTRY_BITS_c - 1 downto 0);
    variable pop    : integer range -1 to SCALES_g - 1;
    variable p      : natural range 0 to SCALES_g - 1;  -- pop as an index (GHDL synth needs >= 0)
    variable s      : natural range 0 to SCALES_g - 1;
    variable all_at : boolean;
    variable cnt    : cnt_arr_t;
    variable a0, a1 : cnt_arr_t;
    variable mk     : marks_t;
    variable hd, tl : ptr_arr_t;
    variable fd     : frame_drops_t;
    variable drops  : natural range 0 to SCALES_g;
  begin
    if rising_edge(clk) then
      cnt   := count;
      a0    := ahead0;
      a1    := ahead1;
      mk    := marks;
      hd    := head;
      tl    := tail;
      fd    := frame_drp;
      drops := 0;

      -- Output side. A scale is eligible when it holds a feature of the oldest waiting frame.
      if o_valid = '0' or m_axis_feat_tready = '1' then
        o_valid <= '0';
        o_last  <= '0';
        pop     := -1;
        all_at  := true;
        for k in 0 to SCALES_g - 1 loop
          if mk(k) = 0 or a0(k) /= 0 then
            all_at := false;
          end if;
        end loop;
        for k in 0 to SCALES_g - 1 loop
          s := (rr + k) mod SCALES_g;
          if pop < 0 and cnt(s) > 0 and (mk(s) = 0 or a0(s) > 0) then
            pop := s;
          end if;
        end loop;
        if pop >= 0 then
          p       := pop;
          entry   := fifo(p)(hd(p));
          o_valid <= '1';
          o_data  <= (others => '0');
          o_data(FEAT_SCORE_LO_c + SCORE_BITS_c - 1 downto FEAT_SCORE_LO_c) <= entry(SCORE_BITS_c - 1 downto 0);
          o_data(FEAT_X_LO_c + COORD_BITS_c - 1 downto FEAT_X_LO_c) <=
            entry(SCORE_BITS_c + COORD_BITS_c - 1 downto SCORE_BITS_c);
          o_data(FEAT_Y_LO_c + COORD_BITS_c - 1 downto FEAT_Y_LO_c) <=
            entry(SCORE_BITS_c + 2 * COORD_BITS_c - 1 downto SCORE_BITS_c + COORD_BITS_c);
          o_data(FEAT_SCALE_LO_c + 1 downto FEAT_SCALE_LO_c) <= std_logic_vector(to_unsigned(p, 2));
          hd(p)  := (hd(p) + 1) mod FIFO_DEPTH_g;
          cnt(p) := cnt(p) - 1;
          if mk(p) >= 1 then
            a0(p) := a0(p) - 1;
          end if;
          if mk(p) = 2 then
            a1(p) := a1(p) - 1;
          end if;
          rr <= (p + 1) mod SCALES_g;
        elsif all_at then
          o_valid <= '1';
          o_last  <= '1';
          o_data  <= (others => '0');
          o_data(FEAT_EOF_BIT_c) <= '1';
          o_data(EOF_FRAME_LO_c + 15 downto EOF_FRAME_LO_c) <= std_logic_vector(frame_no);
          o_data(EOF_DROPS_LO_c + 15 downto EOF_DROPS_LO_c) <= std_logic_vector(to_unsigned(fd(0), 16));
          frame_no <= frame_no + 1;
          fd       := (fd(1), fd(2), 0);
          for k in 0 to SCALES_g - 1 loop
            mk(k) := mk(k) - 1;
            a0(k) := a1(k);
          end loop;
        end if;
      end if;

      -- Input side: a feature joins its FIFO or is dropped (and counted for its own frame, the
      -- frame after this scale's waiting frame ends); a frame end records the entries ahead of it.
      for k in 0 to SCALES_g - 1 loop
        if in_valid(k) = '1' then
          if cnt(k) < FIFO_DEPTH_g then
            fifo(k)(tl(k)) <= in_y((k + 1) * COORD_BITS_c - 1 downto k * COORD_BITS_c) &
                              in_x((k + 1) * COORD_BITS_c - 1 downto k * COORD_BITS_c) &
                              in_score((k + 1) * SCORE_BITS_c - 1 downto k * SCORE_BITS_c);
            tl(k)  := (tl(k) + 1) mod FIFO_DEPTH_g;
            cnt(k) := cnt(k) + 1;
          else
            drops     := drops + 1;
            fd(mk(k)) := sat_add(fd(mk(k)), 1);
          end if;
        end if;
        if in_done(k) = '1' then
          if mk(k) = 0 then
            a0(k) := cnt(k);
            mk(k) := 1;
          else
            a1(k) := cnt(k);
            mk(k) := 2;
          end if;
        end if;
      end loop;
      if drops > 0 then
        total_drp <= total_drp + drops;
      end if;

      count     <= cnt;
      ahead0    <= a0;
      ahead1    <= a1;
      marks     <= mk;
      head      <= hd;
      tail      <= tl;
      frame_drp <= fd;

      if rst = '1' then
        count     <= (others => 0);
        ahead0    <= (others => 0);
        ahead1    <= (others => 0);
        marks     <= (others => 0);
        head      <= (others => 0);
        tail      <= (others => 0);
        frame_drp <= (others => 0);
        rr        <= 0;
        o_valid   <= '0';
        o_last    <= '0';
        frame_no  <= (others => '0');
        total_drp <= (others => '0');
      end if;
    end if;
  end process merge;

  m_axis_feat_tdata  <= o_data;
  m_axis_feat_tvalid <= o_valid;
  m_axis_feat_tlast  <= o_last;
  dropped            <= std_logic_vector(total_drp);

end architecture rtl;
