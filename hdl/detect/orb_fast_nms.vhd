-- SPDX-License-Identifier: MIT
-- orb_fast_nms: 3x3 non-maximum suppression of the FAST score stream (docs/spec.md section 5)
-- with the raster-order tie rule (strict '>' against the four earlier neighbours, '>=' against
-- the four later ones), on the combined map S' = score + 4096 for a corner at the main threshold
-- (in_main), the score otherwise: a low corner never suppresses a main one. The input is
-- orb_fast_score's stream with each centre's corner response code beside it (orb_harris): at
-- stream position (px, py) it carries the centre (px - 3, py - 3). A 3x3 window of S' and the
-- code (two lines in block RAM) decides the centre (px - 4, py - 4); a survivor leaves with its
-- score, feat_low = 1 when it is a corner at the low threshold only, and its code. The last column and row of centres, whose right or
-- lower neighbours lie in the border (score 0) and never arrive, are decided together with their
-- neighbours at the end of each line (px = W - 1) and in the last line (py = H - 1); of those up
-- to four mutually adjacent candidates at most one can survive, so the output carries at most one
-- feature per clock. frame_done pulses with the decision at stream position (W - 1, H - 1).
-- Latency: FAST_NMS_LAT_c = 3 clocks (orb_latency_pkg, docs/latency.md).
-- Ports and generics: docs/entities/orb_fast_nms.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_fast_pkg.all;

entity orb_fast_nms is
  generic (
    LINE_WIDTH_g   : positive range 8 to 4096 := 640;
    FRAME_HEIGHT_g : positive range 1 to 4096 := 480
  );
  port (
    clk        : in    std_logic;
    rst        : in    std_logic;
    in_valid   : in    std_logic;
    in_x       : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y       : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_score   : in    std_logic_vector(SCORE_BITS_c - 1 downto 0);
    in_main    : in    std_logic;
    in_code    : in    std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
    feat_valid : out   std_logic;
    feat_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    feat_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    feat_score : out   std_logic_vector(SCORE_BITS_c - 1 downto 0);
    feat_low   : out   std_logic;
    feat_code  : out   std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
    frame_done : out   std_logic
  );
end entity orb_fast_nms;

architecture rtl of orb_fast_nms is

  constant S_c : positive := SCORE_BITS_c + 1;          -- S' = main & score
  constant D_c : positive := S_c + RESPONSE_BITS_c;    -- a window element: code & S'

  subtype score_t is unsigned(S_c - 1 downto 0);
  subtype code_t is std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
  type row_t is array (0 to 3) of score_t;
  type code_row_t is array (0 to 2) of code_t;
  type code_array_t is array (0 to 2) of code_row_t;

  signal w_valid : std_logic;
  signal w_x     : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal w_y     : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal w_flat  : std_logic_vector(9 * D_c - 1 downto 0);
  signal in_d    : std_logic_vector(D_c - 1 downto 0);

  signal f_valid : std_logic := '0';
  signal f_x     : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal f_y     : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal f_score : score_t := (others => '0');
  signal f_code  : code_t := (others => '0');
  signal f_done  : std_logic := '0';

  -- Survives: > every earlier neighbour, >= every later one, and a corner at all (> 0).
  function survives (c : score_t; e0, e1, e2, e3, l0, l1, l2, l3 : score_t) return boolean is
  begin
    return c > 0 and c > e0 and c > e1 and c > e2 and c > e3 and
           c >= l0 and c >= l1 and c >= l2 and c >= l3;
  end function survives;

begin

  -- the 3x3 window of scores (orb_window), then the decision register
  assert FAST_NMS_LAT_c = WINDOW_LAT_c + 1
    report "orb_fast_nms: FAST_NMS_LAT_c (orb_latency_pkg) must be orb_window's latency + 1"
    severity failure;

  in_d <= in_code & in_main & in_score;

  scores : entity work.orb_window
    generic map (
      LINE_WIDTH_g => LINE_WIDTH_g,
      WIN_g        => 3,
      DATA_WIDTH_g => D_c
    )
    port map (
      clk       => clk,
      rst       => rst,
      in_valid  => in_valid,
      in_x      => in_x,
      in_y      => in_y,
      in_data   => in_d,
      out_valid => w_valid,
      out_x     => w_x,
      out_y     => w_y,
      out_win   => w_flat
    );

  decide : process (clk) is
    type win_t is array (0 to 3) of row_t; -- (r, c) with row/column 3 the zero border
    variable w                  : win_t;
    variable px, py             : unsigned(COORD_BITS_c - 1 downto 0);
    variable at_end_x, at_end_y : boolean;
    variable x_ok, y_ok         : boolean;
    constant Z_c                : score_t := (others => '0');
    variable cd                 : code_array_t;
    -- the candidate (1,1), (1,2), (2,1), (2,2) survives
    variable s0 : boolean;
    variable s1 : boolean;
    variable s2 : boolean;
    variable s3 : boolean;
  begin
    if rising_edge(clk) then
      f_valid <= '0';
      f_done  <= '0';
      if w_valid = '1' then
        w := (others => (others => Z_c));
        for r in 0 to 2 loop
          for c in 0 to 2 loop
            w(r)(c)  := unsigned(w_flat((r * 3 + c) * D_c + S_c - 1 downto (r * 3 + c) * D_c));
            cd(r)(c) := w_flat((r * 3 + c + 1) * D_c - 1 downto (r * 3 + c) * D_c + S_c);
          end loop;
        end loop;
        px       := unsigned(w_x);
        py       := unsigned(w_y);
        at_end_x := px = LINE_WIDTH_g - 1;
        at_end_y := py = FRAME_HEIGHT_g - 1;
        x_ok     := px >= 7;
        y_ok     := py >= 7;
        f_done   <= '1' when at_end_x and at_end_y else '0';
        -- At most one of the four candidates can survive: they are mutually 8-adjacent (of two
        -- neighbours the earlier must be >= the later and the later > the earlier). So the outputs
        -- are selected in parallel (an AND-OR of the one that survives), not by a priority chain.
        s0 := x_ok and y_ok and survives(w(1)(1), w(0)(0), w(0)(1), w(0)(2), w(1)(0),
                                         w(1)(2), w(2)(0), w(2)(1), w(2)(2));
        s1 := at_end_x and y_ok and survives(w(1)(2), w(0)(1), w(0)(2), Z_c, w(1)(1),
                                             Z_c, w(2)(1), w(2)(2), Z_c);
        s2 := at_end_y and x_ok and survives(w(2)(1), w(1)(0), w(1)(1), w(1)(2), w(2)(0),
                                             w(2)(2), Z_c, Z_c, Z_c);
        s3 := at_end_x and at_end_y and survives(w(2)(2), w(1)(1), w(1)(2), Z_c, w(2)(1),
                                                 Z_c, Z_c, Z_c, Z_c);
        f_valid <= '1' when s0 or s1 or s2 or s3 else '0';
        f_x     <= px - 3 when s1 or s3 else px - 4;
        f_y     <= py - 3 when s2 or s3 else py - 4;
        f_score <= (w(1)(1) and (score_t'range => bool2sl(s0))) or (w(1)(2) and (score_t'range => bool2sl(s1))) or
                   (w(2)(1) and (score_t'range => bool2sl(s2))) or (w(2)(2) and (score_t'range => bool2sl(s3)));
        f_code  <= (cd(1)(1) and (code_t'range => bool2sl(s0))) or (cd(1)(2) and (code_t'range => bool2sl(s1))) or
                   (cd(2)(1) and (code_t'range => bool2sl(s2))) or (cd(2)(2) and (code_t'range => bool2sl(s3)));
      end if;
      if rst = '1' then
        f_valid <= '0';
        f_done  <= '0';
      end if;
    end if;
  end process decide;

  feat_valid <= f_valid;
  feat_x     <= std_logic_vector(f_x);
  feat_y     <= std_logic_vector(f_y);
  feat_score <= std_logic_vector(f_score(SCORE_BITS_c - 1 downto 0));
  feat_low   <= not f_score(SCORE_BITS_c);
  feat_code  <= f_code;
  frame_done <= f_done;

end architecture rtl;
