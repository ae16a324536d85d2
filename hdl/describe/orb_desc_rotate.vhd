-- SPDX-License-Identifier: MIT
-- orb_desc_rotate: the orbit rotation of rBRIEF (docs/spec.md section 10) as one register stage
-- on the merged feature stream, shared by every scale. A feature word (tlast = 0) arrives with the
-- 256 tests of the sector-0 table in its descriptor field and its sector s in the sector field;
-- it leaves with the sector-s descriptor: test j * ORBIT + k is test j * ORBIT + (k + s) mod ORBIT
-- of the input (ORBIT = SECTORS_g, one member per sector), every other field unchanged. An
-- end-of-frame word (tlast = 1) passes unchanged. One orb_desc_rotate after orb_feat_merge
-- replaces a rotator per scale (orb_desc_path with ROTATE_g = false). AXI4-Stream register
-- slice: s_axis_feat_tready = not m_axis_feat_tvalid or m_axis_feat_tready (full throughput, no
-- bubble); latency DESC_ROTATE_LAT_c = 1 clock (orb_latency_pkg, docs/latency.md). Page:
-- docs/rtl-description.md.
-- Ports and generics: docs/entities/orb_desc_rotate.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_feat_pkg.all;
use work.orb_limits_pkg.all;

entity orb_desc_rotate is
  generic (
    SECTORS_g : sectors_t := 32  -- orientation sectors in all
  );
  port (
    clk                : in    std_logic;
    rst                : in    std_logic;
    s_axis_feat_tdata  : in    std_logic_vector(FEAT_BITS_c - 1 downto 0);
    s_axis_feat_tvalid : in    std_logic;
    s_axis_feat_tready : out   std_logic;
    s_axis_feat_tlast  : in    std_logic;
    m_axis_feat_tdata  : out   std_logic_vector(FEAT_BITS_c - 1 downto 0);
    m_axis_feat_tvalid : out   std_logic;
    m_axis_feat_tready : in    std_logic;
    m_axis_feat_tlast  : out   std_logic
  );
end entity orb_desc_rotate;

architecture rtl of orb_desc_rotate is

  constant ORBIT_c  : positive := SECTORS_g;
  constant STAGES_c : positive := clog2(SECTORS_g);

  signal q_data  : std_logic_vector(FEAT_BITS_c - 1 downto 0) := (others => '0');
  signal q_valid : std_logic := '0';
  signal q_last  : std_logic := '0';
  signal take    : std_logic;

begin

  -- the registers from input to output: the register slice
  assert DESC_ROTATE_LAT_c = 1
    report "orb_desc_rotate: DESC_ROTATE_LAT_c (orb_latency_pkg) must be this pipeline's 1 clocks"
    severity failure;

  assert sectors_legal(SECTORS_g)
    report "orb_desc_rotate: SECTORS_g (sectors in all) must be " & SECTORS_TEXT_c
    severity failure;

  assert FEAT_DESC_BITS_c mod ORBIT_c = 0
    report "orb_desc_rotate: the descriptor must split into orbits of SECTORS_g tests"
    severity failure;

  take <= not q_valid or m_axis_feat_tready;

  stage : process (clk) is
    variable sector : unsigned(FEAT_SECTOR_BITS_c - 1 downto 0);
    variable orbit  : unsigned(ORBIT_c - 1 downto 0);
    variable word   : std_logic_vector(FEAT_BITS_c - 1 downto 0);
  begin
    if rising_edge(clk) then
      if take = '1' then
        q_valid <= s_axis_feat_tvalid;
        if s_axis_feat_tvalid = '1' then
          word := s_axis_feat_tdata;
          if s_axis_feat_tlast = '0' then
            -- A logarithmic rotator: stage k rotates by 2^k when bit k of the sector is set
            -- (sectors are below SECTORS_g, so bits 0 .. log2(SECTORS_g) - 1 say it all). Written
            -- as stages, it maps to about two LUT6 per bit (4:1 muxes) instead of wide muxes.
            sector := unsigned(s_axis_feat_tdata(FEAT_SECTOR_LO_c + FEAT_SECTOR_BITS_c - 1 downto FEAT_SECTOR_LO_c));
            for j in 0 to FEAT_DESC_BITS_c / ORBIT_c - 1 loop
              orbit := unsigned(s_axis_feat_tdata(FEAT_DESC_LO_c + (j + 1) * ORBIT_c - 1 downto
                                                  FEAT_DESC_LO_c + j * ORBIT_c));
              for k in 0 to STAGES_c - 1 loop
                if sector(k) = '1' then
                  orbit := orbit(2 ** k - 1 downto 0) & orbit(ORBIT_c - 1 downto 2 ** k);
                end if;
              end loop;
              word(FEAT_DESC_LO_c + (j + 1) * ORBIT_c - 1 downto FEAT_DESC_LO_c + j * ORBIT_c) := std_logic_vector(orbit);
            end loop;
          end if;
          q_data <= word;
          q_last <= s_axis_feat_tlast;
        end if;
      end if;
      if rst = '1' then
        q_valid <= '0';
      end if;
    end if;
  end process stage;

  s_axis_feat_tready <= take;
  m_axis_feat_tdata  <= q_data;
  m_axis_feat_tvalid <= q_valid;
  m_axis_feat_tlast  <= q_last;

end architecture rtl;
