-- SPDX-License-Identifier: MIT
-- orb_harris: the corner response code of docs/spec.md section 15 (golden_model.response) for
-- every position of a 7x7 window stream from orb_window, beside orb_fast_score. The window's
-- newest pixel is at (in_x, in_y), so the centre is (in_x - 3, in_y - 3); the code is 0 unless the
-- centre is at least 3 pixels from the left and top borders (the right and bottom ones are implied).
-- Incremental, the thesis's column-sum idea: each window brings one new gradient column, the
-- window's column 5 (its columns 4 to 6 give the Sobel derivatives of rows 1 to 5); the products
-- Ix^2, Ix Iy and Iy^2 of each row are 8 x 8 signed products into 16 bits, one DSP48 each (GHDL's
-- Verilog widens a signed product's operands to the result's width, so a wider result would
-- become a cascade of several DSP48s); each column's three sums slide through a
-- four-deep delay line that advances with every window, and the 5x5 block sums are the newest
-- column plus the four before it (consecutive windows of one line are consecutive columns; the
-- first positions of a line, whose block still holds the previous line's columns, are masked by
-- the border rule). Then a, b, c (>> 3), the three products of R (a b, |c|^2, (a + b)^2: unsigned;
-- a, b and |c| are at most 51200) and the floating-point code.
-- Pipeline: 17 stages, every one registered; latency HARRIS_LAT_c = 17 clocks (orb_latency_pkg,
-- docs/latency.md; the valid flags and tags are a delay line of that length), whatever the input
-- gaps; the output keeps the input's (x, y) tag. Page: docs/rtl-detection.md.
-- Ports and generics: docs/entities/orb_harris.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_fast_pkg.all;

entity orb_harris is
  port (
    clk       : in    std_logic;
    rst       : in    std_logic;
    in_valid  : in    std_logic;
    in_x      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_win    : in    std_logic_vector(49 * PIXEL_BITS_c - 1 downto 0);
    out_valid : out   std_logic;
    out_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_code  : out   std_logic_vector(RESPONSE_BITS_c - 1 downto 0)
  );
end entity orb_harris;

architecture rtl of orb_harris is

  constant L_c : positive := HARRIS_LAT_c;

  subtype pix_t is unsigned(7 downto 0);
  subtype diff_t is signed(8 downto 0);      -- a pixel difference
  subtype grad_t is signed(7 downto 0);      -- Ix, Iy: -128 .. 127
  subtype prod_t is signed(15 downto 0);     -- Ix^2, Ix Iy, Iy^2: |.| <= 16384
  subtype sq_t is unsigned(14 downto 0);     -- Ix^2, Iy^2 <= 16384
  subtype xy_t is signed(15 downto 0);       -- Ix Iy: |.| <= 16384
  subtype col_t is unsigned(17 downto 0);    -- a column's sum of squares <= 81920
  subtype colxy_t is signed(17 downto 0);
  subtype blk_t is unsigned(19 downto 0);    -- a block's sum of squares <= 409600
  subtype blkxy_t is signed(19 downto 0);
  subtype ab_t is unsigned(16 downto 0);     -- a, b, |c| <= 51200; a + b <= 102400
  subtype r_t is signed(35 downto 0);

  type pix_col_t is array (0 to 6) of pix_t;
  type pix_win_t is array (4 to 6) of pix_col_t;  -- window columns 4..6, rows 0..6
  type diff_arr_t is array (0 to 6) of diff_t;
  type vdiff_arr_t is array (1 to 5) of diff_t;
  type fdiff_t is array (4 to 6) of vdiff_arr_t;  -- vertical differences of columns 4..6 (rows 1..5)
  type grad_arr_t is array (1 to 5) of grad_t;
  type prod_arr_t is array (1 to 5) of prod_t;
  type sq_arr_t is array (1 to 5) of sq_t;
  type xy_arr_t is array (1 to 5) of xy_t;
  type col_dly_t is array (1 to 4) of col_t;
  type colxy_dly_t is array (1 to 4) of colxy_t;

  type coord_arr_t is array (0 to L_c - 1) of std_logic_vector(COORD_BITS_c - 1 downto 0);

  -- the valid flag, the tags and the border flag beside the stages
  signal v     : std_logic_vector(0 to L_c - 1) := (others => '0');
  signal tx    : coord_arr_t := (others => (others => '0'));
  signal ty    : coord_arr_t := (others => (others => '0'));
  signal inner : std_logic_vector(0 to L_c - 1) := (others => '0');

  -- stage 0: the 21 pixels
  signal p0 : pix_win_t := (others => (others => (others => '0')));
  -- stage 1: differences
  signal dx1 : diff_arr_t := (others => (others => '0'));   -- P(6, r) - P(4, r)
  signal dy1 : fdiff_t := (others => (others => (others => '0')));  -- P(c, r+1) - P(c, r-1)
  -- stage 2: gradients of the new column
  signal ix2,  iy2 : grad_arr_t := (others => (others => '0'));
  -- stage 3: multiplier operands
  signal ix3,  iy3 : grad_arr_t := (others => (others => '0'));
  -- stages 4, 5: products (DSP48 M and P registers)
  signal pxx4, pxx5 : prod_arr_t := (others => (others => '0'));
  signal pxy4, pxy5 : prod_arr_t := (others => (others => '0'));
  signal pyy4, pyy5 : prod_arr_t := (others => (others => '0'));
  -- stage 6: the column's products unpacked, stage 7: the column's sums
  signal sxx6, syy6 : sq_arr_t := (others => (others => '0'));
  signal sxy6       : xy_arr_t := (others => (others => '0'));
  signal cxx7, cyy7 : col_t := (others => '0');
  signal cxy7       : colxy_t := (others => '0');
  -- the four columns before, and the block sums (stages 8, 9)
  signal dxx,  dyy  : col_dly_t := (others => (others => '0'));
  signal dxy        : colxy_dly_t := (others => (others => '0'));
  signal hxx8, hyy8 : blk_t := (others => '0');  -- newest three columns
  signal hxy8       : blkxy_t := (others => '0');
  signal lxx8, lyy8 : blk_t := (others => '0');  -- the two before
  signal lxy8       : blkxy_t := (others => '0');
  signal a9,   b9   : ab_t := (others => '0');
  signal c9         : signed(17 downto 0) := (others => '0');
  -- stage 10: operands, stages 11, 12: products
  signal a10, b10, s10 : ab_t := (others => '0');
  signal c10           : ab_t := (others => '0');  -- |c|
  signal ab11, ab12    : unsigned(33 downto 0) := (others => '0');
  signal cc11, cc12    : unsigned(33 downto 0) := (others => '0');
  signal ss11, ss12    : unsigned(33 downto 0) := (others => '0');
  -- stages 13, 14: R
  signal t13 : r_t := (others => '0');
  signal q13 : r_t := (others => '0');
  signal r14 : r_t := (others => '0');
  -- stages 15, 16: the code
  signal hi15   : std_logic_vector(3 downto 0) := (others => '0');  -- bytes of R holding a one
  signal r15    : unsigned(31 downto 0) := (others => '0');
  signal pos15  : std_logic := '0';  -- R >= 2
  signal code16 : unsigned(RESPONSE_BITS_c - 1 downto 0) := (others => '0');

  -- the leading one of a byte (0..7) and the bit after it (0 when the leading one is bit 0)
  procedure lead (
    b          : unsigned(7 downto 0);
    variable e : out natural;
    variable m : out std_logic
  ) is
  begin
    e := 0;
    m := '0';
    for i in 1 to 7 loop
      if b(i) = '1' then
        e := i;
        m := b(i - 1);
      end if;
    end loop;
  end procedure lead;

begin

  stages : process (clk) is
    variable sx, sy : signed(10 downto 0);
    variable s3     : unsigned(16 downto 0);
    variable s3xy   : signed(16 downto 0);
    variable e      : natural;
    variable m      : std_logic;
    variable byte   : natural;
    variable nxt    : std_logic;
  begin
    if rising_edge(clk) then
      -- tags and the border flag travel beside the data
      v(0)     <= in_valid;
      v(1 to L_c - 1) <= v(0 to L_c - 2);
      if in_valid = '1' then
        tx(0)    <= in_x;
        ty(0)    <= in_y;
        inner(0) <= '1' when unsigned(in_x) >= 6 and unsigned(in_y) >= 6 else '0';
        for c in 4 to 6 loop
          for r in 0 to 6 loop
            p0(c)(r) <= window_pixel(in_win, 7, r, c);
          end loop;
        end loop;
      end if;
      for k in 1 to L_c - 1 loop
        if v(k - 1) = '1' then
          tx(k)    <= tx(k - 1);
          ty(k)    <= ty(k - 1);
          inner(k) <= inner(k - 1);
        end if;
      end loop;

      -- stage 1: horizontal differences of every row, vertical ones of rows 1..5
      if v(0) = '1' then
        for r in 0 to 6 loop
          dx1(r) <= signed(resize(p0(6)(r), 9)) - signed(resize(p0(4)(r), 9));
        end loop;
        for c in 4 to 6 loop
          for r in 1 to 5 loop
            dy1(c)(r) <= signed(resize(p0(c)(r + 1), 9)) - signed(resize(p0(c)(r - 1), 9));
          end loop;
        end loop;
      end if;

      -- stage 2: Ix = (2 dx(r) + dx(r - 1) + dx(r + 1)) >> 3, Iy likewise from the columns
      if v(1) = '1' then
        for r in 1 to 5 loop
          sx      := shift_left(resize(dx1(r), 11), 1) + resize(dx1(r - 1), 11) + resize(dx1(r + 1), 11);
          sy      := shift_left(resize(dy1(5)(r), 11), 1) + resize(dy1(4)(r), 11) + resize(dy1(6)(r), 11);
          ix2(r) <= resize(shift_right(sx, 3), 8);
          iy2(r) <= resize(shift_right(sy, 3), 8);
        end loop;
      end if;

      -- stage 3: the operands registered (the DSP48's A and B registers)
      if v(2) = '1' then
        ix3 <= ix2;
        iy3 <= iy2;
      end if;

      -- stages 4, 5: Ix^2, Ix Iy, Iy^2, registered twice; each an 8 x 8 signed product into 16 bits
      -- (GHDL's Verilog widens a signed product's operands to the result's width: 16 bits keep it in
      -- one DSP48, where a wider result makes a cascade of several)
      if v(3) = '1' then
        for r in 1 to 5 loop
          pxx4(r) <= ix3(r) * ix3(r);
          pxy4(r) <= ix3(r) * iy3(r);
          pyy4(r) <= iy3(r) * iy3(r);
        end loop;
      end if;
      if v(4) = '1' then
        pxx5 <= pxx4;
        pxy5 <= pxy4;
        pyy5 <= pyy4;
      end if;

      -- stage 6: the products as the column sums take them (squares <= 16384: 15 bits); a plain
      -- register stage now, kept so that HARRIS_LAT_c and its users stay as they are
      if v(5) = '1' then
        for r in 1 to 5 loop
          sxx6(r) <= unsigned(pxx5(r)(14 downto 0));
          sxy6(r) <= pxy5(r);
          syy6(r) <= unsigned(pyy5(r)(14 downto 0));
        end loop;
      end if;

      -- stage 7: the column's sums of the five rows
      if v(6) = '1' then
        cxx7 <= resize(sxx6(1), 18) + sxx6(2) + sxx6(3) + sxx6(4) + sxx6(5);
        cyy7 <= resize(syy6(1), 18) + syy6(2) + syy6(3) + syy6(4) + syy6(5);
        cxy7 <= resize(sxy6(1), 18) + sxy6(2) + sxy6(3) + sxy6(4) + sxy6(5);
      end if;

      -- stage 8: the newest three columns and the two before (the delay line advances with every
      -- column); stage 9: the block sums and a, b, c = sums >> 3
      if v(7) = '1' then
        hxx8   <= resize(cxx7, 20) + dxx(1) + dxx(2);
        hyy8   <= resize(cyy7, 20) + dyy(1) + dyy(2);
        hxy8   <= resize(cxy7, 20) + dxy(1) + dxy(2);
        lxx8   <= resize(dxx(3), 20) + dxx(4);
        lyy8   <= resize(dyy(3), 20) + dyy(4);
        lxy8   <= resize(dxy(3), 20) + dxy(4);
        dxx    <= cxx7 & dxx(1 to 3);
        dyy    <= cyy7 & dyy(1 to 3);
        dxy    <= cxy7 & dxy(1 to 3);
      end if;
      if v(8) = '1' then
        s3   := resize(shift_right(hxx8 + lxx8, 3), 17);
        a9   <= s3;
        s3   := resize(shift_right(hyy8 + lyy8, 3), 17);
        b9   <= s3;
        s3xy := resize(shift_right(hxy8 + lxy8, 3), 17);
        c9   <= resize(s3xy, 18);
      end if;

      -- stage 10: the operands of R's three products
      if v(9) = '1' then
        a10 <= a9;
        b10 <= b9;
        c10 <= resize(unsigned(abs (c9)), 17);
        s10 <= a9 + b9;
      end if;

      -- stages 11, 12: a b, |c|^2, (a + b)^2, registered twice
      if v(10) = '1' then
        ab11 <= a10 * b10;
        cc11 <= c10 * c10;
        ss11 <= s10 * s10;
      end if;
      if v(11) = '1' then
        ab12 <= ab11;
        cc12 <= cc11;
        ss12 <= ss11;
      end if;

      -- stages 13, 14: R = a b - c^2 - ((a + b)^2 >> 5)
      if v(12) = '1' then
        t13 <= signed(resize(ab12, 36)) - signed(resize(cc12, 36));
        q13 <= signed(resize(shift_right(ss12, 5), 36));
      end if;
      if v(13) = '1' then
        r14 <= t13 - q13;
      end if;

      -- stages 15, 16: the code 2 e + m of R >= 2 (e its leading one, m the bit after), else 0
      if v(14) = '1' then
        pos15 <= '1' when r14 >= 2 else '0';
        r15   <= unsigned(r14(31 downto 0));
        for k in 0 to 3 loop
          hi15(k) <= '1' when r14(8 * k + 7 downto 8 * k) /= 0 else '0';
        end loop;
      end if;
      if v(15) = '1' then
        byte := 0;
        for k in 1 to 3 loop
          if hi15(k) = '1' then
            byte := k;
          end if;
        end loop;
        lead(r15(8 * byte + 7 downto 8 * byte), e, m);
        nxt := m;
        if e = 0 and byte > 0 then  -- the leading one is a byte's bit 0: the next bit is below it
          nxt := r15(8 * byte - 1);
        end if;
        if pos15 = '1' and inner(15) = '1' then
          code16 <= to_unsigned(2 * (8 * byte + e) + b2n(nxt), RESPONSE_BITS_c);
        else
          code16 <= (others => '0');
        end if;
      end if;

      if rst = '1' then
        v <= (others => '0');
      end if;
    end if;
  end process stages;

  out_valid <= v(L_c - 1);
  out_x     <= tx(L_c - 1);
  out_y     <= ty(L_c - 1);
  out_code  <= std_logic_vector(code16);

end architecture rtl;
