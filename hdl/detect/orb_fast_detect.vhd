-- SPDX-License-Identifier: MIT
-- orb_fast_detect: the detection path of one scale: 7x7 window (six lines in block RAM), FAST-9
-- segment test at the main and the low threshold with the SAD score (orb_fast_score), the corner
-- response code (orb_harris) and 3x3 non-maximum suppression on the combined map (orb_fast_nms).
-- Input: the scale's pixel stream with each pixel's position; output: the NMS survivors (docs/
-- spec.md sections 4 to 6 and 15, fast mode) with their position, score, low flag and code, at
-- most one per clock, HARRIS_LAT_c + FAST_NMS_LAT_c clocks after the window that completes their
-- NMS neighbourhood, FAST_DETECT_LAT_c = 22 clocks after its newest pixel (orb_latency_pkg,
-- docs/latency.md; the score waits beside orb_harris). The thresholds are sampled with the frame's first pixel (0, 0) and
-- hold for that frame. frame_done pulses once the frame's last decision has been made. The 7x7
-- window is also an output, for the smoothing of the descriptor path.
-- Ports and generics: docs/entities/orb_fast_detect.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_fast_pkg.all;

entity orb_fast_detect is
  generic (
    LINE_WIDTH_g   : positive range 8 to 4096 := 640;
    FRAME_HEIGHT_g : positive range 1 to 4096 := 480
  );
  port (
    clk          : in    std_logic;
    rst          : in    std_logic;
    threshold    : in    std_logic_vector(7 downto 0);
    threshold_lo : in    std_logic_vector(7 downto 0);
    in_valid     : in    std_logic;
    in_x         : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y         : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_data      : in    std_logic_vector(PIXEL_BITS_c - 1 downto 0);
    feat_valid   : out   std_logic;
    feat_x       : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    feat_y       : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    feat_score   : out   std_logic_vector(SCORE_BITS_c - 1 downto 0);
    feat_low     : out   std_logic;
    feat_code    : out   std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
    frame_done   : out   std_logic;
    -- the 7x7 window (orb_window's layout), shared with the smoothing of the descriptor path
    win_valid : out   std_logic;
    win_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    win_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    win_data  : out   std_logic_vector(49 * PIXEL_BITS_c - 1 downto 0)
  );
end entity orb_fast_detect;

architecture rtl of orb_fast_detect is

  -- the score waits this many clocks beside orb_harris
  constant WAIT_c : natural := HARRIS_LAT_c - FAST_SCORE_LAT_c;

  type score_dly_t is array (1 to WAIT_c) of std_logic_vector(SCORE_BITS_c downto 0);

  signal thr_next  : std_logic_vector(7 downto 0) := (others => '0');
  signal thr_frame : std_logic_vector(7 downto 0) := (others => '0');
  signal tlo_next  : std_logic_vector(7 downto 0) := (others => '0');
  signal tlo_frame : std_logic_vector(7 downto 0) := (others => '0');
  signal w_valid   : std_logic;
  signal w_x, w_y  : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal w_win     : std_logic_vector(49 * PIXEL_BITS_c - 1 downto 0);
  signal s_valid   : std_logic;
  signal s_x, s_y  : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal s_score   : std_logic_vector(SCORE_BITS_c - 1 downto 0);
  signal s_main    : std_logic;
  signal h_valid   : std_logic;
  signal h_x, h_y  : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal h_code    : std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
  signal dly       : score_dly_t := (others => (others => '0'));

begin

  -- The threshold of a frame is the one present with its first pixel. It is taken over by the
  -- score stage when that pixel leaves the window generator, after the previous frame's last
  -- window (a back-to-back next frame must not change the threshold of the frame still in flight).
  sample : process (clk) is
  begin
    if rising_edge(clk) then
      if in_valid = '1' and unsigned(in_x) = 0 and unsigned(in_y) = 0 then
        thr_next <= threshold;
        tlo_next <= threshold_lo;
      end if;
      if w_valid = '1' and unsigned(w_x) = 0 and unsigned(w_y) = 0 then
        thr_frame <= thr_next;
        tlo_frame <= tlo_next;
      end if;
    end if;
  end process sample;

  window : entity work.orb_window
    generic map (
      LINE_WIDTH_g => LINE_WIDTH_g,
      WIN_g        => 7,
      DATA_WIDTH_g => PIXEL_BITS_c
    )
    port map (
      clk       => clk,
      rst       => rst,
      in_valid  => in_valid,
      in_x      => in_x,
      in_y      => in_y,
      in_data   => in_data,
      out_valid => w_valid,
      out_x     => w_x,
      out_y     => w_y,
      out_win   => w_win
    );

  score : entity work.orb_fast_score
    port map (
      clk          => clk,
      rst          => rst,
      threshold    => thr_frame,
      threshold_lo => tlo_frame,
      in_valid     => w_valid,
      in_x         => w_x,
      in_y         => w_y,
      in_win       => w_win,
      out_valid    => s_valid,
      out_x        => s_x,
      out_y        => s_y,
      out_score    => s_score,
      out_main     => s_main
    );

  harris : entity work.orb_harris
    port map (
      clk       => clk,
      rst       => rst,
      in_valid  => w_valid,
      in_x      => w_x,
      in_y      => w_y,
      in_win    => w_win,
      out_valid => h_valid,
      out_x     => h_x,
      out_y     => h_y,
      out_code  => h_code
    );

  -- the score and main flag of a window, WAIT_c clocks later, beside its code (both stages have
  -- fixed latencies in clocks, so the delay line needs no valid)
  wait_score : process (clk) is
  begin
    if rising_edge(clk) then
      dly <= (s_main & s_score) & dly(1 to WAIT_c - 1);
    end if;
  end process wait_score;

  nms : entity work.orb_fast_nms
    generic map (
      LINE_WIDTH_g   => LINE_WIDTH_g,
      FRAME_HEIGHT_g => FRAME_HEIGHT_g
    )
    port map (
      clk        => clk,
      rst        => rst,
      in_valid   => h_valid,
      in_x       => h_x,
      in_y       => h_y,
      in_score   => dly(WAIT_c)(SCORE_BITS_c - 1 downto 0),
      in_main    => dly(WAIT_c)(SCORE_BITS_c),
      in_code    => h_code,
      feat_valid => feat_valid,
      feat_x     => feat_x,
      feat_y     => feat_y,
      feat_score => feat_score,
      feat_low   => feat_low,
      feat_code  => feat_code,
      frame_done => frame_done
    );

  win_valid <= w_valid;
  win_x     <= w_x;
  win_y     <= w_y;
  win_data  <= w_win;

end architecture rtl;
