-- SPDX-License-Identifier: MIT
-- orb_smooth: 7x7 smoothing (docs/spec.md section 7) of the centre of a sliding 7x7 window:
-- B = (sum k_i k_j P + 2048) >> 12 with k = (5, 8, 12, 14, 12, 8, 5). The window is the last seven
-- columns given (in_col, one column per valid beat, top pixel in the low byte), as orb_window
-- slides its window, so only the newest column is weighed each beat (constant shift-add
-- multiplies, no DSP; in two halves, then their sum) and the seven weighted column sums slide in
-- a register row beside the window; then the weighted row of column sums in two halves (three
-- partial sums, their total), then the rounding shift: no stage adds more than five terms
-- (docs/synthesis.md "Timing"): five pipeline stages, latency SMOOTH_LAT_c = 5 clocks (orb_latency_pkg,
-- docs/latency.md; the valid flags are a delay line of that length). The newest column is at
-- (in_x, in_y), so the output is the smoothed value of
-- (in_x - 3, in_y - 3) and carries the input's (x, y) tag; positions whose window wraps around a
-- line or frame edge (in_x < 6 or in_y < 6) give 0, so a column sum from an earlier line, frame
-- or reset never reaches an output. The sums are ranged integers (their ranges set the hardware
-- widths; GHDL simulates them natively). Page: docs/rtl-description.md.
-- Ports and generics: docs/entities/orb_smooth.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;

entity orb_smooth is
  port (
    clk       : in    std_logic;
    rst       : in    std_logic;
    in_valid  : in    std_logic;
    in_x      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_col    : in    std_logic_vector(7 * PIXEL_BITS_c - 1 downto 0);
    out_valid : out   std_logic;
    out_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_data  : out   std_logic_vector(PIXEL_BITS_c - 1 downto 0)
  );
end entity orb_smooth;

architecture rtl of orb_smooth is

  subtype col_sum_t is integer range 0 to 64 * 255;
  subtype total_t is integer range 0 to 4096 * 255 + 2048;

  type col_sums_t is array (0 to 6) of col_sum_t;

  subtype part_t is integer range 0 to 26 * 64 * 255 + 2048;  -- at most 26 (14 + 12) of the column weights

  type parts_t is array (0 to 2) of part_t;

  type halves_t is array (0 to 1) of col_sum_t;

  -- the valid flags of the stages: v(k) after stage k, v(SMOOTH_LAT_c) the output's
  signal v      : std_logic_vector(1 to SMOOTH_LAT_c) := (others => '0');
  signal xa, ya : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal innera : std_logic := '0';
  signal halfa  : halves_t := (others => 0);
  signal xp, yp : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal innerp : std_logic := '0';
  signal parts  : parts_t := (others => 0);
  signal x1, y1 : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal x2, y2 : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal x3, y3 : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal inner1 : std_logic := '0';
  signal inner2 : std_logic := '0';
  signal cols1  : col_sums_t := (others => 0);  -- cols1(6) is the newest column's sum
  signal total2 : total_t := 0;
  signal out3   : unsigned(PIXEL_BITS_c - 1 downto 0) := (others => '0');

  -- k * v for the kernel's weights, as shifts and adds (multiplications by powers of two).
  function weigh (k : natural; v : natural) return natural is
  begin
    case k is
      when 0 | 6  => return v * 4 + v;          -- 5
      when 1 | 5  => return v * 8;              -- 8
      when 2 | 4  => return v * 8 + v * 4;      -- 12
      when others => return v * 16 - v * 2;     -- 14
    end case;
  end function weigh;

begin

  stages : process (clk) is
    variable acc : total_t;
  begin
    if rising_edge(clk) then
      -- stage 1a: the newest column weighed in two halves (rows 0-3, rows 4-6)
      v <= in_valid & v(1 to SMOOTH_LAT_c - 1);
      if in_valid = '1' then
        xa     <= in_x;
        ya     <= in_y;
        innera <= '1' when unsigned(in_x) >= 6 and unsigned(in_y) >= 6 else '0';
        acc    := 0;
        for r in 0 to 3 loop
          acc := acc + weigh(r, to_integer(unsigned(in_col((r + 1) * PIXEL_BITS_c - 1 downto r * PIXEL_BITS_c))));
        end loop;
        halfa(0) <= acc;
        acc      := 0;
        for r in 4 to 6 loop
          acc := acc + weigh(r, to_integer(unsigned(in_col((r + 1) * PIXEL_BITS_c - 1 downto r * PIXEL_BITS_c))));
        end loop;
        halfa(1) <= acc;
      end if;
      -- stage 1b: the column's weighted sum slides into the row of column sums
      if v(1) = '1' then
        x1     <= xa;
        y1     <= ya;
        inner1 <= innera;
        cols1  <= cols1(1 to 6) & (halfa(0) + halfa(1));
      end if;
      -- stage 2a: the weighted column sums in three parts (columns 0-2, 3-4, 5-6 and the rounding
      -- constant), each a balanced sum of at most five shifted terms
      if v(2) = '1' then
        xp       <= x1;
        yp       <= y1;
        innerp   <= inner1;
        parts(0) <= (weigh(0, cols1(0)) + weigh(1, cols1(1))) + weigh(2, cols1(2));
        parts(1) <= weigh(3, cols1(3)) + weigh(4, cols1(4));
        parts(2) <= (weigh(5, cols1(5)) + weigh(6, cols1(6))) + 2048;
      end if;
      -- stage 2b: their total
      if v(3) = '1' then
        x2     <= xp;
        y2     <= yp;
        inner2 <= innerp;
        total2 <= (parts(0) + parts(1)) + parts(2);
      end if;
      -- stage 3: divide by 4096
      if v(4) = '1' then
        x3 <= x2;
        y3 <= y2;
        if inner2 = '1' then
          out3 <= to_unsigned(total2 / 4096, PIXEL_BITS_c);
        else
          out3 <= (others => '0');
        end if;
      end if;
      if rst = '1' then
        v <= (others => '0');
      end if;
    end if;
  end process stages;

  out_valid <= v(SMOOTH_LAT_c);
  out_x     <= x3;
  out_y     <= y3;
  out_data  <= std_logic_vector(out3);

end architecture rtl;
