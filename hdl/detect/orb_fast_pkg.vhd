-- SPDX-License-Identifier: MIT
-- orb_fast_pkg: the FAST-9 circle (docs/spec.md section 4), the segment-test helpers and the
-- corner response's width (section 15; golden_model.response, orb_harris). The latencies of
-- orb_fast_score and orb_harris are in orb_latency_pkg (docs/latency.md).

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

package orb_fast_pkg is

  type offset_t is record
    dx : integer range -3 to 3;
    dy : integer range -3 to 3;
  end record offset_t;

  type circle_t is array (0 to 15) of offset_t;

  -- Clockwise on screen (y grows downwards) from straight up; bit i of a mask is CIRCLE_c(i).
  constant CIRCLE_c : circle_t := (
    (0, -3), (1, -3), (2, -2), (3, -1), (3, 0), (3, 1), (2, 2), (1, 3),
    (0, 3), (-1, 3), (-2, 2), (-3, 1), (-3, 0), (-3, -1), (-2, -2), (-1, -3)
  );

  constant ARC_c : positive := 9;

  -- the corner response code (golden_model.response.RESPONSE_BITS; tb/detect/test_orb_harris.py
  -- checks the value)
  constant RESPONSE_BITS_c : positive := 6;

  -- True when the mask holds ARC_c cyclically contiguous ones.
  function has_arc (mask : std_logic_vector(15 downto 0)) return std_logic;

  -- 1 for '1', else 0
  function b2n (b : std_logic) return natural;

end package orb_fast_pkg;

package body orb_fast_pkg is

  function has_arc (mask : std_logic_vector(15 downto 0)) return std_logic is
    variable doubled : std_logic_vector(31 downto 0);
    variable run     : boolean;
    variable found   : boolean := false;
  begin
    -- booleans: the same AND-OR network, simulated without std_logic resolution tables
    doubled := mask & mask;
    for start in 0 to 15 loop
      run := true;
      for k in 0 to ARC_c - 1 loop
        run := run and doubled(start + k) = '1';
      end loop;
      found := found or run;
    end loop;
    if found then
      return '1';
    end if;
    return '0';
  end function has_arc;

  function b2n (b : std_logic) return natural is
  begin
    if b = '1' then
      return 1;
    end if;
    return 0;
  end function b2n;

end package body orb_fast_pkg;
