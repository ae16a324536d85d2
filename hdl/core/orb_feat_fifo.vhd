-- SPDX-License-Identifier: MIT
-- orb_feat_fifo: synchronous first-word-fall-through FIFO of DEPTH_g (a power of two) words of
-- DATA_BITS_g bits, one write and one read port on one clock. The words live in an orb_sdp_ram
-- (latency 1: LUT RAM or block RAM by size); the RAM's read register is the FIFO's output, so
-- the head word is on rd_data while rd_valid is high and rd_en = '1' takes it, one word per clock.
-- A word written into an empty FIFO appears on rd_data FEAT_FIFO_LAT_c = 2 clocks later
-- (orb_latency_pkg, docs/latency.md). A write is accepted
-- when the FIFO holds fewer than DEPTH_g words (level < DEPTH_g) or a word is read in the same
-- clock (rd_en = '1' with rd_valid = '1'); a write into a full FIFO without a read is ignored.
-- level counts every word held, the one on rd_data included. rst resets pointers and counters.
-- Ports and generics: docs/entities/orb_feat_fifo.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;

entity orb_feat_fifo is
  generic (
    DATA_BITS_g : positive range 1 to 1024 := 36;
    DEPTH_g     : positive range 2 to 4096 := 32
  );
  port (
    clk      : in    std_logic;
    rst      : in    std_logic;
    wr_en    : in    std_logic;
    wr_data  : in    std_logic_vector(DATA_BITS_g - 1 downto 0);
    rd_en    : in    std_logic;
    rd_data  : out   std_logic_vector(DATA_BITS_g - 1 downto 0);
    rd_valid : out   std_logic;
    level    : out   std_logic_vector(clog2(DEPTH_g) downto 0)
  );
end entity orb_feat_fifo;

architecture rtl of orb_feat_fifo is

  constant PTR_BITS_c : positive := clog2(DEPTH_g);

  signal q      : std_logic_vector(DATA_BITS_g - 1 downto 0);
  signal q_vld  : std_logic := '0';
  signal wr_ptr : unsigned(PTR_BITS_c - 1 downto 0) := (others => '0');
  signal rd_ptr : unsigned(PTR_BITS_c - 1 downto 0) := (others => '0');
  signal cnt    : unsigned(PTR_BITS_c downto 0) := (others => '0');
  signal rd_ok  : std_logic;
  signal wr_ok  : std_logic;
  signal load   : std_logic;

begin

  -- the registers from input to output: the RAM write, its read register
  assert FEAT_FIFO_LAT_c = 2
    report "orb_feat_fifo: FEAT_FIFO_LAT_c (orb_latency_pkg) must be this pipeline's 2 clocks"
    severity failure;

  assert DEPTH_g = 2 ** PTR_BITS_c
    report "orb_feat_fifo: DEPTH_g must be a power of two"
    severity failure;

  -- The RAM holds the words behind the one on rd_data: at most DEPTH_g - 1 while rd_data holds
  -- one, at most 1 while it does not. So rd_ptr = wr_ptr means "no word in the RAM", and the RAM
  -- is never read at the address written in the same clock.
  rd_ok <= rd_en and q_vld;
  wr_ok <= wr_en when cnt < DEPTH_g or rd_ok = '1' else
           '0';
  load  <= '1' when rd_ptr /= wr_ptr and (q_vld = '0' or rd_ok = '1') else
           '0';

  ram : entity work.orb_sdp_ram
    generic map (
      DATA_WIDTH_g => DATA_BITS_g,
      DEPTH_g      => DEPTH_g,
      LATENCY_g    => 1,
      INIT_ZERO_g  => false
    )
    port map (
      clk     => clk,
      wr_en   => wr_ok,
      wr_addr => std_logic_vector(wr_ptr),
      wr_data => wr_data,
      rd_en   => load,
      rd_addr => std_logic_vector(rd_ptr),
      out_en  => '1',
      rd_data => q
    );

  ctrl : process (clk) is
  begin
    if rising_edge(clk) then
      if wr_ok = '1' then
        wr_ptr <= wr_ptr + 1;
      end if;
      if load = '1' then
        rd_ptr <= rd_ptr + 1;
        q_vld  <= '1';
      elsif rd_ok = '1' then
        q_vld <= '0';
      end if;
      if wr_ok = '1' and rd_ok = '0' then
        cnt <= cnt + 1;
      elsif wr_ok = '0' and rd_ok = '1' then
        cnt <= cnt - 1;
      end if;
      if rst = '1' then
        wr_ptr <= (others => '0');
        rd_ptr <= (others => '0');
        q_vld  <= '0';
        cnt    <= (others => '0');
      end if;
    end if;
  end process ctrl;

  rd_data  <= q;
  rd_valid <= q_vld;
  level    <= std_logic_vector(cnt);

end architecture rtl;
