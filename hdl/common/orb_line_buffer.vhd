-- SPDX-License-Identifier: MIT
-- orb_line_buffer: keeps the previous LINES_g lines of a pixel stream in one block RAM (an
-- orb_sdp_ram) whose word holds a whole column (LINES_g x DATA_WIDTH_g bits), read two clocks
-- before it is rewritten shifted by one line (the shifted word is registered first, so no logic
-- of a RAM cascade sits between the RAM's output and its input: docs/synthesis.md "Timing"; the
-- next read of that column is a line later, at least LINE_WIDTH_g >= 3 clocks). For every input pixel it outputs, one clock later,
-- the column of the LINES_g + 1 newest lines at that x: slice 0 is the input pixel, slice k the
-- pixel k lines above.
-- The caller supplies the column index, so the buffer needs no counters of its own; input gaps
-- of any length are fine. Lines from an earlier frame stay in the RAM until overwritten: callers
-- mask what they read near the top of a frame.
-- Latency LATENCY_g clocks: 1 gives the block RAM's read register itself; 2 adds an output
-- register (the whole column, its valid and its index), so that no logic follows the block RAM's
-- clock-to-output time (docs/synthesis.md, "Timing"). The read-modify-write of the RAM is the same
-- either way.
-- Ports and generics: docs/entities/orb_line_buffer.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;

entity orb_line_buffer is
  generic (
    LINE_WIDTH_g : positive range 3 to 4096 := 640;
    LINES_g      : positive range 1 to 32   := 6;
    DATA_WIDTH_g : positive range 1 to 64   := 8;
    LATENCY_g    : positive range 1 to 2    := 1
  );
  port (
    clk       : in    std_logic;
    rst       : in    std_logic;
    in_valid  : in    std_logic;
    in_col    : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_data   : in    std_logic_vector(DATA_WIDTH_g - 1 downto 0);
    out_valid : out   std_logic;
    out_col   : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_data  : out   std_logic_vector((LINES_g + 1) * DATA_WIDTH_g - 1 downto 0)
  );
end entity orb_line_buffer;

architecture rtl of orb_line_buffer is

  constant WORD_BITS_c : positive := LINES_g * DATA_WIDTH_g;
  constant ADDR_BITS_c : positive := clog2(LINE_WIDTH_g);

  signal rd_word  : std_logic_vector(WORD_BITS_c - 1 downto 0);
  signal wr_en    : std_logic                                  := '0';
  signal wr_addr  : unsigned(ADDR_BITS_c - 1 downto 0)         := (others => '0');
  signal data_dly : std_logic_vector(DATA_WIDTH_g - 1 downto 0) := (others => '0');
  signal col_dly  : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal new_word : std_logic_vector(WORD_BITS_c - 1 downto 0);
  signal wb_en    : std_logic                                  := '0';
  signal wb_addr  : unsigned(ADDR_BITS_c - 1 downto 0)         := (others => '0');
  signal wb_word  : std_logic_vector(WORD_BITS_c - 1 downto 0) := (others => '0');

begin

  assert LINE_WIDTH_g <= 2 ** COORD_BITS_c
    report "orb_line_buffer: LINE_WIDTH_g exceeds the coordinate range"
    severity failure;

  -- The word written back: the column shifted down one line, the new pixel on top (slice 0).
  gen_shift : if LINES_g > 1 generate
    new_word <= rd_word(WORD_BITS_c - DATA_WIDTH_g - 1 downto 0) & data_dly;
  else generate
    new_word <= data_dly;
  end generate gen_shift;

  -- Simple dual-port RAM, zero at power-up: registered read at in_col, write of the shifted word
  -- two clocks later. Read and write addresses differ whenever they coincide in time (columns
  -- two apart).
  ram : entity work.orb_sdp_ram
    generic map (
      DATA_WIDTH_g => WORD_BITS_c,
      DEPTH_g      => LINE_WIDTH_g,
      LATENCY_g    => 1,
      INIT_ZERO_g  => true
    )
    port map (
      clk     => clk,
      wr_en   => wb_en,
      wr_addr => std_logic_vector(wb_addr),
      wr_data => wb_word,
      rd_en   => in_valid,
      rd_addr => in_col(ADDR_BITS_c - 1 downto 0),
      out_en  => '1',
      rd_data => rd_word
    );

  ctrl : process (clk) is
  begin
    if rising_edge(clk) then
      wr_en   <= in_valid;
      wb_en   <= wr_en;
      wb_addr <= wr_addr;
      wb_word <= new_word;
      if in_valid = '1' then
        wr_addr  <= unsigned(in_col(ADDR_BITS_c - 1 downto 0));
        data_dly <= in_data;
        col_dly  <= in_col;
      end if;
      if rst = '1' then
        wr_en <= '0';
        wb_en <= '0';
      end if;
    end if;
  end process ctrl;

  gen_out : if LATENCY_g = 2 generate
    signal o_valid : std_logic := '0';
    signal o_col   : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
    signal o_data  : std_logic_vector((LINES_g + 1) * DATA_WIDTH_g - 1 downto 0) := (others => '0');
  begin

    out_reg : process (clk) is
    begin
      if rising_edge(clk) then
        o_valid <= wr_en;
        o_col   <= col_dly;
        o_data  <= rd_word & data_dly;
        if rst = '1' then
          o_valid <= '0';
        end if;
      end if;
    end process out_reg;

    out_valid <= o_valid;
    out_col   <= o_col;
    out_data  <= o_data;
  else generate
    out_valid <= wr_en;
    out_col   <= col_dly;
    out_data  <= rd_word & data_dly;
  end generate gen_out;

end architecture rtl;
