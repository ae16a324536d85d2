-- SPDX-License-Identifier: MIT
-- orb_scaler: 2:1 image scaler (docs/spec.md section 3). Each output pixel is the 2x2 box
-- average (a + b + c + d + 2) >> 2 of one input block; it leaves two clocks after the block's
-- last (bottom-right) input pixel, so the output runs at a quarter of the input rate, in bursts
-- on odd input lines. Horizontal pair sums of even lines wait in one block-RAM line of
-- LINE_WIDTH_g / 2 words; the upper pair's sum, read at the block's lower left pixel, is
-- registered once more before the final addition (no adder behind the block RAM's
-- clock-to-output time: docs/synthesis.md, "Timing"). Latency SCALER_LAT_c = 2 clocks
-- (orb_latency_pkg, docs/latency.md). An odd last column or line of the input is not used. The
-- output carries
-- its position in the reduced image, so scalers chain for further scales.
-- Ports and generics: docs/entities/orb_scaler.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;

entity orb_scaler is
  generic (
    LINE_WIDTH_g : positive range 2 to 4096 := 640
  );
  port (
    clk       : in    std_logic;
    rst       : in    std_logic;
    in_valid  : in    std_logic;
    in_x      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_data   : in    std_logic_vector(PIXEL_BITS_c - 1 downto 0);
    out_valid : out   std_logic;
    out_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_data  : out   std_logic_vector(PIXEL_BITS_c - 1 downto 0)
  );
end entity orb_scaler;

architecture rtl of orb_scaler is

  constant HALF_c : positive := LINE_WIDTH_g / 2;

  type mem_t is array (0 to HALF_c - 1) of unsigned(PIXEL_BITS_c downto 0);

  signal mem     : mem_t;
  signal rd_sum  : unsigned(PIXEL_BITS_c downto 0) := (others => '0');
  signal rd_q    : unsigned(PIXEL_BITS_c downto 0) := (others => '0');
  signal p_valid : std_logic := '0';  -- a complete block's lower pair, waiting for rd_q
  signal p_x     : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal p_y     : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal p_pair  : unsigned(PIXEL_BITS_c + 1 downto 0) := (others => '0');
  signal left_px : unsigned(PIXEL_BITS_c - 1 downto 0) := (others => '0');
  signal o_valid : std_logic := '0';
  signal o_x     : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal o_y     : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal o_data  : unsigned(PIXEL_BITS_c - 1 downto 0) := (others => '0');

begin

  -- the registers from input to output: the upper pair's sum (p_valid), the average (o_valid)
  assert SCALER_LAT_c = 2
    report "orb_scaler: SCALER_LAT_c (orb_latency_pkg) must be this pipeline's 2 clocks"
    severity failure;

  scale : process (clk) is
    variable x, y  : unsigned(COORD_BITS_c - 1 downto 0);
    variable half  : natural range 0 to 2 ** COORD_BITS_c - 1;
    variable pair  : unsigned(PIXEL_BITS_c downto 0);
    variable total : unsigned(PIXEL_BITS_c + 1 downto 0);
  begin
    if rising_edge(clk) then
      -- The upper pair sum read at a block's lower left pixel is in rd_sum after that edge and in
      -- rd_q after the next, at the latest the block's right pixel's edge; the next read (the
      -- next block's left pixel) comes one edge after that at the earliest, the edge that adds
      -- rd_q.
      rd_q    <= rd_sum;
      p_valid <= '0';
      if in_valid = '1' then
        x    := unsigned(in_x);
        y    := unsigned(in_y);
        half := to_integer(x(COORD_BITS_c - 1 downto 1));
        pair := resize(left_px, PIXEL_BITS_c + 1) + unsigned(in_data);
        if x(0) = '0' then
          -- left pixel of a block: keep it, and fetch the upper pair sum of this block
          left_px <= unsigned(in_data);
          if half < HALF_c then
            rd_sum <= mem(half);
          end if;
        elsif y(0) = '0' then
          -- right pixel of an upper pair: store the pair sum
          mem(half) <= pair;
        else
          -- right pixel of a lower pair: the block is complete
          p_valid <= '1';
          p_x     <= resize(x(COORD_BITS_c - 1 downto 1), COORD_BITS_c);
          p_y     <= resize(y(COORD_BITS_c - 1 downto 1), COORD_BITS_c);
          p_pair  <= resize(pair, PIXEL_BITS_c + 2) + 2;
        end if;
      end if;
      -- the block's output, one clock after its last pixel
      o_valid <= p_valid;
      if p_valid = '1' then
        total  := resize(rd_q, PIXEL_BITS_c + 2) + p_pair;
        o_x    <= p_x;
        o_y    <= p_y;
        o_data <= total(PIXEL_BITS_c + 1 downto 2);
      end if;
      if rst = '1' then
        p_valid <= '0';
        o_valid <= '0';
      end if;
    end if;
  end process scale;

  out_valid <= o_valid;
  out_x     <= std_logic_vector(o_x);
  out_y     <= std_logic_vector(o_y);
  out_data  <= std_logic_vector(o_data);

end architecture rtl;
