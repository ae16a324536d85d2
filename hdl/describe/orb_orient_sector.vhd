-- SPDX-License-Identifier: MIT
-- orb_orient_sector: quantises the intensity-centroid moments (m10, m01) into one of
-- SECTORS_g orientation sectors (the total; N_c = SECTORS_g / 4 per quadrant) exactly as
-- golden_model.orientation.quantise (docs/spec.md section 9): the quadrant q and the magnitudes
-- (a, b) along its two axes come from the signs, then the local sector j counts the boundaries
-- beta_k = (k - 1/2) * 90 / N_c degrees the angle has reached, each tested without division as
-- b * 2^16 >= a * TAN_k (beta_k < 45) or b * COT_k >= a * 2^16 (beta_k > 45), one constant
-- multiplication per boundary (a DSP48 or LUT adders). The 16-bit constants are computed at
-- elaboration with ieee.math_real, rounded half up like the model. sector = (q * N_c + j) mod
-- SECTORS_g, and 0 when m10 = m01 = 0.
-- Five pipeline stages (signs and magnitudes, products, products again, comparisons, count): the
-- product is registered twice so that it can use both the DSP48's M and P registers and the
-- comparison starts from a short clock-to-output (docs/synthesis.md, "Timing"). Fixed latency
-- ORIENT_SECTOR_LAT_c = 5 clocks (orb_latency_pkg, docs/latency.md; the valid flags and tags are a
-- delay line of that length), input gaps allowed; (x, y) tags pass through unchanged.
-- Ports and generics: docs/entities/orb_orient_sector.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;
use ieee.math_real.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_limits_pkg.all;

entity orb_orient_sector is
  generic (
    SECTORS_g : sectors_t := 32  -- orientation sectors in all (orb_limits_pkg: 16, 32 or 64)
  );
  port (
    clk        : in    std_logic;
    rst        : in    std_logic;
    in_valid   : in    std_logic;
    in_x       : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y       : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_m10     : in    std_logic_vector(23 downto 0);
    in_m01     : in    std_logic_vector(23 downto 0);
    out_valid  : out   std_logic;
    out_x      : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_y      : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_sector : out   std_logic_vector(5 downto 0)
  );
end entity orb_orient_sector;

architecture rtl of orb_orient_sector is

  -- The sectors per quadrant (the thesis's N).
  constant N_c        : positive := SECTORS_g / 4;
  constant TAN_BITS_c : positive := 16;
  constant MAG_BITS_c : positive := 24;                        -- |m| of any 24-bit input
  constant K_BITS_c   : positive := TAN_BITS_c + 1;             -- constants < 2^16, signed
  constant P_BITS_c   : positive := MAG_BITS_c + TAN_BITS_c;    -- products < 2^40

  type const_array_t is array (1 to N_c) of natural;
  type prod_array_t is array (1 to N_c) of unsigned(P_BITS_c - 1 downto 0);
  type tag_t is array (1 to ORIENT_SECTOR_LAT_c) of std_logic_vector(2 * COORD_BITS_c - 1 downto 0);

  -- Boundary k uses the cotangent form when beta_k > 45 degrees.
  function uses_cot (k : positive) return boolean is
  begin
    return (real(k) - 0.5) * 90.0 / real(N_c) > 45.0;
  end function uses_cot;

  -- tan(x) for 0 <= x < pi/4 from Taylor series of sin and cos (relative error far below 1e-12;
  -- ghdl synth cannot evaluate math_real's tan, only real arithmetic).
  function tangent (x : real) return real is
    variable term_s : real := x;
    variable term_c : real := 1.0;
    variable s      : real := 0.0;
    variable c      : real := 0.0;
  begin
    for i in 1 to 14 loop
      s      := s + term_s;
      c      := c + term_c;
      term_s := -term_s * x * x / real((2 * i) * (2 * i + 1));
      term_c := -term_c * x * x / real((2 * i - 1) * (2 * i));
    end loop;
    return s / c;
  end function tangent;

  -- round(tan(beta_k) * 2^16), or round(tan(90 - beta_k) * 2^16) for the cotangent form; every
  -- product lies at least 0.07 away from a rounding tie, so the series is exact enough
  function tangent_constants return const_array_t is
    variable r    : const_array_t;
    variable beta : real;
  begin
    for k in 1 to N_c loop
      beta := (real(k) - 0.5) * 90.0 / real(N_c);
      if uses_cot(k) then
        beta := 90.0 - beta;
      end if;
      r(k) := natural(floor(tangent(beta * (MATH_PI / 180.0)) * 2.0 ** TAN_BITS_c + 0.5));
    end loop;
    return r;
  end function tangent_constants;

  constant CONST_c : const_array_t := tangent_constants;

  -- Number of ones, as a balanced tree of small adders.
  function popcount (bits : std_logic_vector) return unsigned is
    type     count_array_t is array (0 to 15) of unsigned(5 downto 0);
    variable c : count_array_t := (others => (others => '0'));
  begin
    for i in 0 to bits'length - 1 loop
      c(i) := "00000" & bits(bits'low + i);
    end loop;
    for level in 0 to 3 loop
      for i in 0 to 7 loop
        c(i) := c(2 * i) + c(2 * i + 1);
      end loop;
      c(8 to 15) := (others => (others => '0'));
    end loop;
    return c(0);
  end function popcount;

  signal valid : std_logic_vector(1 to ORIENT_SECTOR_LAT_c) := (others => '0');
  signal tags  : tag_t                            := (others => (others => '0'));

  -- stage 1: quadrant and magnitudes
  signal quad1 : unsigned(1 downto 0)              := (others => '0');
  signal a1    : unsigned(MAG_BITS_c - 1 downto 0) := (others => '0');
  signal b1    : unsigned(MAG_BITS_c - 1 downto 0) := (others => '0');
  signal zero1 : std_logic                         := '0';
  -- stage 2: one product per boundary, and the other side (a or b, times 2^16 by wiring)
  signal quad2 : unsigned(1 downto 0)              := (others => '0');
  signal a2    : unsigned(MAG_BITS_c - 1 downto 0) := (others => '0');
  signal b2    : unsigned(MAG_BITS_c - 1 downto 0) := (others => '0');
  signal zero2 : std_logic                         := '0';
  signal prod2 : prod_array_t                      := (others => (others => '0'));
  -- stage 3: the products again (the DSP48's P register) and their other sides
  signal quad3 : unsigned(1 downto 0)              := (others => '0');
  signal a3    : unsigned(MAG_BITS_c - 1 downto 0) := (others => '0');
  signal b3    : unsigned(MAG_BITS_c - 1 downto 0) := (others => '0');
  signal zero3 : std_logic                         := '0';
  signal prod3 : prod_array_t                      := (others => (others => '0'));
  -- stage 4: boundaries reached
  signal quad4    : unsigned(1 downto 0)                := (others => '0');
  signal zero4    : std_logic                           := '0';
  signal reached4 : std_logic_vector(1 to N_c)          := (others => '0');
  -- stage 5: sector
  signal sector5 : unsigned(5 downto 0)                := (others => '0');

begin

  assert sectors_legal(SECTORS_g)
    report "orb_orient_sector: SECTORS_g (sectors in all) must be " & SECTORS_TEXT_c
    severity failure;

  control : process (clk) is
  begin
    if rising_edge(clk) then
      valid <= in_valid & valid(1 to ORIENT_SECTOR_LAT_c - 1);
      tags  <= std_logic_vector'(in_x & in_y) & tags(1 to ORIENT_SECTOR_LAT_c - 1);
      if rst = '1' then
        valid <= (others => '0');
      end if;
    end if;
  end process control;

  stages : process (clk) is
    variable m10, m01 : signed(MAG_BITS_c downto 0);
    variable neg_m10  : signed(MAG_BITS_c downto 0);
    variable neg_m01  : signed(MAG_BITS_c downto 0);
    variable j        : unsigned(5 downto 0);
    variable prod_hi  : unsigned(MAG_BITS_c - 1 downto 0);
  begin
    if rising_edge(clk) then
      -- stage 1: q=0: m10 > 0, m01 >= 0 (a, b) = (m10, m01); q=1: m10 <= 0, m01 > 0 (m01, -m10);
      -- q=2: m10 < 0, m01 <= 0 (-m10, -m01); q=3: m10 >= 0, m01 < 0 (-m01, m10)
      if in_valid = '1' then
        m10   := resize(signed(in_m10), MAG_BITS_c + 1);
        m01   := resize(signed(in_m01), MAG_BITS_c + 1);
        neg_m10 := -m10;
        neg_m01 := -m01;
        zero1   <= '1' when m10 = 0 and m01 = 0 else '0';
        if m10 > 0 and m01 >= 0 then
          quad1 <= "00";
          a1    <= unsigned(m10(MAG_BITS_c - 1 downto 0));
          b1    <= unsigned(m01(MAG_BITS_c - 1 downto 0));
        elsif m10 <= 0 and m01 > 0 then
          quad1 <= "01";
          a1    <= unsigned(m01(MAG_BITS_c - 1 downto 0));
          b1    <= unsigned(neg_m10(MAG_BITS_c - 1 downto 0));
        elsif m10 < 0 and m01 <= 0 then
          quad1 <= "10";
          a1    <= unsigned(neg_m10(MAG_BITS_c - 1 downto 0));
          b1    <= unsigned(neg_m01(MAG_BITS_c - 1 downto 0));
        else
          quad1 <= "11";
          a1    <= unsigned(neg_m01(MAG_BITS_c - 1 downto 0));
          b1    <= unsigned(m10(MAG_BITS_c - 1 downto 0));
        end if;
      end if;
      -- stage 2: the constant products
      if valid(1) = '1' then
        quad2 <= quad1;
        zero2 <= zero1;
        a2    <= a1;
        b2    <= b1;
        for k in 1 to N_c loop
          if uses_cot(k) then
            prod2(k) <= resize(b1 * to_unsigned(CONST_c(k), K_BITS_c), P_BITS_c);
          else
            prod2(k) <= resize(a1 * to_unsigned(CONST_c(k), K_BITS_c), P_BITS_c);
          end if;
        end loop;
      end if;
      -- stage 3: the products pass the DSP48's output register
      if valid(2) = '1' then
        quad3 <= quad2;
        zero3 <= zero2;
        a3    <= a2;
        b3    <= b2;
        prod3 <= prod2;
      end if;
      -- stage 4: b * 2^16 >= a * TAN_k, or b * COT_k >= a * 2^16. As the 2^16 side has 16 zero
      -- low bits, only the product's high part P_h = P / 2^16 is compared at full width:
      -- b * 2^16 >= P <=> b > P_h or (b = P_h and P mod 2^16 = 0); P >= a * 2^16 <=> P_h >= a.
      if valid(3) = '1' then
        quad4 <= quad3;
        zero4 <= zero3;
        for k in 1 to N_c loop
          prod_hi := prod3(k)(P_BITS_c - 1 downto TAN_BITS_c);
          if uses_cot(k) then
            reached4(k) <= '1' when prod_hi >= a3 else '0';
          elsif b3 > prod_hi or (b3 = prod_hi and prod3(k)(TAN_BITS_c - 1 downto 0) = 0) then
            reached4(k) <= '1';
          else
            reached4(k) <= '0';
          end if;
        end loop;
      end if;
      -- stage 5: j = boundaries reached; sector = (q * N + j) mod 4N
      if valid(4) = '1' then
        j := popcount(reached4) + resize(quad4 * to_unsigned(N_c, 5), 6);
        if zero4 = '1' then
          sector5 <= (others => '0');
        else
          sector5 <= j and to_unsigned(SECTORS_g - 1, 6);
        end if;
      end if;
    end if;
  end process stages;

  out_valid  <= valid(ORIENT_SECTOR_LAT_c);
  out_x      <= tags(ORIENT_SECTOR_LAT_c)(2 * COORD_BITS_c - 1 downto COORD_BITS_c);
  out_y      <= tags(ORIENT_SECTOR_LAT_c)(COORD_BITS_c - 1 downto 0);
  out_sector <= std_logic_vector(sector5);

end architecture rtl;
