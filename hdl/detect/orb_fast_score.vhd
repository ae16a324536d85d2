-- SPDX-License-Identifier: MIT
-- orb_fast_score: FAST-9 segment test at two run-time thresholds and the sum-of-absolute-
-- differences score (docs/spec.md sections 4 and 5) on a 7x7 window from orb_window. The
-- window's newest pixel is at (in_x, in_y), so the tested centre is (in_x - 3, in_y - 3); the
-- output score is 0 unless the centre is a corner at the main threshold or at the low one
-- (threshold_lo, taken as the main threshold when above it) at least 3 pixels from the left and
-- top borders (the right and bottom borders are implied: the window only reaches them with its
-- newest pixel); out_main is 1 for a corner at the main threshold. Four pipeline
-- stages: the 17 pixels of the test registered (the window's shift registers map to SRLs, whose
-- clock-to-output time leaves no room for arithmetic behind them: docs/synthesis.md, "Timing"),
-- differences and comparisons, arc test and partial sums, final score: latency FAST_SCORE_LAT_c = 4 clocks
-- (orb_latency_pkg, docs/latency.md; the valid flags are a delay line of that length). The
-- output keeps the input's (x, y) tag.
-- Ports and generics: docs/entities/orb_fast_score.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_fast_pkg.all;

entity orb_fast_score is
  port (
    clk          : in    std_logic;
    rst          : in    std_logic;
    threshold    : in    std_logic_vector(7 downto 0);
    threshold_lo : in    std_logic_vector(7 downto 0);
    in_valid     : in    std_logic;
    in_x         : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y         : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_win       : in    std_logic_vector(49 * PIXEL_BITS_c - 1 downto 0);
    out_valid    : out   std_logic;
    out_x        : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_y        : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_score    : out   std_logic_vector(SCORE_BITS_c - 1 downto 0);
    out_main     : out   std_logic
  );
end entity orb_fast_score;

architecture rtl of orb_fast_score is

  -- Ranged integers: their ranges set the hardware widths; GHDL simulates them natively.
  subtype mag_t is integer range 0 to 255;
  subtype part_sum_t is integer range 0 to 4 * 255;
  subtype score_t is integer range 0 to 16 * 255;

  type abs_t is array (0 to 15) of mag_t;
  type ring_t is array (0 to 15) of std_logic_vector(PIXEL_BITS_c - 1 downto 0);
  type part_t is array (0 to 3) of part_sum_t;

  -- stage 0: the circle, its centre and the threshold, registered
  -- the valid flags of the stages: v(k) after stage k, v(FAST_SCORE_LAT_c - 1) the output's
  signal v       : std_logic_vector(0 to FAST_SCORE_LAT_c - 1) := (others => '0');
  signal x0, y0  : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal ring0   : ring_t := (others => (others => '0'));
  signal centre0 : std_logic_vector(PIXEL_BITS_c - 1 downto 0) := (others => '0');
  signal t0      : std_logic_vector(7 downto 0) := (others => '0');
  signal tl0     : std_logic_vector(7 downto 0) := (others => '0');  -- the low threshold in effect
  -- stage 1
  signal x1, y1  : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal bright1 : std_logic_vector(15 downto 0) := (others => '0');
  signal dark1   : std_logic_vector(15 downto 0) := (others => '0');
  signal brlo1   : std_logic_vector(15 downto 0) := (others => '0');  -- at the low threshold
  signal dklo1   : std_logic_vector(15 downto 0) := (others => '0');
  signal abs1    : abs_t := (others => 0);
  signal inner1  : std_logic := '0';
  -- stage 2
  signal x2, y2  : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal corner2 : std_logic := '0';  -- a corner at either threshold
  signal main2   : std_logic := '0';  -- a corner at the main threshold
  signal part2   : part_t := (others => 0);
  -- stage 3
  signal x3, y3 : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal score3 : score_t := 0;
  signal main3  : std_logic := '0';


begin

  stages : process (clk) is
    variable centre : mag_t;
    variable diff   : integer range -255 to 255;
    variable t      : mag_t;
    variable tl     : mag_t;
  begin
    if rising_edge(clk) then
      -- stage 0: the pixels of the test, out of the window (its centre is (3, 3))
      v <= in_valid & v(0 to FAST_SCORE_LAT_c - 2);
      if in_valid = '1' then
        x0      <= in_x;
        y0      <= in_y;
        centre0 <= std_logic_vector(window_pixel(in_win, 7, 3, 3));
        for i in 0 to 15 loop
          ring0(i) <= std_logic_vector(window_pixel(in_win, 7, 3 + CIRCLE_c(i).dy, 3 + CIRCLE_c(i).dx));
        end loop;
        t0 <= threshold;
        if unsigned(threshold_lo) < unsigned(threshold) then
          tl0 <= threshold_lo;
        else
          tl0 <= threshold;
        end if;
      end if;
      -- stage 1: the 16 differences against the centre
      if v(0) = '1' then
        x1     <= x0;
        y1     <= y0;
        centre := to_integer(unsigned(centre0));
        t      := to_integer(unsigned(t0));
        tl     := to_integer(unsigned(tl0));
        for i in 0 to 15 loop
          diff       := to_integer(unsigned(ring0(i))) - centre;
          bright1(i) <= '1' when diff > t else '0';
          dark1(i)   <= '1' when -diff > t else '0';
          brlo1(i)   <= '1' when diff > tl else '0';
          dklo1(i)   <= '1' when -diff > tl else '0';
          if diff < 0 then  -- (ghdl synth has no integer abs)
            abs1(i) <= -diff;
          else
            abs1(i) <= diff;
          end if;
        end loop;
        inner1 <= '1' when unsigned(x0) >= 6 and unsigned(y0) >= 6 else '0';
      end if;
      -- stage 2: arc test and four partial sums
      if v(1) = '1' then
        x2      <= x1;
        y2      <= y1;
        -- a corner at t is one at tl <= t too
        main2   <= inner1 and (has_arc(bright1) or has_arc(dark1));
        corner2 <= inner1 and (has_arc(brlo1) or has_arc(dklo1));
        for p in 0 to 3 loop
          part2(p) <= (abs1(4 * p) + abs1(4 * p + 1)) + (abs1(4 * p + 2) + abs1(4 * p + 3));
        end loop;
      end if;
      -- stage 3: the score, 0 for non-corners
      if v(2) = '1' then
        x3  <= x2;
        y3  <= y2;
        main3 <= main2;
        if corner2 = '1' then
          score3 <= (part2(0) + part2(1)) + (part2(2) + part2(3));
        else
          score3 <= 0;
        end if;
      end if;
      if rst = '1' then
        v <= (others => '0');
      end if;
    end if;
  end process stages;

  out_valid <= v(FAST_SCORE_LAT_c - 1);
  out_x     <= x3;
  out_y     <= y3;
  out_score <= std_logic_vector(to_unsigned(score3, SCORE_BITS_c));
  out_main  <= main3;

end architecture rtl;
