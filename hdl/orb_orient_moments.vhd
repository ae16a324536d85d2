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
-- u = -U - 1; then m10 = B and m01 = A. Modular two's-complement arithmetic, exact since
-- |m| < 2^21. The outputs for an input column are the moments of the patch whose rightmost
-- column it is (centre 15 inputs back, row 15 of the column); columns before the first count as
-- zero and nothing is cleared between lines or by rst. Nine pipeline stages (pair sums, weighted
-- differences, band sums into the delay lines, registered taps, band terms, two adder-tree
-- stages, C and A, B): fixed latency LATENCY_c = 9 clocks, input gaps allowed.

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;

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

  -- Latency in clocks from in_valid to out_valid (documentation; the stages below define it).
  constant LATENCY_c : positive := 9;
  constant RADIUS_c  : positive := 15;

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

  -- Bits of a value range: unsigned bits of max, signed bits of +-max.
  function ubits (max : natural) return positive is
  begin
    return maximum(1, clog2(max + 1));
  end function ubits;

  -- x * c for a constant c >= 0, as shifts and adds/subtracts of its canonical signed digits.
  function mul_const (x : signed; c : natural; width : positive) return signed is
    variable xs  : signed(width - 1 downto 0) := resize(x, width);
    variable acc : signed(width - 1 downto 0) := (others => '0');
    variable r   : natural                    := c;
  begin
    for i in 0 to 20 loop
      if r mod 2 = 1 then
        if r mod 4 = 3 then
          acc := acc - shift_left(xs, i);
          r   := r + 1;
        else
          acc := acc + shift_left(xs, i);
          r   := r - 1;
        end if;
      end if;
      r := r / 2;
    end loop;
    return acc;
  end function mul_const;

  -- Widths: per-row pair sums s_v = p(v) + p(-v) (s_0 = p(0)) and weighted differences
  -- w_v = v * (p(v) - p(-v)); the three per-band delta trees and the accumulators.
  constant S_BITS_c   : positive := PIXEL_BITS_c + 2;                       -- signed, <= 510
  constant DIF_BITS_c : positive := PIXEL_BITS_c + 1;                       -- signed, +-255
  constant W_BITS_c   : positive := ubits(255 * RADIUS_c) + 1;              -- signed, +-3825
  constant T_BITS_c   : positive := ubits(2 * (2 * RADIUS_c + 1) * 31 * 255) + 1;
  constant C_BITS_c   : positive := ubits(31 * 31 * 255) + 1;
  constant M_BITS_c   : positive := 24;

  type s_array_t is array (0 to RADIUS_c) of signed(S_BITS_c - 1 downto 0);
  type d_array_t is array (1 to RADIUS_c) of signed(DIF_BITS_c - 1 downto 0);
  type w_array_t is array (1 to RADIUS_c) of signed(W_BITS_c - 1 downto 0);
  type t_array_t is array (natural range <>) of signed(T_BITS_c - 1 downto 0);
  type tag_t is array (1 to LATENCY_c) of std_logic_vector(2 * COORD_BITS_c - 1 downto 0);

  constant GROUPS_c : positive := (BANDS_c + 3) / 4;

  -- Balanced sum of arr(base .. base + 3) (missing elements count as 0).
  function sum4 (arr : t_array_t; base : natural) return signed is
    variable t : t_array_t(0 to 3) := (others => (others => '0'));
  begin
    for i in 0 to 3 loop
      if base + i <= arr'high then
        t(i) := arr(base + i);
      end if;
    end loop;
    return (t(0) + t(1)) + (t(2) + t(3));
  end function sum4;

  signal valid : std_logic_vector(1 to LATENCY_c) := (others => '0');
  signal tags  : tag_t                            := (others => (others => '0'));

  -- stage 1: pair sums and differences; stage 2: weighted differences
  signal s1   : s_array_t := (others => (others => '0'));
  signal dif1 : d_array_t := (others => (others => '0'));
  signal s2   : s_array_t := (others => (others => '0'));
  signal w2   : w_array_t := (others => (others => '0'));

  -- stage 5: per-band terms; stage 6: groups of four; stage 7: deltas
  signal term_c5, term_a5, term_b5 : t_array_t(0 to BANDS_c - 1)  := (others => (others => '0'));
  signal part_c6, part_a6, part_b6 : t_array_t(0 to GROUPS_c - 1) := (others => (others => '0'));
  signal delta_c7                  : signed(T_BITS_c - 1 downto 0) := (others => '0');
  signal delta_a7                  : signed(T_BITS_c - 1 downto 0) := (others => '0');
  signal delta_b7                  : signed(T_BITS_c - 1 downto 0) := (others => '0');

  -- stages 8 and 9: the accumulators (C and A in 8, B in 9 from dB - C formed in 8)
  signal acc_c  : signed(C_BITS_c - 1 downto 0) := (others => '0');
  signal acc_a  : signed(M_BITS_c - 1 downto 0) := (others => '0');
  signal step_b : signed(M_BITS_c - 1 downto 0) := (others => '0');
  signal acc_b  : signed(M_BITS_c - 1 downto 0) := (others => '0');
  signal m01_9  : signed(M_BITS_c - 1 downto 0) := (others => '0');

begin

  assert BAND_U_c(0) = RADIUS_c and 2 * RADIUS_c + 1 = in_col'length / PIXEL_BITS_c
    report "orb_orient_moments: UMAX_c must start at the patch radius of the 31-pixel column"
    severity failure;

  -- valid bits and (x, y) tags: a plain delay line of LATENCY_c clocks. rst does not clear it: a
  -- column that has entered a delay line must also reach the sums, or they would stay wrong for
  -- good, so columns already inside complete (and come out) through a reset.
  control : process (clk) is
  begin
    if rising_edge(clk) then
      valid <= in_valid & valid(1 to LATENCY_c - 1);
      tags  <= std_logic_vector'(in_x & in_y) & tags(1 to LATENCY_c - 1);
    end if;
  end process control;

  rows : process (clk) is
    variable top, bottom : signed(S_BITS_c - 1 downto 0);
  begin
    if rising_edge(clk) then
      -- stage 1: row v = 15 - k is slice k; s_v = p(v) + p(-v), dif_v = p(v) - p(-v)
      if in_valid = '1' then
        s1(0) <= resize(signed('0' & in_col((RADIUS_c + 1) * PIXEL_BITS_c - 1 downto RADIUS_c * PIXEL_BITS_c)),
                        S_BITS_c);
        for v in 1 to RADIUS_c loop
          bottom := resize(signed('0' & in_col((RADIUS_c - v + 1) * PIXEL_BITS_c - 1 downto
                                               (RADIUS_c - v) * PIXEL_BITS_c)), S_BITS_c);
          top    := resize(signed('0' & in_col((RADIUS_c + v + 1) * PIXEL_BITS_c - 1 downto
                                               (RADIUS_c + v) * PIXEL_BITS_c)), S_BITS_c);
          s1(v)   <= bottom + top;
          dif1(v) <= resize(bottom - top, DIF_BITS_c);
        end loop;
      end if;
      -- stage 2: w_v = v * dif_v
      if valid(1) = '1' then
        s2 <= s1;
        for v in 1 to RADIUS_c loop
          w2(v) <= mul_const(dif1(v), v, W_BITS_c);
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

    constant U_c      : natural  := BAND_U_c(b);
    constant D_BITS_c : positive := ubits(255 * band_pixels) + 1;          -- signed, >= 0
    constant Q_BITS_c : positive := ubits(255 * band_vsum) + 1;            -- signed
    constant IN_c     : natural  := RADIUS_c - U_c;                        -- enters at u = +U
    constant OUT_c    : natural  := RADIUS_c + 1 + U_c;                    -- leaves from u = -U-1

    type line_t is array (0 to OUT_c) of std_logic_vector(D_BITS_c + Q_BITS_c - 1 downto 0);

    -- entry j: the band's (d, q) of the column that entered j inputs ago (0: the newest)
    signal dline : line_t := (others => (others => '0'));
    -- the entering and leaving entries, registered (an SRL output goes straight into a flip-flop)
    signal tap_in  : std_logic_vector(D_BITS_c + Q_BITS_c - 1 downto 0) := (others => '0');
    signal tap_out : std_logic_vector(D_BITS_c + Q_BITS_c - 1 downto 0) := (others => '0');

  begin

    band : process (clk) is
      variable d     : signed(D_BITS_c - 1 downto 0);
      variable q     : signed(Q_BITS_c - 1 downto 0);
      variable d_in  : signed(D_BITS_c - 1 downto 0);
      variable d_out : signed(D_BITS_c - 1 downto 0);
      variable q_in  : signed(Q_BITS_c - 1 downto 0);
      variable q_out : signed(Q_BITS_c - 1 downto 0);
    begin
      if rising_edge(clk) then
        -- stage 3: band sums, shifted into the delay line
        if valid(2) = '1' then
          d := (others => '0');
          q := (others => '0');
          for v in 0 to RADIUS_c loop
            if ROW_BAND_c(v) = b then
              d := d + resize(s2(v), D_BITS_c);
              if v > 0 then
                q := q + resize(w2(v), Q_BITS_c);
              end if;
            end if;
          end loop;
          dline <= std_logic_vector'(std_logic_vector(d) & std_logic_vector(q)) & dline(0 to OUT_c - 1);
        end if;
        -- stage 4: the entering (u = +U) and leaving (u = -U - 1) entries
        if valid(3) = '1' then
          tap_in  <= dline(IN_c);
          tap_out <= dline(OUT_c);
        end if;
        -- stage 5: this band's contribution to the three deltas
        if valid(4) = '1' then
          d_in  := signed(tap_in(D_BITS_c + Q_BITS_c - 1 downto Q_BITS_c));
          q_in  := signed(tap_in(Q_BITS_c - 1 downto 0));
          d_out := signed(tap_out(D_BITS_c + Q_BITS_c - 1 downto Q_BITS_c));
          q_out := signed(tap_out(Q_BITS_c - 1 downto 0));
          term_c5(b) <= resize(d_in, T_BITS_c) - resize(d_out, T_BITS_c);
          term_a5(b) <= resize(q_in, T_BITS_c) - resize(q_out, T_BITS_c);
          term_b5(b) <= mul_const(d_in, U_c, T_BITS_c) + mul_const(d_out, U_c + 1, T_BITS_c);
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
        acc_c  <= acc_c + resize(delta_c7, C_BITS_c);
        acc_a  <= acc_a + resize(delta_a7, M_BITS_c);
        step_b <= resize(delta_b7, M_BITS_c) - resize(acc_c, M_BITS_c);
      end if;
      -- stage 9: B accumulates
      if valid(8) = '1' then
        acc_b <= acc_b + step_b;
        m01_9 <= acc_a;
      end if;
    end if;
  end process sums;

  out_valid <= valid(LATENCY_c);
  out_x     <= tags(LATENCY_c)(2 * COORD_BITS_c - 1 downto COORD_BITS_c);
  out_y     <= tags(LATENCY_c)(COORD_BITS_c - 1 downto 0);
  out_m10   <= std_logic_vector(acc_b);
  out_m01   <= std_logic_vector(m01_9);

end architecture rtl;
