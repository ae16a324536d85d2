-- SPDX-License-Identifier: MIT
-- orb_frame_gate: passes or drops whole video frames of an AXI4-Stream (tuser = start of frame,
-- tlast = end of line) by `enable`, sampled with each start of frame in the first clock its tuser
-- beat is offered: a frame whose tuser beat comes while enable is 1 passes whole (enable falling
-- later, even while that beat waits on a stalled output, does not cut it: m_axis_video keeps
-- tvalid and the beat until taken), a frame whose tuser beat comes while enable is 0 is taken at
-- once and ignored whole (s_axis_video_tready 1, nothing on m_axis_video; enable rising later
-- does not open it). Out of reset the gate is open, so the
-- rest of a frame cut by a reset passes (orb_video_check discards it as pixels without a start
-- of frame). Latency FRAME_GATE_LAT_c = 0 (orb_latency_pkg, docs/latency.md): data, tuser, tlast
-- and tvalid pass combinationally, tready comes back
-- combinationally; the state is the open/closed bit and the bit that holds a waiting start of
-- frame's decision. See docs/frame-gate.md.
-- Ports and generics: docs/entities/orb_frame_gate.md

library ieee;
use ieee.std_logic_1164.all;

use work.orb_latency_pkg.all;

entity orb_frame_gate is
  generic (
    DATA_WIDTH_g : positive := 8  -- tdata bits (any width: the data only passes through)
  );
  port (
    clk                 : in    std_logic;
    rst                 : in    std_logic;
    enable              : in    std_logic;
    s_axis_video_tdata  : in    std_logic_vector(DATA_WIDTH_g - 1 downto 0);
    s_axis_video_tvalid : in    std_logic;
    s_axis_video_tready : out   std_logic;
    s_axis_video_tuser  : in    std_logic;
    s_axis_video_tlast  : in    std_logic;
    m_axis_video_tdata  : out   std_logic_vector(DATA_WIDTH_g - 1 downto 0);
    m_axis_video_tvalid : out   std_logic;
    m_axis_video_tready : in    std_logic;
    m_axis_video_tuser  : out   std_logic;
    m_axis_video_tlast  : out   std_logic
  );
end entity orb_frame_gate;

architecture rtl of orb_frame_gate is

  signal gate_open : std_logic := '1';  -- the frame under way passes (its tuser beat saw enable)
  signal sof_hold  : std_logic := '0';  -- a passing tuser beat waits on the output: it stays passing
  signal gate_pass : std_logic;         -- the beat on s_axis_video passes
  signal ready     : std_logic;

begin

  -- the registers from input to output: none (combinational)
  assert FRAME_GATE_LAT_c = 0
    report "orb_frame_gate: FRAME_GATE_LAT_c (orb_latency_pkg) must be this pipeline's 0 clocks"
    severity failure;

  gate : process (clk) is
  begin
    if rising_edge(clk) then
      if s_axis_video_tvalid = '1' and ready = '1' and s_axis_video_tuser = '1' then
        gate_open <= gate_pass;
      end if;
      -- offered on m_axis_video and not taken: the same beat is there at the next edge (AXI4-Stream)
      sof_hold <= s_axis_video_tvalid and s_axis_video_tuser and gate_pass and not m_axis_video_tready;
      if rst = '1' then
        gate_open <= '1';
        sof_hold  <= '0';
      end if;
    end if;
  end process gate;

  -- a start-of-frame beat passes by enable itself (or, while it waits on the output, by the enable
  -- of the clock it came in), every other beat by the state of its frame
  gate_pass <= (enable or sof_hold) when s_axis_video_tuser = '1' else
               gate_open;
  ready     <= m_axis_video_tready when gate_pass = '1' else
               '1';

  s_axis_video_tready <= ready;
  m_axis_video_tvalid <= s_axis_video_tvalid and gate_pass;
  m_axis_video_tdata  <= s_axis_video_tdata;
  m_axis_video_tuser  <= s_axis_video_tuser;
  m_axis_video_tlast  <= s_axis_video_tlast;

end architecture rtl;
