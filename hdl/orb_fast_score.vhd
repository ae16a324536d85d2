-- SPDX-License-Identifier: MIT
-- orb_fast_score: FAST-9 segment test with a run-time threshold and the sum-of-absolute-
-- differences score (docs/spec.md section 4) on a 7x7 window from orb_window. The window's newest
-- pixel is at (in_x, in_y), so the tested centre is (in_x - 3, in_y - 3); the output score is 0
-- unless the centre is a corner at least 3 pixels from the left and top borders (the right and
-- bottom borders are implied: the window only reaches them with its newest pixel). Three pipeline
-- stages: differences and comparisons, arc test and partial sums, final score. The output keeps
-- the input's (x, y) tag.

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_fast_pkg.all;

entity orb_fast_score is
  port (
    clk       : in    std_logic;
    rst       : in    std_logic;
    threshold : in    std_logic_vector(7 downto 0);
    in_valid  : in    std_logic;
    in_x      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_win    : in    std_logic_vector(49 * PIXEL_BITS_c - 1 downto 0);
    out_valid : out   std_logic;
    out_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_score : out   std_logic_vector(SCORE_BITS_c - 1 downto 0)
  );
end entity orb_fast_score;

architecture rtl of orb_fast_score is

  type abs_t is array (0 to 15) of unsigned(7 downto 0);
  type part_t is array (0 to 3) of unsigned(9 downto 0);

  -- stage 1
  signal v1      : std_logic := '0';
  signal x1, y1  : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal bright1 : std_logic_vector(15 downto 0) := (others => '0');
  signal dark1   : std_logic_vector(15 downto 0) := (others => '0');
  signal abs1    : abs_t := (others => (others => '0'));
  signal inner1  : std_logic := '0';
  -- stage 2
  signal v2      : std_logic := '0';
  signal x2, y2  : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal corner2 : std_logic := '0';
  signal part2   : part_t := (others => (others => '0'));
  -- stage 3
  signal v3     : std_logic := '0';
  signal x3, y3 : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal score3 : unsigned(SCORE_BITS_c - 1 downto 0) := (others => '0');

  function pixel (win : std_logic_vector; r, c : natural) return signed is
  begin
    return signed('0' & window_pixel(win, 7, r, c));
  end function pixel;

begin

  stages : process (clk) is
    variable centre : signed(8 downto 0);
    variable diff   : signed(9 downto 0);
    variable t      : signed(9 downto 0);
    variable mag    : signed(9 downto 0);
    variable acc    : unsigned(SCORE_BITS_c - 1 downto 0);
  begin
    if rising_edge(clk) then
      -- stage 1: the 16 differences against the centre (3, 3)
      v1 <= in_valid;
      if in_valid = '1' then
        x1     <= in_x;
        y1     <= in_y;
        centre := pixel(in_win, 3, 3);
        t      := signed("00" & threshold);
        for i in 0 to 15 loop
          diff       := resize(pixel(in_win, 3 + CIRCLE_c(i).dy, 3 + CIRCLE_c(i).dx), 10) - resize(centre, 10);
          bright1(i) <= '1' when diff > t else '0';
          dark1(i)   <= '1' when -diff > t else '0';
          mag        := abs(diff);
          abs1(i)    <= unsigned(mag(7 downto 0));
        end loop;
        inner1 <= '1' when unsigned(in_x) >= 6 and unsigned(in_y) >= 6 else '0';
      end if;
      -- stage 2: arc test and four partial sums
      v2 <= v1;
      if v1 = '1' then
        x2      <= x1;
        y2      <= y1;
        corner2 <= inner1 and (has_arc(bright1) or has_arc(dark1));
        for p in 0 to 3 loop
          part2(p) <= resize(abs1(4 * p), 10) + abs1(4 * p + 1) + abs1(4 * p + 2) + abs1(4 * p + 3);
        end loop;
      end if;
      -- stage 3: the score, 0 for non-corners
      v3 <= v2;
      if v2 = '1' then
        x3  <= x2;
        y3  <= y2;
        acc := resize(part2(0), SCORE_BITS_c) + part2(1) + part2(2) + part2(3);
        if corner2 = '1' then
          score3 <= acc;
        else
          score3 <= (others => '0');
        end if;
      end if;
      if rst = '1' then
        v1 <= '0';
        v2 <= '0';
        v3 <= '0';
      end if;
    end if;
  end process stages;

  out_valid <= v3;
  out_x     <= x3;
  out_y     <= y3;
  out_score <= std_logic_vector(score3);

end architecture rtl;
