-- SPDX-License-Identifier: MIT
-- orb_scale_path: everything one scale computes. orb_fast_detect (7x7 window, FAST-9 score at the
-- main and the low threshold, corner response, 3x3 NMS) and, when DESC_g is true, orb_smooth on
-- the same 7x7 window feeding orb_desc_path (sector and rBRIEF descriptor of every NMS survivor
-- inside the descriptor border), then the level's selection (orb_feat_select: docs/spec.md
-- section 14, docs/selection.md). The mode (fast: every NMS survivor, no descriptor; orb:
-- described features only), the thresholds and the selection's parameters (grid, the level's
-- budget, the grid's cells) are sampled with the frame's first pixel (0, 0) and hold for
-- that frame; the budget is taken again at the pixel (0, 1), when orb_core's split of the frame's
-- budget is ready. Both paths always run; a small per-frame queue of the modes and parameters tells
-- each path's output whether its current frame is to be reported and what the selection applies,
-- so a change never mixes or loses frames (the fast path reports a frame about 4 lines after its
-- pixels, the descriptor path 18 lines after). The selection decides on each candidate before the
-- candidate leaves: orb_desc_path shows its features CAND_LEAD_LAT_c clocks early, and the fast
-- path's survivors wait CAND_LEAD_LAT_c clocks. The candidates pass a two-entry queue that gives the
-- selection at most one every second clock (two survivors can leave the NMS in consecutive clocks
-- at a line's end), and the decisions wait in a small FIFO for their features (one decision per
-- feature, in order; a decision is at most FEAT_SELECT_LAT_c + 2 clocks old when its feature comes
-- CAND_LEAD_LAT_c clocks after its candidate; both in orb_latency_pkg, docs/latency.md). A feature
-- leaves only when the selection
-- keeps it, with its slot (BASE_g + the level's slot) and whether it replaces that slot's occupant;
-- in `all` mode every main feature leaves (slot BASE_g, a new slot: replace 0). frame_done pulses once per frame,
-- after the frame's last reported feature.
-- Ports and generics: docs/entities/orb_scale_path.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_limits_pkg.all;
use work.orb_fast_pkg.all;
use work.orb_feat_pkg.all;

entity orb_scale_path is
  generic (
    LINE_WIDTH_g   : positive range 8 to 4095 := 640;
    FRAME_HEIGHT_g : positive range 1 to 4095 := 480;
    SECTORS_g      : sectors_t                := 32;   -- orientation sectors in all
    DESC_g         : boolean                  := true;
    ROTATE_g       : boolean                  := true; -- orb_desc_path's ROTATE_g
    SLOTS_g        : positive range 1 to 4095 := 1023; -- the most slots the level can be given
    BASE_g         : natural range 0 to 8191  := 0;    -- the level's first slot in the frame's slots
    -- the selection's cell map (orb_feat_select): the frame's size, the pyramid step, the level
    FULL_WIDTH_g  : width_t              := 640;
    FULL_HEIGHT_g : height_t             := 480;
    STEP_NUM_g    : step_num_t           := 2;
    STEP_DEN_g    : step_den_t           := 1;
    LEVEL_g       : natural range 0 to 7 := 0
  );
  port (
    clk          : in    std_logic;
    rst          : in    std_logic;
    threshold    : in    std_logic_vector(7 downto 0);
    threshold_lo : in    std_logic_vector(7 downto 0);
    mode_orb     : in    std_logic;
    select_grid  : in    std_logic;
    budget       : in    std_logic_vector(SEL_SLOT_BITS_c - 1 downto 0); -- the level's, at most SLOTS_g
    grid_cols    : in    std_logic_vector(GRID_BITS_c - 1 downto 0);     -- cells across the frame
    grid_rows    : in    std_logic_vector(GRID_BITS_c - 1 downto 0);     -- cells down the frame
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
    feat_sector  : out   std_logic_vector(5 downto 0);
    feat_desc    : out   std_logic_vector(255 downto 0);
    feat_slot    : out   std_logic_vector(FEAT_SEL_SLOT_BITS_c - 1 downto 0);
    feat_replace : out   std_logic;
    frame_done   : out   std_logic;
    lost         : out   std_logic_vector(31 downto 0)
  );
end entity orb_scale_path;

architecture rtl of orb_scale_path is

  type modes_t is array (0 to 3) of std_logic;
  type budgets_t is array (0 to 3) of std_logic_vector(SEL_SLOT_BITS_c - 1 downto 0);
  type cells_t is array (0 to 3) of std_logic_vector(2 * GRID_BITS_c - 1 downto 0);

  -- a fast-path survivor (x, y, score, low, code) waiting CAND_LEAD_LAT_c clocks
  constant FW_c : positive := 2 * COORD_BITS_c + SCORE_BITS_c + 1 + RESPONSE_BITS_c;
  -- a decision waiting for its feature: keep, new, slot
  constant DW_c : positive := 2 + SEL_SLOT_BITS_c;
  -- a candidate waiting for the selection: x, y, low, code
  constant CW_c : positive := 2 * COORD_BITS_c + 1 + RESPONSE_BITS_c;

  type fast_dly_t is array (1 to CAND_LEAD_LAT_c) of std_logic_vector(FW_c - 1 downto 0);
  type dec_fifo_t is array (0 to 15) of std_logic_vector(DW_c - 1 downto 0);
  type cand_q_t is array (0 to 1) of std_logic_vector(CW_c - 1 downto 0);

  -- A scale smaller than the descriptor border (37 x 37) has no describable pixel: in orb mode
  -- it reports no feature, only its frame ends.
  constant HAS_DESC_c : boolean := DESC_g and LINE_WIDTH_g >= 37 and FRAME_HEIGHT_g >= 37;

  signal d_valid, d_done : std_logic;
  signal d_x,     d_y    : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal d_score         : std_logic_vector(SCORE_BITS_c - 1 downto 0);
  signal d_low           : std_logic;
  signal d_code          : std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
  signal w_valid         : std_logic;
  signal w_x,     w_y    : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal w_win           : std_logic_vector(49 * PIXEL_BITS_c - 1 downto 0);

  -- the fast path's survivors CAND_LEAD_LAT_c clocks later (fd_done: its frame end as late)
  signal fd_valid : std_logic_vector(1 to CAND_LEAD_LAT_c) := (others => '0');
  signal fd_done  : std_logic_vector(1 to CAND_LEAD_LAT_c) := (others => '0');
  signal fd_data  : fast_dly_t := (others => (others => '0'));

  signal o_valid, o_done : std_logic := '0';
  signal o_x,     o_y    : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal o_score         : std_logic_vector(SCORE_BITS_c - 1 downto 0) := (others => '0');
  signal o_low           : std_logic := '0';
  signal o_code          : std_logic_vector(RESPONSE_BITS_c - 1 downto 0) := (others => '0');
  signal o_sector        : std_logic_vector(5 downto 0) := (others => '0');
  signal o_desc          : std_logic_vector(255 downto 0) := (others => '0');
  signal o_lost          : std_logic_vector(31 downto 0) := (others => '0');
  signal c_valid         : std_logic := '0';  -- the descriptor path's candidates
  signal c_x,     c_y    : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal c_low           : std_logic := '0';
  signal c_code          : std_logic_vector(RESPONSE_BITS_c - 1 downto 0) := (others => '0');

  -- per-frame modes and selection parameters, written at each frame's first pixel, read by each
  -- path at its frame end and by the selection at the end of the frame it selects
  signal modes     : modes_t := (others => '0');
  signal grids     : modes_t := (others => '0');
  signal budgets   : budgets_t := (others => (others => '0'));
  signal cells     : cells_t := (others => (others => '0'));
  signal mode_wr   : unsigned(1 downto 0) := (others => '0');
  signal mode_rd_d : unsigned(1 downto 0) := (others => '0');
  signal mode_rd_o : unsigned(1 downto 0) := (others => '0');
  signal sel_rd    : unsigned(1 downto 0) := (others => '0');
  signal fast_on   : std_logic;
  signal orb_on    : std_logic;

  -- the selection: candidates in, decisions out, and the decisions waiting for their features
  signal p_grid       : std_logic;
  signal p_budget     : std_logic_vector(SEL_SLOT_BITS_c - 1 downto 0);
  signal p_cells      : std_logic_vector(2 * GRID_BITS_c - 1 downto 0);
  signal e_valid      : std_logic;
  signal e_x,     e_y : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal e_low        : std_logic;
  signal e_code       : std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
  signal s_valid      : std_logic;
  signal s_keep       : std_logic;
  signal s_slot       : std_logic_vector(SEL_SLOT_BITS_c - 1 downto 0);
  signal s_new        : std_logic;
  -- the candidates' queue (at most one out every second clock) and the selection's inputs
  signal cq           : cand_q_t := (others => (others => '0'));
  signal cq_n         : natural range 0 to 2 := 0;
  signal cq_fed       : std_logic := '0';  -- the selection took a candidate in the last clock
  signal q_valid      : std_logic;
  signal q_x,     q_y : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal q_low        : std_logic;
  signal q_code       : std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
  -- the decisions' FIFO
  signal dq    : dec_fifo_t := (others => (others => '0'));
  signal dq_wr : unsigned(3 downto 0) := (others => '0');
  signal dq_rd : unsigned(3 downto 0) := (others => '0');

  signal f_valid      : std_logic := '0';
  signal f_done       : std_logic := '0';
  signal f_x,     f_y : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal f_score      : std_logic_vector(SCORE_BITS_c - 1 downto 0) := (others => '0');
  signal f_low        : std_logic := '0';
  signal f_code       : std_logic_vector(RESPONSE_BITS_c - 1 downto 0) := (others => '0');
  signal f_sector     : std_logic_vector(5 downto 0) := (others => '0');
  signal f_desc       : std_logic_vector(255 downto 0) := (others => '0');
  signal f_slot       : unsigned(FEAT_SEL_SLOT_BITS_c - 1 downto 0) := (others => '0');
  signal f_repl       : std_logic := '0';

begin

  assert BASE_g + SLOTS_g <= 2 ** FEAT_SEL_SLOT_BITS_c
    report "orb_scale_path: BASE_g + SLOTS_g must fit the feature word's sel_slot field"
    severity failure;

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
      feat_low     => d_low,
      feat_code    => d_code,
      frame_done   => d_done,
      win_valid    => w_valid,
      win_x        => w_x,
      win_y        => w_y,
      win_data     => w_win
    );

  gen_desc : if HAS_DESC_c generate
    signal m_valid  : std_logic;
    signal m_x, m_y : std_logic_vector(COORD_BITS_c - 1 downto 0);
    signal m_data   : std_logic_vector(PIXEL_BITS_c - 1 downto 0);
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
        out_valid => m_valid,
        out_x     => m_x,
        out_y     => m_y,
        out_data  => m_data
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
        in_valid    => m_valid,
        in_x        => m_x,
        in_y        => m_y,
        in_data     => m_data,
        det_valid   => d_valid,
        det_x       => d_x,
        det_y       => d_y,
        det_score   => d_score,
        det_low     => d_low,
        det_code    => d_code,
        cand_valid  => c_valid,
        cand_x      => c_x,
        cand_y      => c_y,
        cand_low    => c_low,
        cand_code   => c_code,
        feat_valid  => o_valid,
        feat_x      => o_x,
        feat_y      => o_y,
        feat_score  => o_score,
        feat_low    => o_low,
        feat_code   => o_code,
        feat_sector => o_sector,
        feat_desc   => o_desc,
        frame_done  => o_done,
        lost        => o_lost
      );

  else generate
    o_valid <= '0';
    c_valid <= '0';
    o_done  <= d_done;
    o_lost  <= (others => '0');
  end generate gen_desc;

  p_grid   <= grids(to_integer(sel_rd));
  p_budget <= budgets(to_integer(sel_rd));
  p_cells  <= cells(to_integer(sel_rd));

  fast_on <= not modes(to_integer(mode_rd_d));
  orb_on  <= modes(to_integer(mode_rd_o));

  -- the candidates of the frame being reported: the descriptor path's (orb) or the survivors
  -- (fast); the two paths never report in one clock
  e_valid <= (c_valid and orb_on) or (d_valid and fast_on);
  e_x     <= c_x when c_valid = '1' and orb_on = '1' else
             d_x;
  e_y     <= c_y when c_valid = '1' and orb_on = '1' else
             d_y;
  e_low   <= c_low when c_valid = '1' and orb_on = '1' else
             d_low;
  e_code  <= c_code when c_valid = '1' and orb_on = '1' else
             d_code;

  selection : entity work.orb_feat_select
    generic map (
      SLOTS_g       => SLOTS_g,
      FULL_WIDTH_g  => FULL_WIDTH_g,
      FULL_HEIGHT_g => FULL_HEIGHT_g,
      STEP_NUM_g    => STEP_NUM_g,
      STEP_DEN_g    => STEP_DEN_g,
      LEVEL_g       => LEVEL_g
    )
    port map (
      clk       => clk,
      rst       => rst,
      grid      => p_grid,
      budget    => p_budget,
      cols      => p_cells(2 * GRID_BITS_c - 1 downto GRID_BITS_c),
      rows      => p_cells(GRID_BITS_c - 1 downto 0),
      in_valid  => q_valid,
      in_x      => q_x,
      in_y      => q_y,
      in_low    => q_low,
      in_code   => q_code,
      in_done   => f_done,
      out_valid => s_valid,
      out_keep  => s_keep,
      out_slot  => s_slot,
      out_new   => s_new
    );

  -- the queue's head goes to the selection when the selection did not take one in the last clock
  q_valid <= '1' when cq_n /= 0 and cq_fed = '0' else
             '0';
  q_x     <= cq(0)(CW_c - 1 downto CW_c - COORD_BITS_c);
  q_y     <= cq(0)(CW_c - COORD_BITS_c - 1 downto RESPONSE_BITS_c + 1);
  q_low   <= cq(0)(RESPONSE_BITS_c);
  q_code  <= cq(0)(RESPONSE_BITS_c - 1 downto 0);

  -- the fast path's survivors and frame ends wait CAND_LEAD_LAT_c clocks (a fixed latency in clocks);
  -- the candidates' queue; the decisions' FIFO, pushed by the selection, popped by each feature
  waits : process (clk) is
    variable word : std_logic_vector(CW_c - 1 downto 0);
    variable n    : natural range 0 to 3;
    variable q    : cand_q_t;
  begin
    if rising_edge(clk) then
      fd_valid <= d_valid & fd_valid(1 to CAND_LEAD_LAT_c - 1);
      fd_done  <= d_done & fd_done(1 to CAND_LEAD_LAT_c - 1);
      fd_data  <= std_logic_vector'(d_x & d_y & d_score & d_low & d_code) & fd_data(1 to CAND_LEAD_LAT_c - 1);
      word     := e_x & e_y & e_low & e_code;
      q        := cq;
      n        := cq_n;
      if q_valid = '1' then  -- the head leaves
        q(0) := q(1);
        n    := n - 1;
      end if;
      if e_valid = '1' then
        -- pragma translate_off
        assert n < 2
          report "orb_scale_path: the candidates' queue overflows (more than two in a row)"
          severity failure;
        -- pragma translate_on
        q(n) := word;
        n    := n + 1;
      end if;
      cq     <= q;
      cq_n   <= n;
      cq_fed <= q_valid;
      if s_valid = '1' then
        dq(to_integer(dq_wr)) <= s_keep & s_new & s_slot;
        dq_wr                 <= dq_wr + 1;
      end if;
      if rst = '1' then
        fd_valid <= (others => '0');
        fd_done  <= (others => '0');
        cq_n     <= 0;
        cq_fed   <= '0';
        dq_wr    <= (others => '0');
      end if;
    end if;
  end process waits;

  select_out : process (clk) is
    variable fw   : std_logic_vector(FW_c - 1 downto 0);
    variable dw   : std_logic_vector(DW_c - 1 downto 0);
    variable feat : std_logic;
    variable done : std_logic;
  begin
    if rising_edge(clk) then
      if in_valid = '1' and unsigned(in_x) = 0 and unsigned(in_y) = 0 then
        modes(to_integer(mode_wr))   <= mode_orb when DESC_g else '0';
        grids(to_integer(mode_wr))   <= select_grid;
        budgets(to_integer(mode_wr)) <= budget;
        cells(to_integer(mode_wr))   <= grid_cols & grid_rows;
        mode_wr                      <= mode_wr + 1;
      end if;
      -- the budget again at (0, 1): orb_core's split of the frame's budget is ready only after the
      -- frame's first pixels (no candidate is decided before line 1); constant indices, as GHDL 2.0
      -- synthesises variable-indexed writes into small arrays wrongly (docs/netlist-sim.md)
      if in_valid = '1' and unsigned(in_x) = 0 and unsigned(in_y) = 1 then
        for i in budgets_t'range loop
          if i = to_integer(mode_wr - 1) then
            budgets(i) <= budget;
          end if;
        end loop;
      end if;
      -- (the fast path's frame ends when its last survivor has left, CAND_LEAD_LAT_c clocks late)
      if fd_done(CAND_LEAD_LAT_c) = '1' then
        mode_rd_d <= mode_rd_d + 1;
      end if;
      if o_done = '1' then
        mode_rd_o <= mode_rd_o + 1;
      end if;
      -- the frame's features: the descriptor path's, or the survivors CAND_LEAD_LAT_c clocks late;
      -- each leaves when its decision (met here) keeps it
      fw   := fd_data(CAND_LEAD_LAT_c);
      dw   := dq(to_integer(dq_rd));
      feat := (fd_valid(CAND_LEAD_LAT_c) and fast_on) or (o_valid and orb_on);
      if feat = '1' then
        dq_rd <= dq_rd + 1;
      end if;
      done := (fd_done(CAND_LEAD_LAT_c) and fast_on) or (o_done and orb_on);
      f_valid <= feat and dw(DW_c - 1);
      f_done  <= done;
      f_repl  <= not dw(DW_c - 2);
      f_slot  <= to_unsigned(BASE_g, FEAT_SEL_SLOT_BITS_c) + unsigned(dw(SEL_SLOT_BITS_c - 1 downto 0));
      if done = '1' then
        sel_rd <= sel_rd + 1;
      end if;
      if o_valid = '1' and orb_on = '1' then
        f_x      <= o_x;
        f_y      <= o_y;
        f_score  <= o_score;
        f_low    <= o_low;
        f_code   <= o_code;
        f_sector <= o_sector;
        f_desc   <= o_desc;
      else
        f_x      <= fw(FW_c - 1 downto FW_c - COORD_BITS_c);
        f_y      <= fw(FW_c - COORD_BITS_c - 1 downto FW_c - 2 * COORD_BITS_c);
        f_score  <= fw(SCORE_BITS_c + RESPONSE_BITS_c downto RESPONSE_BITS_c + 1);
        f_low    <= fw(RESPONSE_BITS_c);
        f_code   <= fw(RESPONSE_BITS_c - 1 downto 0);
        f_sector <= (others => '0');
        f_desc   <= (others => '0');
      end if;
      -- pragma translate_off
      assert feat = '0' or dq_rd /= dq_wr
        report "orb_scale_path: a feature without its selection's decision (CAND_LEAD_LAT_c is wrong)"
        severity failure;
      assert not (c_valid = '1' and orb_on = '1' and d_valid = '1' and fast_on = '1')
        report "orb_scale_path: candidates of both paths in one clock"
        severity failure;
      -- pragma translate_on
      if rst = '1' then
        mode_wr   <= (others => '0');
        mode_rd_d <= (others => '0');
        mode_rd_o <= (others => '0');
        sel_rd    <= (others => '0');
        dq_rd     <= (others => '0');
        f_valid   <= '0';
        f_done    <= '0';
      end if;
    end if;
  end process select_out;

  feat_valid   <= f_valid;
  feat_x       <= f_x;
  feat_y       <= f_y;
  feat_score   <= f_score;
  feat_low     <= f_low;
  feat_code    <= f_code;
  feat_sector  <= f_sector;
  feat_desc    <= f_desc;
  feat_slot    <= std_logic_vector(f_slot);
  feat_replace <= f_repl;
  frame_done   <= f_done;
  lost         <= o_lost;

end architecture rtl;
