-- SPDX-License-Identifier: MIT
-- orb_util_pkg: shared constants and helpers of the ORB accelerator (coordinate width, log2,
-- pyramid level sizes, the selection's slot and reciprocal widths).

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
  constant SLOT_BITS_c : positive := 12;
  -- The cell size's reciprocal ceil(2^24 / cell): at most 2^20 for cells of 16 pixels or more.
  constant RECIP_BITS_c : positive := 21;

  -- '1' for true
  function bool2sl (b : boolean) return std_logic;

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

end package body orb_util_pkg;
