-- SPDX-License-Identifier: MIT
-- orb_core: the accelerator's streaming core, detection and description, for SCALES_g
-- scales (pyramid levels). Pixels enter as AXI4-Stream video (8-bit luma, tuser = start of frame,
-- tlast = end of line) at up to one per clock; tready is high whenever not in reset, since a video
-- source cannot be stalled. Scale 0 is the input; each further scale is the STEP_NUM_g:STEP_DEN_g
-- reduction of the previous one: an orb_scaler (the 2x2 box) for 2:1, an orb_resampler
-- (fixed-phase bilinear) for any other step, each a streaming path at its fraction of the pixel
-- rate with no frame buffer (docs/spec.md section 3, docs/pyramid.md). Each scale's
-- orb_scale_path reports, per frame, either every NMS survivor (fast mode, mode_orb = 0) or
-- every survivor inside the descriptor border with its sector and 256-bit rBRIEF descriptor
-- (orb mode, mode_orb = 1; needs DESC_g = true, which builds the descriptor path), each
-- scale's selection (orb_feat_select: in grid mode, select_grid = 1, every frame keeps at most
-- `budget` features, split over the scales as docs/spec.md section 14 says, each scale's share
-- spread over a grid of grid_cols x grid_rows cells over the frame; in all mode every feature), merged by orb_feat_merge
-- into m_axis_feat (layout in orb_feat_pkg) with an end-of-frame beat after each frame; the
-- descriptor paths leave their tests unrotated and one orb_desc_rotate after the merge applies
-- every feature's orbit rotation. The FAST thresholds, the mode and the selection's parameters
-- are sampled with each frame's first pixel (tuser) and hold for every scale of that frame; the
-- budget's split is computed from the sampled budget in the core_split_lat(SCALES_g) =
-- 3 SCALES_g + 1 clocks after it (orb_latency_pkg, docs/latency.md) and the scale paths take
-- their share at their pixel (0, 1). The sampled values also wait, one entry per frame in flight
-- (PARAM_FRAMES_c = 4, as the scale paths' per-frame queues), from the frame's first pixel to its
-- end-of-frame beat, which carries them (orb_feat_pkg's EOF_ fields, written as the beat leaves
-- the core): each frame says how it was made, whatever was written since
-- (docs/feature-memory.md). Pixels
-- outside the configured WIDTH_g x HEIGHT_g frame (a long line or extra lines) are ignored and
-- counted in bad_pixels; features the descriptor path had to discard (only on a malformed frame)
-- are counted in desc_lost.
-- Ports and generics: docs/entities/orb_core.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_feat_pkg.all;
use work.orb_limits_pkg.all;

entity orb_core is
  generic (
    WIDTH_g      : width_t                 := 640;
    HEIGHT_g     : height_t                := 480;
    SCALES_g     : scales_t                := 1;
    STEP_NUM_g   : step_num_t              := 2;  -- pyramid step STEP_NUM_g:STEP_DEN_g
    STEP_DEN_g   : step_den_t              := 1;
    FIFO_DEPTH_g : positive range 2 to 512 := 32;
    SECTORS_g    : sectors_t               := 32; -- orientation sectors in all (orb_limits_pkg)
    DESC_g       : boolean                 := true;
    -- the largest budget: the feature memory's capacity (each scale's selection is sized for it)
    BUDGET_MAX_g : positive range 1 to 4095 := 1023
  );
  port (
    clk                 : in    std_logic;
    rst                 : in    std_logic;
    s_axis_video_tdata  : in    std_logic_vector(7 downto 0);
    s_axis_video_tvalid : in    std_logic;
    s_axis_video_tready : out   std_logic;
    s_axis_video_tuser  : in    std_logic;
    s_axis_video_tlast  : in    std_logic;
    threshold           : in    std_logic_vector(7 downto 0);
    threshold_lo        : in    std_logic_vector(7 downto 0);
    mode_orb            : in    std_logic;
    select_grid         : in    std_logic;
    budget              : in    std_logic_vector(SEL_SLOT_BITS_c - 1 downto 0);
    grid_cols           : in    std_logic_vector(GRID_BITS_c - 1 downto 0);
    grid_rows           : in    std_logic_vector(GRID_BITS_c - 1 downto 0);
    m_axis_feat_tdata   : out   std_logic_vector(FEAT_BITS_c - 1 downto 0);
    m_axis_feat_tvalid  : out   std_logic;
    m_axis_feat_tready  : in    std_logic;
    m_axis_feat_tlast   : out   std_logic;
    dropped             : out   std_logic_vector(31 downto 0);
    bad_pixels          : out   std_logic_vector(31 downto 0);
    desc_lost           : out   std_logic_vector(31 downto 0)
  );
end entity orb_core;

architecture rtl of orb_core is

  type coord_arr_t is array (0 to SCALES_g - 1) of std_logic_vector(COORD_BITS_c - 1 downto 0);
  type pixel_arr_t is array (0 to SCALES_g - 1) of std_logic_vector(PIXEL_BITS_c - 1 downto 0);

  -- position of the next input pixel
  signal next_x  : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal next_y  : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal bad_cnt : unsigned(31 downto 0) := (others => '0');
  signal ready   : std_logic := '0';
  signal thr_frm : std_logic_vector(7 downto 0) := (others => '0');

  -- per-scale pixel streams (index 0: the input, registered)
  signal px_valid : std_logic_vector(SCALES_g - 1 downto 0) := (others => '0');
  signal px_x     : coord_arr_t := (others => (others => '0'));
  signal px_y     : coord_arr_t := (others => (others => '0'));
  signal px_data  : pixel_arr_t := (others => (others => '0'));

  signal f_valid : std_logic_vector(SCALES_g - 1 downto 0);
  signal f_done  : std_logic_vector(SCALES_g - 1 downto 0);
  signal f_x     : std_logic_vector(SCALES_g * COORD_BITS_c - 1 downto 0);
  signal f_y     : std_logic_vector(SCALES_g * COORD_BITS_c - 1 downto 0);
  signal f_score : std_logic_vector(SCALES_g * SCORE_BITS_c - 1 downto 0);
  signal f_sect  : std_logic_vector(SCALES_g * FEAT_SECTOR_BITS_c - 1 downto 0);
  signal f_desc  : std_logic_vector(SCALES_g * DESC_BITS_c - 1 downto 0);
  signal f_low   : std_logic_vector(SCALES_g - 1 downto 0);
  signal f_code  : std_logic_vector(SCALES_g * FEAT_RESPONSE_BITS_c - 1 downto 0);
  signal f_slot  : std_logic_vector(SCALES_g * FEAT_SEL_SLOT_BITS_c - 1 downto 0);
  signal f_repl  : std_logic_vector(SCALES_g - 1 downto 0);

  type lost_arr_t is array (0 to SCALES_g - 1) of std_logic_vector(31 downto 0);

  signal lost     : lost_arr_t;
  signal lost_q   : unsigned(31 downto 0) := (others => '0');
  signal mode_frm : std_logic := '0';

  -- the selection's parameters: formed from the inputs (live), sampled with tuser (frm)
  type split_t is array (0 to SCALES_g - 1) of unsigned(SEL_SLOT_BITS_c - 1 downto 0);
  type fraction_t is array (0 to SCALES_g - 1) of unsigned(16 downto 0);

  function fractions return fraction_t is
    variable f : fraction_t;
  begin
    for k in 0 to SCALES_g - 1 loop
      f(k) := to_unsigned(split_fraction(STEP_NUM_g, STEP_DEN_g, SCALES_g, k), 17);
    end loop;
    return f;
  end function fractions;

  constant FRACTIONS_c : fraction_t  := fractions;

  -- the split's phases per level (process split: the product, its rounding, the share)
  subtype split_phase_t is natural range 0 to 2;

  signal split_live : split_t := (others => (others => '0'));
  signal split_work : split_t := (others => (others => '0'));
  -- the budget of the frame (sampled with its start of frame), and the split's restart on it
  signal budget_frm : std_logic_vector(SEL_SLOT_BITS_c - 1 downto 0) := (others => '0');
  signal sp_restart : std_logic := '0';
  signal sp_k       : natural range 0 to SCALES_g - 1 := 0;
  signal sp_phase   : split_phase_t := 0;
  signal sp_n       : unsigned(SEL_SLOT_BITS_c - 1 downto 0) := (others => '0');  -- the budget being split
  signal sp_rem     : unsigned(SEL_SLOT_BITS_c - 1 downto 0) := (others => '0');  -- N - the levels before
  signal sp_round   : unsigned(SEL_SLOT_BITS_c + 1 downto 0) := (others => '0');   -- (N F_k + 2^15) >> 16
  signal sp_prod    : unsigned(SEL_SLOT_BITS_c + 16 downto 0) := (others => '0');
  signal cols_frm   : std_logic_vector(GRID_BITS_c - 1 downto 0) := (others => '0');
  signal rows_frm   : std_logic_vector(GRID_BITS_c - 1 downto 0) := (others => '0');
  signal grid_frm   : std_logic := '0';
  signal tlo_frm    : std_logic_vector(7 downto 0) := (others => '0');

  -- The parameters of each frame in flight (docs/feature-word.md, the end-of-frame beat): pushed
  -- with the values sampled at the frame's start of frame, popped when its end-of-frame beat leaves
  -- the core (written into the beat after the orbit rotation, so that nothing is added in front of
  -- the rotator; orb_feat_mem registers the word at its input). Every start of frame has one
  -- end-of-frame beat (orb_video_check completes every frame; orb_feat_mem never stalls the stream,
  -- so the merge never joins two frame ends), in order.
  type frame_params_t is record
    threshold    : std_logic_vector(7 downto 0);
    threshold_lo : std_logic_vector(7 downto 0);
    mode_orb     : std_logic;
    select_grid  : std_logic;
    budget       : std_logic_vector(SEL_SLOT_BITS_c - 1 downto 0);
    cols         : std_logic_vector(GRID_BITS_c - 1 downto 0);
    rows         : std_logic_vector(GRID_BITS_c - 1 downto 0);
  end record frame_params_t;

  constant PARAM_FRAMES_c : positive := 4;

  type param_q_t is array (0 to PARAM_FRAMES_c - 1) of frame_params_t;

  signal prm_q : param_q_t := (others => ((others => '0'), (others => '0'), '0', '0', (others => '0'),
                                          (others => '0'), (others => '0')));
  -- frames pushed and popped, mod 8: entry (count mod 4); their difference is the frames in flight
  signal prm_wr   : unsigned(2 downto 0) := (others => '0');
  signal prm_rd   : unsigned(2 downto 0) := (others => '0');
  signal prm_head : frame_params_t;
  -- an end-of-frame beat offered and not taken keeps the parameters it was offered with
  -- (AXI4-Stream: its data is held until taken, whatever the queue does meanwhile)
  signal eof_waiting : std_logic := '0';
  signal prm_hold    : frame_params_t := ((others => '0'), (others => '0'), '0', '0', (others => '0'),
                                          (others => '0'), (others => '0'));
  signal prm_out     : frame_params_t;

  -- the merged stream, before the shared orbit rotation
  signal mg_tdata  : std_logic_vector(FEAT_BITS_c - 1 downto 0);
  signal mg_tvalid : std_logic;
  signal mg_tready : std_logic;
  signal mg_tlast  : std_logic;
  -- the output stream before the end-of-frame beat gets its frame's parameters
  signal out_word   : std_logic_vector(FEAT_BITS_c - 1 downto 0);
  signal out_tvalid : std_logic;
  signal out_tlast  : std_logic;

begin

  assert scale_width_legal(level_size(WIDTH_g, STEP_NUM_g, STEP_DEN_g, SCALES_g - 1))
    report "orb_core: the smallest scale must be at least " & SCALE_WIDTH_TEXT_c & " pixels wide"
    severity failure;

  assert scale_height_legal(level_size(HEIGHT_g, STEP_NUM_g, STEP_DEN_g, SCALES_g - 1))
    report "orb_core: the smallest scale must have at least " & SCALE_HEIGHT_TEXT_c & " lines"
    severity failure;

  assert step_den_legal(STEP_DEN_g) and STEP_DEN_g < STEP_NUM_g and STEP_NUM_g <= 2 * STEP_DEN_g
    report "orb_core: the pyramid step STEP_NUM_g:STEP_DEN_g needs STEP_DEN_g a power of two and "
           & "STEP_DEN_g < STEP_NUM_g <= 2 * STEP_DEN_g"
    severity failure;

  assert WIDTH_g > core_split_lat(SCALES_g)
    report "orb_core: the budget's split must be ready before level 0's pixel (0, 1)"
    severity failure;

  -- the split takes split_phase_t's phases per level after one clock to restart
  assert core_split_lat(SCALES_g) = (split_phase_t'high + 1) * SCALES_g + 1
    report "orb_core: core_split_lat (orb_latency_pkg) must be the split's clocks"
    severity failure;

  assert EOF_BUDGET_BITS_c = SEL_SLOT_BITS_c and EOF_COLS_BITS_c = GRID_BITS_c and EOF_ROWS_BITS_c = GRID_BITS_c
    report "orb_core: the end-of-frame beat's budget, cols and rows must be as wide as the inputs (orb_feat_pkg)"
    severity failure;

  assert sectors_legal(SECTORS_g)
    report "orb_core: SECTORS_g (sectors in all) must be " & SECTORS_TEXT_c
    severity failure;

  s_axis_video_tready <= ready;

  -- Input registers and frame position: tuser marks (0, 0), tlast ends a line.
  input : process (clk) is
    variable x, y : unsigned(COORD_BITS_c - 1 downto 0);
  begin
    if rising_edge(clk) then
      ready       <= '1';
      px_valid(0) <= '0';
      sp_restart  <= '0';
      if s_axis_video_tvalid = '1' and ready = '1' then
        if s_axis_video_tuser = '1' then
          sp_restart <= '1';
          x := (others => '0');
          y := (others => '0');
        else
          x := next_x;
          y := next_y;
        end if;
        if s_axis_video_tuser = '1' then
          thr_frm   <= threshold;  -- the whole frame, every scale, uses these values
          mode_frm  <= mode_orb;
          grid_frm  <= select_grid;
          budget_frm <= budget;
          cols_frm   <= grid_cols;
          rows_frm   <= grid_rows;
          -- the frame's parameters wait for its end-of-frame beat (constant-index writes, as GHDL
          -- 2.0 synthesises a variable-indexed write into a small array wrongly: docs/netlist-sim.md)
          for i in param_q_t'range loop
            if i = to_integer(prm_wr(1 downto 0)) then
              prm_q(i) <= (threshold, threshold_lo, mode_orb, select_grid, budget, grid_cols, grid_rows);
            end if;
          end loop;
          prm_wr <= prm_wr + 1;
          -- pragma translate_off
          assert prm_wr - prm_rd < PARAM_FRAMES_c
            report "orb_core: more than PARAM_FRAMES_c frames in flight (their parameters are lost)"
            severity failure;
          -- pragma translate_on
          -- all mode reports main corners only: no low threshold
          if select_grid = '1' then
            tlo_frm <= threshold_lo;
          else
            tlo_frm <= threshold;
          end if;
        end if;
        if x < WIDTH_g and y < HEIGHT_g then
          px_valid(0) <= '1';
          px_x(0)     <= std_logic_vector(x);
          px_y(0)     <= std_logic_vector(y);
          px_data(0)  <= s_axis_video_tdata;
        else
          bad_cnt <= bad_cnt + 1;
        end if;
        if s_axis_video_tlast = '1' then
          next_x <= (others => '0');
          next_y <= y + 1;
        elsif x /= 2 ** COORD_BITS_c - 1 then
          next_x <= x + 1;
          next_y <= y;
        end if;
      end if;
      if rst = '1' then
        ready       <= '0';
        px_valid(0) <= '0';
        next_x      <= (others => '0');
        next_y      <= (others => '0');
        bad_cnt     <= (others => '0');
        prm_wr      <= (others => '0');
      end if;
    end if;
  end process input;

  -- a frame's parameters leave the queue with its end-of-frame beat
  params_out : process (clk) is
  begin
    if rising_edge(clk) then
      if out_tvalid = '1' and m_axis_feat_tready = '1' and out_tlast = '1' then
        prm_rd <= prm_rd + 1;
      end if;
      eof_waiting <= out_tvalid and out_tlast and not m_axis_feat_tready;
      prm_hold    <= prm_out;
      -- pragma translate_off
      assert not (out_tvalid = '1' and out_tlast = '1' and prm_rd = prm_wr)
        report "orb_core: an end-of-frame beat without its frame's parameters"
        severity failure;
      -- pragma translate_on
      if rst = '1' then
        prm_rd      <= (others => '0');
        eof_waiting <= '0';
      end if;
    end if;
  end process params_out;

  prm_head <= prm_q(to_integer(prm_rd(1 downto 0)));
  prm_out  <= prm_hold when eof_waiting = '1' else
              prm_head;

  -- the end-of-frame beat with its frame's parameters in its EOF_ fields (0 in the merge's word)
  eof_params : process (all) is
    variable word_v : std_logic_vector(FEAT_BITS_c - 1 downto 0);
  begin
    word_v := out_word;
    if out_tlast = '1' then
      word_v(EOF_THRESHOLD_LO_c + EOF_THRESHOLD_BITS_c - 1 downto EOF_THRESHOLD_LO_c) := prm_out.threshold;
      word_v(EOF_TLO_LO_c + EOF_TLO_BITS_c - 1 downto EOF_TLO_LO_c)                   := prm_out.threshold_lo;
      word_v(EOF_MODE_ORB_BIT_c)                                                      := prm_out.mode_orb;
      word_v(EOF_SELECT_GRID_BIT_c)                                                   := prm_out.select_grid;
      word_v(EOF_BUDGET_LO_c + EOF_BUDGET_BITS_c - 1 downto EOF_BUDGET_LO_c)          := prm_out.budget;
      word_v(EOF_COLS_LO_c + EOF_COLS_BITS_c - 1 downto EOF_COLS_LO_c)                := prm_out.cols;
      word_v(EOF_ROWS_LO_c + EOF_ROWS_BITS_c - 1 downto EOF_ROWS_LO_c)                := prm_out.rows;
    end if;
    m_axis_feat_tdata <= word_v;
  end process eof_params;

  m_axis_feat_tvalid <= out_tvalid;
  m_axis_feat_tlast  <= out_tlast;

  -- The budget's split (docs/spec.md section 14), level after level, three clocks each (the
  -- product, its rounding, the minimum and the remainder: one carry chain per clock), over and
  -- over: n_k = min((N F_k + 2^15) >> 16, N - the levels before), the last level the rest; a whole
  -- new split replaces split_live at once. N is the frame's budget (sampled with its start of
  -- frame, at most BUDGET_MAX_g); the split restarts on every start of frame, so split_live holds
  -- the frame's split core_split_lat(SCALES_g) clocks after it, before any level's pixel (0, 1)
  -- (the scale paths take their budget there: orb_scale_path).
  split : process (clk) is
    variable n     : unsigned(SEL_SLOT_BITS_c - 1 downto 0);
    variable share : unsigned(SEL_SLOT_BITS_c - 1 downto 0);
    variable fin   : split_t;
  begin
    if rising_edge(clk) then
      if sp_restart = '1' then
        sp_k     <= 0;
        sp_phase <= 0;
      elsif sp_phase = 0 then
        if sp_k = 0 then
          n := unsigned(budget_frm);
          if n > BUDGET_MAX_g then
            n := to_unsigned(BUDGET_MAX_g, SEL_SLOT_BITS_c);
          end if;
          sp_n   <= n;
          sp_rem <= n;
        else
          n := sp_n;
        end if;
        sp_prod  <= resize(n * FRACTIONS_c(sp_k), sp_prod'length);
        sp_phase <= 1;
      elsif sp_phase = 1 then
        sp_round <= resize(shift_right(sp_prod + 2 ** 15, 16), sp_round'length);
        sp_phase <= 2;
      else
        sp_phase <= 0;
        if sp_k = SCALES_g - 1 or sp_round > sp_rem then
          share := sp_rem;
        else
          share := resize(sp_round, SEL_SLOT_BITS_c);
        end if;
        -- constant-index writes under a compare: GHDL 2.0 synthesises a variable-indexed write
        -- into a small array as a constant (docs/netlist-sim.md)
        fin := split_work;
        for k in 0 to SCALES_g - 1 loop
          if k = sp_k then
            fin(k)        := share;
            split_work(k) <= share;
          end if;
        end loop;
        sp_rem           <= sp_rem - share;
        if sp_k = SCALES_g - 1 then
          sp_k       <= 0;
          split_live <= fin;
        else
          sp_k <= sp_k + 1;
        end if;
      end if;
    end if;
  end process split;

  scales : for s in 0 to SCALES_g - 1 generate

    has_box : if s > 0 and STEP_NUM_g = 2 * STEP_DEN_g generate
      scaler : entity work.orb_scaler
        generic map (
          LINE_WIDTH_g => level_size(WIDTH_g, STEP_NUM_g, STEP_DEN_g, s - 1)
        )
        port map (
          clk       => clk,
          rst       => rst,
          in_valid  => px_valid(s - 1),
          in_x      => px_x(s - 1),
          in_y      => px_y(s - 1),
          in_data   => px_data(s - 1),
          out_valid => px_valid(s),
          out_x     => px_x(s),
          out_y     => px_y(s),
          out_data  => px_data(s)
        );
    end generate has_box;

    has_resampler : if s > 0 and STEP_NUM_g /= 2 * STEP_DEN_g generate
      resampler : entity work.orb_resampler
        generic map (
          LINE_WIDTH_g => level_size(WIDTH_g, STEP_NUM_g, STEP_DEN_g, s - 1),
          LINE_COUNT_g => level_size(HEIGHT_g, STEP_NUM_g, STEP_DEN_g, s - 1),
          NUM_g        => STEP_NUM_g,
          DEN_g        => STEP_DEN_g
        )
        port map (
          clk       => clk,
          rst       => rst,
          in_valid  => px_valid(s - 1),
          in_x      => px_x(s - 1),
          in_y      => px_y(s - 1),
          in_data   => px_data(s - 1),
          out_valid => px_valid(s),
          out_x     => px_x(s),
          out_y     => px_y(s),
          out_data  => px_data(s)
        );
    end generate has_resampler;

    -- ROTATE_g false: one orb_desc_rotate after the merge serves every scale
    path : entity work.orb_scale_path
      generic map (
        LINE_WIDTH_g   => level_size(WIDTH_g, STEP_NUM_g, STEP_DEN_g, s),
        FRAME_HEIGHT_g => level_size(HEIGHT_g, STEP_NUM_g, STEP_DEN_g, s),
        SECTORS_g      => SECTORS_g,
        DESC_g         => DESC_g,
        ROTATE_g       => false,
        SLOTS_g        => level_slots(BUDGET_MAX_g, STEP_NUM_g, STEP_DEN_g, SCALES_g, s),
        BASE_g         => level_base(BUDGET_MAX_g, STEP_NUM_g, STEP_DEN_g, SCALES_g, s),
        FULL_WIDTH_g   => WIDTH_g,
        FULL_HEIGHT_g  => HEIGHT_g,
        STEP_NUM_g     => STEP_NUM_g,
        STEP_DEN_g     => STEP_DEN_g,
        LEVEL_g        => s
      )
      port map (
        clk          => clk,
        rst          => rst,
        threshold    => thr_frm,
        threshold_lo => tlo_frm,
        select_grid  => grid_frm,
        budget       => std_logic_vector(split_live(s)),
        grid_cols    => cols_frm,
        grid_rows    => rows_frm,
        mode_orb     => mode_frm,
        in_valid     => px_valid(s),
        in_x         => px_x(s),
        in_y         => px_y(s),
        in_data      => px_data(s),
        feat_valid   => f_valid(s),
        feat_x       => f_x((s + 1) * COORD_BITS_c - 1 downto s * COORD_BITS_c),
        feat_y       => f_y((s + 1) * COORD_BITS_c - 1 downto s * COORD_BITS_c),
        feat_score   => f_score((s + 1) * SCORE_BITS_c - 1 downto s * SCORE_BITS_c),
        feat_low     => f_low(s),
        feat_code    => f_code((s + 1) * FEAT_RESPONSE_BITS_c - 1 downto s * FEAT_RESPONSE_BITS_c),
        feat_slot    => f_slot((s + 1) * FEAT_SEL_SLOT_BITS_c - 1 downto s * FEAT_SEL_SLOT_BITS_c),
        feat_replace => f_repl(s),
        feat_sector  => f_sect((s + 1) * FEAT_SECTOR_BITS_c - 1 downto s * FEAT_SECTOR_BITS_c),
        feat_desc    => f_desc((s + 1) * DESC_BITS_c - 1 downto s * DESC_BITS_c),
        frame_done   => f_done(s),
        lost         => lost(s)
      );

  end generate scales;

  merge : entity work.orb_feat_merge
    generic map (
      SCALES_g     => SCALES_g,
      FIFO_DEPTH_g => FIFO_DEPTH_g,
      DESC_g       => DESC_g
    )
    port map (
      clk                => clk,
      rst                => rst,
      in_valid           => f_valid,
      in_x               => f_x,
      in_y               => f_y,
      in_score           => f_score,
      in_low             => f_low,
      in_code            => f_code,
      in_slot            => f_slot,
      in_replace         => f_repl,
      in_sector          => f_sect,
      in_desc            => f_desc,
      in_done            => f_done,
      m_axis_feat_tdata  => mg_tdata,
      m_axis_feat_tvalid => mg_tvalid,
      m_axis_feat_tready => mg_tready,
      m_axis_feat_tlast  => mg_tlast,
      dropped            => dropped
    );

  -- The scales' descriptors leave unrotated (sector-0 tests); one rotation stage serves them all.
  gen_rotate : if DESC_g generate

    rotate : entity work.orb_desc_rotate
      generic map (
        SECTORS_g => SECTORS_g
      )
      port map (
        clk                => clk,
        rst                => rst,
        s_axis_feat_tdata  => mg_tdata,
        s_axis_feat_tvalid => mg_tvalid,
        s_axis_feat_tready => mg_tready,
        s_axis_feat_tlast  => mg_tlast,
        m_axis_feat_tdata  => out_word,
        m_axis_feat_tvalid => out_tvalid,
        m_axis_feat_tready => m_axis_feat_tready,
        m_axis_feat_tlast  => out_tlast
      );

  else generate

    out_word   <= mg_tdata;
    out_tvalid <= mg_tvalid;
    out_tlast  <= mg_tlast;
    mg_tready  <= m_axis_feat_tready;

  end generate gen_rotate;

  bad_pixels <= std_logic_vector(bad_cnt);

  -- features the descriptor paths discarded (malformed frames only), all scales
  lost_sum : process (clk) is
    variable acc : unsigned(31 downto 0);
  begin
    if rising_edge(clk) then
      acc := (others => '0');
      for s in 0 to SCALES_g - 1 loop
        acc := acc + unsigned(lost(s));
      end loop;
      lost_q <= acc;
    end if;
  end process lost_sum;

  desc_lost <= std_logic_vector(lost_q);

end architecture rtl;
