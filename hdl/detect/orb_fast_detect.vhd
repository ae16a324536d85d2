-- SPDX-License-Identifier: MIT
-- orb_fast_detect: the detection path of one scale: 7x7 window (six lines in block RAM), FAST-9
-- segment test and SAD score, 3x3 non-maximum suppression. Input: the scale's pixel stream with
-- each pixel's position; output: the NMS survivors (docs/spec.md sections 4 to 6, fast mode) with
-- their position and score, at most one per clock, a few clocks after the pixel that completes
-- them. The threshold is sampled with the frame's first pixel (0, 0) and holds for that frame.
-- frame_done pulses once the frame's last decision has been made. The 7x7 window is also an
-- output, for the smoothing of the descriptor path.

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;

entity orb_fast_detect is
  generic (
    LINE_WIDTH_g   : positive range 8 to 4096 := 640;
    FRAME_HEIGHT_g : positive range 1 to 4096 := 480
  );
  port (
    clk        : in    std_logic;
    rst        : in    std_logic;
    threshold  : in    std_logic_vector(7 downto 0);
    in_valid   : in    std_logic;
    in_x       : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y       : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_data    : in    std_logic_vector(PIXEL_BITS_c - 1 downto 0);
    feat_valid : out   std_logic;
    feat_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    feat_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    feat_score : out   std_logic_vector(SCORE_BITS_c - 1 downto 0);
    frame_done : out   std_logic;
    -- the 7x7 window (orb_window's layout), shared with the smoothing of the descriptor path
    win_valid : out   std_logic;
    win_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    win_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    win_data  : out   std_logic_vector(49 * PIXEL_BITS_c - 1 downto 0)
  );
end entity orb_fast_detect;

architecture rtl of orb_fast_detect is

  signal thr_next  : std_logic_vector(7 downto 0) := (others => '0');
  signal thr_frame : std_logic_vector(7 downto 0) := (others => '0');
  signal w_valid   : std_logic;
  signal w_x, w_y  : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal w_win     : std_logic_vector(49 * PIXEL_BITS_c - 1 downto 0);
  signal s_valid   : std_logic;
  signal s_x, s_y  : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal s_score   : std_logic_vector(SCORE_BITS_c - 1 downto 0);

begin

  -- The threshold of a frame is the one present with its first pixel. It is taken over by the
  -- score stage when that pixel leaves the window generator, after the previous frame's last
  -- window (a back-to-back next frame must not change the threshold of the frame still in flight).
  sample : process (clk) is
  begin
    if rising_edge(clk) then
      if in_valid = '1' and unsigned(in_x) = 0 and unsigned(in_y) = 0 then
        thr_next <= threshold;
      end if;
      if w_valid = '1' and unsigned(w_x) = 0 and unsigned(w_y) = 0 then
        thr_frame <= thr_next;
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
      clk       => clk,
      rst       => rst,
      threshold => thr_frame,
      in_valid  => w_valid,
      in_x      => w_x,
      in_y      => w_y,
      in_win    => w_win,
      out_valid => s_valid,
      out_x     => s_x,
      out_y     => s_y,
      out_score => s_score
    );

  nms : entity work.orb_fast_nms
    generic map (
      LINE_WIDTH_g   => LINE_WIDTH_g,
      FRAME_HEIGHT_g => FRAME_HEIGHT_g
    )
    port map (
      clk        => clk,
      rst        => rst,
      in_valid   => s_valid,
      in_x       => s_x,
      in_y       => s_y,
      in_score   => s_score,
      feat_valid => feat_valid,
      feat_x     => feat_x,
      feat_y     => feat_y,
      feat_score => feat_score,
      frame_done => frame_done
    );

  win_valid <= w_valid;
  win_x     <= w_x;
  win_y     <= w_y;
  win_data  <= w_win;

end architecture rtl;
