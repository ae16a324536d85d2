-- SPDX-License-Identifier: MIT
-- orb_orient_moments: intensity-centroid moments m10 = sum u p and m01 = sum v p of the circular
-- radius-15 patch (docs/spec.md section 8, golden_model.orientation), computed incrementally
-- from a stream of 31-pixel columns (slice k of in_col is the pixel k lines above the newest,
-- i.e. row v = 15 - k of the patch). The rows are grouped into bands of equal half-width U
-- (UMAX_c of |v|); per entering column each band's pixel sum d and first row moment q are formed
-- with constant shift-adds and pushed into a per-band delay line (a plain shift register, no
-- reset, so it maps to SRLs). Per band the patch is a sliding window of the 2U + 1 columns around
-- the column that entered 15 inputs earlier, so with C = sum d, B = sum u d, A = sum q over all
-- windows: C' = C + sum (d_in - d_out), A' = A + sum (q_in - q_out) and
-- B' = B - C + sum (U d_in + (U + 1) d_out), d_in entering at u = +U and d_out leaving from
-- u = -U - 1; then m10 = B and m01 = A. The arithmetic is on ranged integers (their ranges set
-- the hardware widths; GHDL simulates them natively): the sums always equal the moments of the
-- columns in the window, so |m| < 2^21 and no range is ever exceeded. The outputs for an input
-- column are the moments of the patch whose rightmost column it is (centre 15 inputs back, row 15
-- of the column); columns before the first count as zero and nothing is cleared between lines or
-- by rst. Nine pipeline stages (pair sums, weighted differences, band sums into the delay lines,
-- registered taps, band terms, two adder-tree stages, C and A, B): fixed latency
-- ORIENT_MOMENTS_LAT_c = 9 clocks (orb_latency_pkg, docs/latency.md; the valid flags and tags are
-- a delay line of that length), input gaps allowed.
-- Ports and generics: docs/entities/orb_orient_moments.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;

entity orb_orient_moments is
  port (
    clk       : in    std_logic;
    rst       : in    std_logic;
    in_valid  : in    std_logic;
    in_x      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_col    : in    std_logic_vector(31 * PIXEL_BITS_c - 1 downto 0);
    out_valid : out   std_logic;
    out_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_m10   : out   std_logic_vector(23 downto 0);
    out_m01   : out   std_logic_vector(23 downto 0)
  );
end entity orb_orient_moments;

architecture rtl of orb_orient_moments is

  constant RADIUS_c : positive := 15;

  type nat_array_t is array (natural range <>) of natural;

  -- Half-width of patch row |v| (golden_model.orientation.UMAX); by its transposition symmetry
  -- also the half-height of column |u|.
  constant UMAX_c : nat_array_t(0 to RADIUS_c) := (15, 15, 15, 15, 14, 14, 14, 13, 13, 12, 11, 10, 9, 8, 6, 3);

  -- Bands: rows of equal half-width, numbered in order of first appearance from v = 0.
  function first_row (um : nat_array_t; v : natural) return natural is
  begin
    for w in 0 to v loop
      if um(w) = um(v) then
        return w;
      end if;
    end loop;
    return v;
  end function first_row;

  function band_of (um : nat_array_t; v : natural) return natural is
    variable n : natural := 0;
  begin
    for w in 0 to v loop
      if first_row(um, w) = w and w < first_row(um, v) then
        n := n + 1;
      end if;
    end loop;
    return n;
  end function band_of;

  function count_bands (um : nat_array_t) return positive is
    variable n : natural := 0;
  begin
    for v in um'range loop
      if first_row(um, v) = v then
        n := n + 1;
      end if;
    end loop;
    return n;
  end function count_bands;

  constant BANDS_c : positive := count_bands(UMAX_c);

  function band_rows (um : nat_array_t) return nat_array_t is
    variable r : nat_array_t(0 to RADIUS_c);
  begin
    for v in um'range loop
      r(v) := band_of(um, v);
    end loop;
    return r;
  end function band_rows;

  constant ROW_BAND_c : nat_array_t(0 to RADIUS_c) := band_rows(UMAX_c);

  function band_halfwidths (um : nat_array_t) return nat_array_t is
    variable r : nat_array_t(0 to BANDS_c - 1);
  begin
    for v in um'range loop
      r(band_of(um, v)) := um(v);
    end loop;
    return r;
  end function band_halfwidths;

  constant BAND_U_c : nat_array_t(0 to BANDS_c - 1) := band_halfwidths(UMAX_c);

  -- Bits of a value range: unsigned bits of max.
  function ubits (max : natural) return positive is
  begin
    return maximum(1, clog2(max + 1));
  end function ubits;

  -- x * c for a constant c >= 0, as shifts and adds/subtracts of its canonical signed digits
  -- (multiplications by powers of two only: shifts in hardware, no DSP). Integer arithmetic: the
  -- pipeline works on ranged integers, whose widths follow from their ranges in synthesis and
  -- which GHDL simulates as native integers (numeric_std vectors cost it a loop per bit).
  function mul_const (x : integer; c : natural) return integer is
    variable acc : integer := 0;
    variable p   : integer := x;
    variable r   : natural := c;
  begin
    for i in 0 to 20 loop
      exit when r = 0;
      if r mod 2 = 1 then
        if r mod 4 = 3 then
          acc := acc - p;
          r   := r + 1;
        else
          acc := acc + p;
          r   := r - 1;
        end if;
      end if;
      r := r / 2;
      if r /= 0 then
        p := p * 2;
      end if;
    end loop;
    return acc;
  end function mul_const;

  -- Value ranges: per-row pair sums s_v = p(v) + p(-v) (s_0 = p(0)) and differences
  -- p(v) - p(-v), weighted differences w_v = v (p(v) - p(-v)); the per-band delta terms and the
  -- accumulators (24-bit outputs, |m| < 2^21).
  constant T_MAX_c : positive := 2 ** ubits(2 * (2 * RADIUS_c + 1) * 31 * 255);
  constant C_MAX_c : positive := 31 * 31 * 255;
  constant M_MAX_c : positive := 2 ** 23;

  subtype pix_t is integer range 0 to 255;
  subtype s_t is integer range 0 to 510;
  subtype dif_t is integer range -255 to 255;
  subtype w_t is integer range -255 * RADIUS_c to 255 * RADIUS_c;
  subtype term_t is integer range -T_MAX_c to T_MAX_c - 1;
  subtype acc_c_t is integer range 0 to C_MAX_c;
  subtype m_t is integer range -M_MAX_c to M_MAX_c - 1;

  type s_array_t is array (0 to RADIUS_c) of s_t;
  type d_array_t is array (1 to RADIUS_c) of dif_t;
  type w_array_t is array (1 to RADIUS_c) of w_t;
  type t_array_t is array (natural range <>) of term_t;
  type tag_t is array (1 to ORIENT_MOMENTS_LAT_c) of std_logic_vector(2 * COORD_BITS_c - 1 downto 0);

  constant GROUPS_c : positive := (BANDS_c + 3) / 4;

  -- Balanced sum of arr(base .. base + 3) (missing elements count as 0).
  function sum4 (arr : t_array_t; base : natural) return integer is
    variable t : t_array_t(0 to 3) := (others => 0);
  begin
    for i in 0 to 3 loop
      if base + i <= arr'high then
        t(i) := arr(base + i);
      end if;
    end loop;
    return (t(0) + t(1)) + (t(2) + t(3));
  end function sum4;

  function pixel (col : std_logic_vector; k : natural) return pix_t is
  begin
    return to_integer(unsigned(col(col'low + (k + 1) * PIXEL_BITS_c - 1 downto col'low + k * PIXEL_BITS_c)));
  end function pixel;

  signal valid : std_logic_vector(1 to ORIENT_MOMENTS_LAT_c) := (others => '0');
  signal tags  : tag_t                            := (others => (others => '0'));

  -- stage 1: pair sums and differences; stage 2: weighted differences
  signal s1   : s_array_t := (others => 0);
  signal dif1 : d_array_t := (others => 0);
  signal s2   : s_array_t := (others => 0);
  signal w2   : w_array_t := (others => 0);

  -- stage 5: per-band terms; stage 6: groups of four; stage 7: deltas
  signal term_c5, term_a5, term_b5 : t_array_t(0 to BANDS_c - 1)  := (others => 0);
  signal part_c6, part_a6, part_b6 : t_array_t(0 to GROUPS_c - 1) := (others => 0);
  signal delta_c7                  : term_t := 0;
  signal delta_a7                  : term_t := 0;
  signal delta_b7                  : term_t := 0;

  -- stages 8 and 9: the accumulators (C and A in 8, B in 9 from dB - C formed in 8)
  signal acc_c  : acc_c_t := 0;
  signal acc_a  : m_t     := 0;
  signal step_b : m_t     := 0;
  signal acc_b  : m_t     := 0;
  signal m01_9  : m_t     := 0;

begin

  assert BAND_U_c(0) = RADIUS_c and 2 * RADIUS_c + 1 = in_col'length / PIXEL_BITS_c
    report "orb_orient_moments: UMAX_c must start at the patch radius of the 31-pixel column"
    severity failure;

  -- valid bits and (x, y) tags: a plain delay line of ORIENT_MOMENTS_LAT_c clocks. rst does not
  -- clear it: a column that has entered a delay line must also reach the sums, or they would stay
  -- wrong for good, so columns already inside complete (and come out) through a reset.
  control : process (clk) is
  begin
    if rising_edge(clk) then
      valid <= in_valid & valid(1 to ORIENT_MOMENTS_LAT_c - 1);
      tags  <= std_logic_vector'(in_x & in_y) & tags(1 to ORIENT_MOMENTS_LAT_c - 1);
    end if;
  end process control;

  rows : process (clk) is
    variable top, bottom : pix_t;
  begin
    if rising_edge(clk) then
      -- stage 1: row v = 15 - k is slice k; s_v = p(v) + p(-v), dif_v = p(v) - p(-v)
      if in_valid = '1' then
        s1(0) <= pixel(in_col, RADIUS_c);
        for v in 1 to RADIUS_c loop
          bottom  := pixel(in_col, RADIUS_c - v);
          top     := pixel(in_col, RADIUS_c + v);
          s1(v)   <= bottom + top;
          dif1(v) <= bottom - top;
        end loop;
      end if;
      -- stage 2: w_v = v * dif_v
      if valid(1) = '1' then
        s2 <= s1;
        for v in 1 to RADIUS_c loop
          w2(v) <= mul_const(dif1(v), v);
        end loop;
      end if;
    end if;
  end process rows;

  gen_band : for b in 0 to BANDS_c - 1 generate

    function band_pixels return natural is
      variable n : natural := 0;
    begin
      for v in 0 to RADIUS_c loop
        if ROW_BAND_c(v) = b then
          if v = 0 then
            n := n + 1;
          else
            n := n + 2;
          end if;
        end if;
      end loop;
      return n;
    end function band_pixels;

    function band_vsum return natural is
      variable n : natural := 0;
    begin
      for v in 0 to RADIUS_c loop
        if ROW_BAND_c(v) = b then
          n := n + v;
        end if;
      end loop;
      return n;
    end function band_vsum;

    constant U_c     : natural := BAND_U_c(b);
    constant D_MAX_c : natural := 255 * band_pixels;
    constant Q_MAX_c : natural := 255 * band_vsum;
    constant IN_c    : natural := RADIUS_c - U_c;                        -- enters at u = +U
    constant OUT_c   : natural := RADIUS_c + 1 + U_c;                    -- leaves from u = -U-1

    subtype d_t is integer range 0 to D_MAX_c;
    subtype q_t is integer range -Q_MAX_c to Q_MAX_c;
    type    d_line_t is array (0 to OUT_c) of d_t;
    type    q_line_t is array (0 to OUT_c) of q_t;

    -- the entering and leaving entries, registered (an SRL output goes straight into a flip-flop)
    signal tap_in_d, tap_out_d : d_t := 0;
    signal tap_in_q, tap_out_q : q_t := 0;

  begin

    band : process (clk) is
      variable d : d_t;
      variable q : q_t;
      -- entry j: the band's d and q of the column that entered j inputs ago (0: the newest); a
      -- variable (SRLs in hardware, no reset) so the simulator moves it as one block
      variable d_line : d_line_t := (others => 0);
      variable q_line : q_line_t := (others => 0);
    begin
      if rising_edge(clk) then
        -- stage 5: this band's contribution to the three deltas
        if valid(4) = '1' then
          term_c5(b) <= tap_in_d - tap_out_d;
          term_a5(b) <= tap_in_q - tap_out_q;
          term_b5(b) <= mul_const(tap_in_d, U_c) + mul_const(tap_out_d, U_c + 1);
        end if;
        -- stage 4: the entering (u = +U) and leaving (u = -U - 1) entries, before this clock's shift
        if valid(3) = '1' then
          tap_in_d  <= d_line(IN_c);
          tap_in_q  <= q_line(IN_c);
          tap_out_d <= d_line(OUT_c);
          tap_out_q <= q_line(OUT_c);
        end if;
        -- stage 3: band sums, shifted into the delay line
        if valid(2) = '1' then
          d := 0;
          q := 0;
          for v in 0 to RADIUS_c loop
            if ROW_BAND_c(v) = b then
              d := d + s2(v);
              if v > 0 then
                q := q + w2(v);
              end if;
            end if;
          end loop;
          d_line := d & d_line(0 to OUT_c - 1);
          q_line := q & q_line(0 to OUT_c - 1);
        end if;
      end if;
    end process band;

  end generate gen_band;

  sums : process (clk) is
  begin
    if rising_edge(clk) then
      -- stage 6: groups of four bands
      if valid(5) = '1' then
        for g in 0 to GROUPS_c - 1 loop
          part_c6(g) <= sum4(term_c5, 4 * g);
          part_a6(g) <= sum4(term_a5, 4 * g);
          part_b6(g) <= sum4(term_b5, 4 * g);
        end loop;
      end if;
      -- stage 7: the deltas
      if valid(6) = '1' then
        delta_c7 <= sum4(part_c6, 0);
        delta_a7 <= sum4(part_a6, 0);
        delta_b7 <= sum4(part_b6, 0);
      end if;
      -- stage 8: C and A accumulate; B's step uses C before this column
      if valid(7) = '1' then
        acc_c  <= acc_c + delta_c7;
        acc_a  <= acc_a + delta_a7;
        step_b <= delta_b7 - acc_c;
      end if;
      -- stage 9: B accumulates
      if valid(8) = '1' then
        acc_b <= acc_b + step_b;
        m01_9 <= acc_a;
      end if;
    end if;
  end process sums;

  out_valid <= valid(ORIENT_MOMENTS_LAT_c);
  out_x     <= tags(ORIENT_MOMENTS_LAT_c)(2 * COORD_BITS_c - 1 downto COORD_BITS_c);
  out_y     <= tags(ORIENT_MOMENTS_LAT_c)(COORD_BITS_c - 1 downto 0);
  out_m10   <= std_logic_vector(to_signed(acc_b, 24));
  out_m01   <= std_logic_vector(to_signed(m01_9, 24));

end architecture rtl;
