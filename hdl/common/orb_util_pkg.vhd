-- SPDX-License-Identifier: MIT
-- orb_util_pkg: shared constants and helpers of the ORB accelerator (coordinate width, log2,
-- pyramid level sizes, the selection's slot widths and cell map).

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

package orb_util_pkg is

  -- Coordinates are carried as 12-bit unsigned values (up to 4095, room above 1920x1080).
  constant COORD_BITS_c : positive := 12;
  -- FAST SAD score: 16 differences of at most 255.
  constant SCORE_BITS_c : positive := 12;
  constant PIXEL_BITS_c : positive := 8;
  -- A level's selection slot: 0 .. 4094 (a budget is at most 4095; slot 4095 means none).
  constant SEL_SLOT_BITS_c : positive := 12;
  -- The selection's grid: cells across (down) the frame, 1 .. 15 (SELECT.cols, SELECT.rows), and
  -- the cell map's fraction bits: a level coordinate v lies in cell (v K + O) >> CELL_SHIFT_c.
  constant GRID_BITS_c  : positive := 4;
  constant CELL_SHIFT_c : positive := 24;

  -- '1' for true
  function bool2sl (b : boolean) return std_logic;

  -- The budget split of docs/spec.md section 14 (golden_model.select): F_k = round(2^16 (num - den)
  -- den^k num^(L-1-k) / (num^L - den^L)) for k < L - 1 (the last level: 2^16 minus the others).
  function split_fraction (num, den, levels, k : natural) return natural;
  -- The most slots level k can be given by a budget of at most `cap`: min(cap, ((cap F_k) >> 16) +
  -- levels) (golden_model.select.level_slots), and the first slot of level k when the levels'
  -- slots are laid out one after the other (level_base(..., levels) is their total).
  function level_slots (cap, num, den, levels, k : natural) return natural;
  function level_base (cap, num, den, levels, k : natural) return natural;
  -- The cell map of one axis of level k (docs/spec.md section 14, golden_model.select.cell_axis):
  -- with a = num^k, b = den^k, K = min(ceil(2^24 cells a / (full b)), 2^24 - 1) and
  -- O = floor(2^23 cells (a - b) / (full b)), the cell of the full-resolution position
  -- (v + 0.5) a / b - 0.5 of `cells` cells over the frame's `full` pixels.
  function cell_k (cells, full, num, den, k : natural) return natural;
  function cell_o (cells, full, num, den, k : natural) return natural;

  function clog2 (n : positive) return natural;

  -- Size (width or height) of pyramid level k of a SIZE-pixel frame for the step NUM:DEN: each
  -- level is floor(size * DEN / NUM) of the one before (docs/spec.md section 3; the model's
  -- golden_model.config.level_size).
  function level_size (size, num, den, k : natural) return natural;

  -- Pixel (r, c) of a flat WIN x WIN window of 8-bit pixels (orb_window's layout: element
  -- r * WIN + c, r = 0 the top line, c = 0 the leftmost column).
  function window_pixel (win : std_logic_vector; width, r, c : natural) return unsigned;

end package orb_util_pkg;

package body orb_util_pkg is

  function bool2sl (b : boolean) return std_logic is
  begin
    if b then
      return '1';
    end if;
    return '0';
  end function bool2sl;

  function clog2 (n : positive) return natural is
    variable bits : natural := 0;
    variable cap  : natural := 1;
  begin
    while cap < n loop
      bits := bits + 1;
      cap  := cap * 2;
    end loop;
    return bits;
  end function clog2;

  function level_size (size, num, den, k : natural) return natural is
    variable v : natural := size;
  begin
    for i in 1 to k loop
      v := v * den / num;
    end loop;
    return v;
  end function level_size;

  function window_pixel (win : std_logic_vector; width, r, c : natural) return unsigned is
    constant K_c : natural := r * width + c;
  begin
    return unsigned(win((K_c + 1) * PIXEL_BITS_c - 1 downto K_c * PIXEL_BITS_c));
  end function window_pixel;

  function split_fraction (num, den, levels, k : natural) return natural is
    variable a, d, acc : unsigned(95 downto 0);
    variable sum       : natural := 0;
  begin
    if k = levels - 1 then
      for j in 0 to levels - 2 loop
        sum := sum + split_fraction(num, den, levels, j);
      end loop;
      return 2 ** 16 - sum;
    end if;
    a := to_unsigned(num - den, 96);
    for j in 1 to k loop
      a := resize(a * to_unsigned(den, 8), 96);
    end loop;
    for j in 1 to levels - 1 - k loop
      a := resize(a * to_unsigned(num, 8), 96);
    end loop;
    d   := to_unsigned(1, 96);
    acc := to_unsigned(1, 96);
    for j in 1 to levels loop
      d   := resize(d * to_unsigned(num, 8), 96);
      acc := resize(acc * to_unsigned(den, 8), 96);
    end loop;
    d := d - acc;
    return to_integer((shift_left(a, 17) + d) / shift_left(d, 1));
  end function split_fraction;

  function level_slots (cap, num, den, levels, k : natural) return natural is
    variable s : natural;
  begin
    s := (cap * split_fraction(num, den, levels, k)) / 2 ** 16 + levels;
    if s > cap then
      return cap;
    end if;
    return s;
  end function level_slots;

  function level_base (cap, num, den, levels, k : natural) return natural is
    variable b : natural := 0;
  begin
    for j in 0 to k - 1 loop
      b := b + level_slots(cap, num, den, levels, j);
    end loop;
    return b;
  end function level_base;

  function cell_k (cells, full, num, den, k : natural) return natural is
    variable a, b, q : unsigned(95 downto 0);
  begin
    a := to_unsigned(cells, 96);
    b := to_unsigned(full, 96);
    for j in 1 to k loop
      a := resize(a * to_unsigned(num, 8), 96);
      b := resize(b * to_unsigned(den, 8), 96);
    end loop;
    q := (shift_left(a, CELL_SHIFT_c) + b - 1) / b;
    if q > 2 ** CELL_SHIFT_c - 1 then
      return 2 ** CELL_SHIFT_c - 1;
    end if;
    return to_integer(q);
  end function cell_k;

  function cell_o (cells, full, num, den, k : natural) return natural is
    variable a, b, d : unsigned(95 downto 0);
  begin
    a := to_unsigned(1, 96);
    d := to_unsigned(1, 96);
    for j in 1 to k loop
      a := resize(a * to_unsigned(num, 8), 96);
      d := resize(d * to_unsigned(den, 8), 96);
    end loop;
    -- cells (a - b) << 23 / (full b)
    b := resize(to_unsigned(full, 16) * d, 96);
    a := resize((a - d) * to_unsigned(cells, 8), 96);
    return to_integer(shift_left(a, CELL_SHIFT_c - 1) / b);
  end function cell_o;

end package body orb_util_pkg;
