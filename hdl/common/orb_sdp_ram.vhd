-- SPDX-License-Identifier: MIT
-- orb_sdp_ram: the inferred simple dual-port RAM under the FIFOs, line buffers and memories:
-- DEPTH_g words of DATA_WIDTH_g bits (a depth need not be a power of two), one write port and
-- one read port on one clock. wr_en writes wr_data at wr_addr. rd_en loads the word at rd_addr
-- into the read register: latency 1. With LATENCY_g = 2 an output register follows, loaded when
-- out_en is 1 (tie it to 1 for a plain latency of 2; LATENCY_g = 1 ignores it). Read during a
-- write of the same address is read-first: the read register gets the word as it was before the
-- write. Both registers hold while their enable is 0 and start at 0. Addresses must be below
-- DEPTH_g whenever their port is enabled. INIT_ZERO_g: the words start at 0 (the 7-series
-- power-up value); false gives them no initial value, so unwritten words read 'U' in simulation
-- and GHDL's netlist carries no initialiser (for a large RAM it is megabytes). No reset: a RAM
-- holds no control state. With INIT_ZERO_g the words are a process variable (one value per word
-- for the simulator, not a signal per bit), without it a signal (see gen_ram below). `ghdl synth`
-- reports them as RAM "gen_ram.ram.mem" / "gen_ram.mem", and yosys maps them to block RAM
-- (RAMB18E1 / RAMB36E1) or LUT RAM by size. Doc: docs/conventions.md ("Memories").
-- Ports and generics: docs/entities/orb_sdp_ram.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;

entity orb_sdp_ram is
  generic (
    DATA_WIDTH_g : positive range 1 to 4096    := 8;
    DEPTH_g      : positive range 2 to 2 ** 20 := 1024;
    LATENCY_g    : positive range 1 to 2       := 1;
    INIT_ZERO_g  : boolean                     := true
  );
  port (
    clk     : in    std_logic;
    wr_en   : in    std_logic;
    wr_addr : in    std_logic_vector(clog2(DEPTH_g) - 1 downto 0);
    wr_data : in    std_logic_vector(DATA_WIDTH_g - 1 downto 0);
    rd_en   : in    std_logic;
    rd_addr : in    std_logic_vector(clog2(DEPTH_g) - 1 downto 0);
    out_en  : in    std_logic;
    rd_data : out   std_logic_vector(DATA_WIDTH_g - 1 downto 0)
  );
end entity orb_sdp_ram;

architecture rtl of orb_sdp_ram is

  subtype word_t is std_logic_vector(DATA_WIDTH_g - 1 downto 0);

  type mem_t is array (0 to DEPTH_g - 1) of word_t;

  signal q  : word_t := (others => '0');  -- read register
  signal q2 : word_t := (others => '0');  -- output register (LATENCY_g = 2)

begin

  -- Read before write: read-first (a signal memory is read-first by itself). With INIT_ZERO_g the
  -- memory is a process variable. Without, it is a signal: GHDL 2.0 writes a variable memory
  -- without an initial value as all 'X' in its VHDL netlist, which the netlist simulation
  -- (sw/orb_sim/netlist.py) does not start at 0 as it does a signal without one.
  gen_ram : if INIT_ZERO_g generate

    ram : process (clk) is
      variable mem : mem_t := (others => (others => '0'));
    begin
      if rising_edge(clk) then
        if rd_en = '1' then
          q <= mem(to_integer(unsigned(rd_addr)));
        end if;
        if wr_en = '1' then
          mem(to_integer(unsigned(wr_addr))) := wr_data;
        end if;
      end if;
    end process ram;

  else generate
    signal mem : mem_t;
  begin

    ram : process (clk) is
    begin
      if rising_edge(clk) then
        if rd_en = '1' then
          q <= mem(to_integer(unsigned(rd_addr)));
        end if;
        if wr_en = '1' then
          mem(to_integer(unsigned(wr_addr))) <= wr_data;
        end if;
      end if;
    end process ram;

  end generate gen_ram;

  gen_latency : if LATENCY_g = 2 generate

    out_reg : process (clk) is
    begin
      if rising_edge(clk) then
        if out_en = '1' then
          q2 <= q;
        end if;
      end if;
    end process out_reg;

    rd_data <= q2;
  else generate
    rd_data <= q;
  end generate gen_latency;

end architecture rtl;
