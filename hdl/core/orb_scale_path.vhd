-- SPDX-License-Identifier: MIT
-- orb_scale_path: everything one scale computes. orb_fast_detect (7x7 window, FAST-9 score, 3x3
-- NMS) and, when DESC_g is true, orb_smooth on the same 7x7 window feeding orb_desc_path
-- (sector and rBRIEF descriptor of every NMS survivor inside the descriptor border). The mode
-- (fast: every NMS survivor, no descriptor; orb: described features only) and the threshold are
-- sampled with the frame's first pixel (0, 0) and hold for that frame. Both paths always run; a
-- small per-frame queue of modes tells each path's output whether its current frame is to be
-- reported, so a mode change never mixes or loses frames (the fast path reports a frame about 4
-- lines after its pixels, the descriptor path 18 lines after). frame_done pulses once per frame,
-- after the frame's last reported feature.

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_limits_pkg.all;

entity orb_scale_path is
  generic (
    LINE_WIDTH_g   : positive range 8 to 4095 := 640;
    FRAME_HEIGHT_g : positive range 1 to 4095 := 480;
    SECTORS_g      : sectors_t                := 32;  -- orientation sectors in all
    DESC_g         : boolean                  := true;
    ROTATE_g       : boolean                  := true -- orb_desc_path's ROTATE_g
  );
  port (
    clk          : in    std_logic;
    rst          : in    std_logic;
    threshold    : in    std_logic_vector(7 downto 0);
    threshold_lo : in    std_logic_vector(7 downto 0);
    mode_orb     : in    std_logic;
    in_valid     : in    std_logic;
    in_x         : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y         : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_data      : in    std_logic_vector(PIXEL_BITS_c - 1 downto 0);
    feat_valid   : out   std_logic;
    feat_x       : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    feat_y       : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    feat_score   : out   std_logic_vector(SCORE_BITS_c - 1 downto 0);
    feat_sector  : out   std_logic_vector(5 downto 0);
    feat_desc    : out   std_logic_vector(255 downto 0);
    frame_done   : out   std_logic;
    lost         : out   std_logic_vector(31 downto 0)
  );
end entity orb_scale_path;

architecture rtl of orb_scale_path is

  type modes_t is array (0 to 3) of std_logic;

  -- A scale smaller than the descriptor border (37 x 37) has no describable pixel: in orb mode
  -- it reports no feature, only its frame ends.
  constant HAS_DESC_c : boolean := DESC_g and LINE_WIDTH_g >= 37 and FRAME_HEIGHT_g >= 37;

  signal d_valid, d_done : std_logic;
  signal d_x,     d_y    : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal d_score         : std_logic_vector(SCORE_BITS_c - 1 downto 0);
  signal w_valid         : std_logic;
  signal w_x,     w_y    : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal w_win           : std_logic_vector(49 * PIXEL_BITS_c - 1 downto 0);

  signal o_valid, o_done : std_logic := '0';
  signal o_x,     o_y    : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal o_score         : std_logic_vector(SCORE_BITS_c - 1 downto 0) := (others => '0');
  signal o_sector        : std_logic_vector(5 downto 0) := (others => '0');
  signal o_desc          : std_logic_vector(255 downto 0) := (others => '0');
  signal o_lost          : std_logic_vector(31 downto 0) := (others => '0');

  -- per-frame modes, written at each frame's first pixel, read by each path at its frame end
  signal modes     : modes_t := (others => '0');
  signal mode_wr   : unsigned(1 downto 0) := (others => '0');
  signal mode_rd_d : unsigned(1 downto 0) := (others => '0');
  signal mode_rd_o : unsigned(1 downto 0) := (others => '0');
  signal fast_on   : std_logic;
  signal orb_on    : std_logic;

  signal f_valid      : std_logic := '0';
  signal f_done       : std_logic := '0';
  signal f_x,     f_y : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal f_score      : std_logic_vector(SCORE_BITS_c - 1 downto 0) := (others => '0');
  signal f_sector     : std_logic_vector(5 downto 0) := (others => '0');
  signal f_desc       : std_logic_vector(255 downto 0) := (others => '0');

begin

  detect : entity work.orb_fast_detect
    generic map (
      LINE_WIDTH_g   => LINE_WIDTH_g,
      FRAME_HEIGHT_g => FRAME_HEIGHT_g
    )
    port map (
      clk          => clk,
      rst          => rst,
      threshold    => threshold,
      threshold_lo => threshold_lo,
      in_valid     => in_valid,
      in_x         => in_x,
      in_y         => in_y,
      in_data      => in_data,
      feat_valid   => d_valid,
      feat_x       => d_x,
      feat_y       => d_y,
      feat_score   => d_score,
      frame_done   => d_done,
      win_valid    => w_valid,
      win_x        => w_x,
      win_y        => w_y,
      win_data     => w_win
    );

  gen_desc : if HAS_DESC_c generate
    signal s_valid  : std_logic;
    signal s_x, s_y : std_logic_vector(COORD_BITS_c - 1 downto 0);
    signal s_data   : std_logic_vector(PIXEL_BITS_c - 1 downto 0);
    signal w_col    : std_logic_vector(7 * PIXEL_BITS_c - 1 downto 0);
  begin

    -- the window's newest column (c = 6), top pixel first: orb_smooth slides its own column sums
    newest : for r in 0 to 6 generate
      w_col((r + 1) * PIXEL_BITS_c - 1 downto r * PIXEL_BITS_c) <= w_win((r * 7 + 7) * PIXEL_BITS_c - 1 downto (r * 7 + 6) * PIXEL_BITS_c);
    end generate newest;

    smooth : entity work.orb_smooth
      port map (
        clk       => clk,
        rst       => rst,
        in_valid  => w_valid,
        in_x      => w_x,
        in_y      => w_y,
        in_col    => w_col,
        out_valid => s_valid,
        out_x     => s_x,
        out_y     => s_y,
        out_data  => s_data
      );

    desc : entity work.orb_desc_path
      generic map (
        LINE_WIDTH_g   => LINE_WIDTH_g,
        FRAME_HEIGHT_g => FRAME_HEIGHT_g,
        SECTORS_g      => SECTORS_g,
        ROTATE_g       => ROTATE_g
      )
      port map (
        clk         => clk,
        rst         => rst,
        in_valid    => s_valid,
        in_x        => s_x,
        in_y        => s_y,
        in_data     => s_data,
        det_valid   => d_valid,
        det_x       => d_x,
        det_y       => d_y,
        det_score   => d_score,
        feat_valid  => o_valid,
        feat_x      => o_x,
        feat_y      => o_y,
        feat_score  => o_score,
        feat_sector => o_sector,
        feat_desc   => o_desc,
        frame_done  => o_done,
        lost        => o_lost
      );

  else generate
    o_valid <= '0';
    o_done  <= d_done;
    o_lost  <= (others => '0');
  end generate gen_desc;

  fast_on <= not modes(to_integer(mode_rd_d));
  orb_on  <= modes(to_integer(mode_rd_o));

  select_out : process (clk) is
  begin
    if rising_edge(clk) then
      if in_valid = '1' and unsigned(in_x) = 0 and unsigned(in_y) = 0 then
        modes(to_integer(mode_wr)) <= mode_orb when DESC_g else '0';
        mode_wr                    <= mode_wr + 1;
      end if;
      if d_done = '1' then
        mode_rd_d <= mode_rd_d + 1;
      end if;
      if o_done = '1' then
        mode_rd_o <= mode_rd_o + 1;
      end if;
      -- The two paths never report in the same clock: a fast frame's survivors leave within a
      -- few clocks of its pixels, an orb frame's features 18 lines after theirs.
      f_valid <= (d_valid and fast_on) or (o_valid and orb_on);
      f_done  <= (d_done and fast_on) or (o_done and orb_on);
      if o_valid = '1' and orb_on = '1' then
        f_x      <= o_x;
        f_y      <= o_y;
        f_score  <= o_score;
        f_sector <= o_sector;
        f_desc   <= o_desc;
      else
        f_x      <= d_x;
        f_y      <= d_y;
        f_score  <= d_score;
        f_sector <= (others => '0');
        f_desc   <= (others => '0');
      end if;
      if rst = '1' then
        mode_wr   <= (others => '0');
        mode_rd_d <= (others => '0');
        mode_rd_o <= (others => '0');
        f_valid   <= '0';
        f_done    <= '0';
      end if;
    end if;
  end process select_out;

  feat_valid  <= f_valid;
  feat_x      <= f_x;
  feat_y      <= f_y;
  feat_score  <= f_score;
  feat_sector <= f_sector;
  feat_desc   <= f_desc;
  frame_done  <= f_done;
  lost        <= o_lost;

end architecture rtl;
