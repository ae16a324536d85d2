-- SPDX-License-Identifier: MIT
-- orb_window: sliding WIN_g x WIN_g window over a pixel stream, built from an orb_line_buffer
-- (WIN_g - 1 lines in block RAM) and WIN_g column registers. For every input pixel at (x, y) it
-- outputs, WINDOW_LAT_c = 2 clocks later (orb_latency_pkg, docs/latency.md), the window whose
-- bottom-right (newest) pixel is that input pixel, with its position. Element (r, c) sits at bits ((r * WIN_g + c) + 1) * DATA_WIDTH_g - 1 downto
-- (r * WIN_g + c) * DATA_WIDTH_g, r = 0 the top (oldest) line, c = 0 the leftmost column.
-- Near the left and top borders the window holds pixels of the previous line or frame; the
-- consumer masks those positions.
-- Ports and generics: docs/entities/orb_window.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;

entity orb_window is
  generic (
    LINE_WIDTH_g : positive range 3 to 4096 := 640;
    WIN_g        : positive range 2 to 32   := 7;
    DATA_WIDTH_g : positive range 1 to 64   := 8
  );
  port (
    clk       : in    std_logic;
    rst       : in    std_logic;
    in_valid  : in    std_logic;
    in_x      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_data   : in    std_logic_vector(DATA_WIDTH_g - 1 downto 0);
    out_valid : out   std_logic;
    out_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_win   : out   std_logic_vector(WIN_g * WIN_g * DATA_WIDTH_g - 1 downto 0)
  );
end entity orb_window;

architecture rtl of orb_window is

  constant D_c : positive := DATA_WIDTH_g;

  signal col_valid : std_logic;
  signal col_x     : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal col_data  : std_logic_vector(WIN_g * D_c - 1 downto 0);
  signal y_dly     : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal win       : std_logic_vector(WIN_g * WIN_g * D_c - 1 downto 0) := (others => '0');
  signal valid_q   : std_logic := '0';
  signal x_q       : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal y_q       : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');

begin

  -- the registers from input to output: the line buffer's read register, the window's columns
  assert WINDOW_LAT_c = 2
    report "orb_window: WINDOW_LAT_c (orb_latency_pkg) must be this pipeline's 2 clocks"
    severity failure;

  lines : entity work.orb_line_buffer
    generic map (
      LINE_WIDTH_g => LINE_WIDTH_g,
      LINES_g      => WIN_g - 1,
      DATA_WIDTH_g => D_c
    )
    port map (
      clk       => clk,
      rst       => rst,
      in_valid  => in_valid,
      in_col    => in_x,
      in_data   => in_data,
      out_valid => col_valid,
      out_col   => col_x,
      out_data  => col_data
    );

  shift : process (clk) is
    constant ROW_c : positive := WIN_g * D_c;
  begin
    if rising_edge(clk) then
      if in_valid = '1' then
        y_dly <= in_y;
      end if;
      valid_q <= col_valid;
      if col_valid = '1' then
        x_q <= col_x;
        y_q <= y_dly;
        -- Each row shifts one column left; line-buffer slice WIN_g - 1 - r (that many lines
        -- above the newest) enters row r on the right.
        for r in 0 to WIN_g - 1 loop
          win((r + 1) * ROW_c - 1 downto r * ROW_c) <=
            col_data((WIN_g - r) * D_c - 1 downto (WIN_g - 1 - r) * D_c) &
            win((r + 1) * ROW_c - 1 downto r * ROW_c + D_c);
        end loop;
      end if;
      if rst = '1' then
        valid_q <= '0';
      end if;
    end if;
  end process shift;

  out_valid <= valid_q;
  out_x     <= x_q;
  out_y     <= y_q;
  out_win   <= win;

end architecture rtl;
