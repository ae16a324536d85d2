-- SPDX-License-Identifier: MIT
-- orb_desc_path: the description path of one scale (docs/spec.md sections 7 to 10, orb mode):
-- sector and 256-bit rBRIEF descriptor for every NMS survivor inside the descriptor border, one
-- evaluation per clock, never stalling and never dropping on a legal stream. The smoothed stream
-- (orb_smooth's output: the value tagged (x, y) is the smoothed pixel (x - 3, y - 3)) fills a
-- 30-line block-RAM buffer whose columns slide through a 31x31 register window; the window tagged
-- (x, y) is centred on (x - 18, y - 18). The same columns feed orb_orient_moments (incremental
-- moments of the radius-15 circle) and orb_orient_sector. Detected features wait in a block-RAM
-- FIFO (in raster order, as the window visits them) until the window reaches them: the 256 tests
-- of the orbit pattern's sector-0 table (orb_pattern_pkg) are evaluated on the window in that
-- clock, and when the feature's sector s arrives the bits of each orbit of 4N tests are rotated
-- by s, which gives the sector-s pattern's descriptor (with ROTATE_g = false the sector-0 tests
-- leave unrotated, beside their sector, and one orb_desc_rotate after the merge of the scales
-- rotates them: orb_core does so). The FIFO holds every feature that can be waiting at the
-- densest legal NMS output (see QDEPTH_c), so it cannot overflow; a feature whose window
-- position is never reached (a malformed frame) is discarded at the next frame start or once the
-- window has passed it, and counted in `lost`, as is one that found the FIFO full. Each feature
-- carries its score, response code and low flag (docs/spec.md sections 14 and 15) through; the
-- queue holds them in 36 bits (the window tag's x in 11 bits: at most 1919; its y modulo 64: a
-- waiting feature is never 32 lines or more from the window), and the full tag is the window's
-- own at the match. cand_* shows every described feature CAND_LEAD_LAT_c = 14 clocks (the
-- latency of the orientation, ORIENT_MOMENTS_LAT_c + ORIENT_SECTOR_LAT_c: orb_latency_pkg,
-- docs/latency.md) before it leaves on feat_*, for the level's selection (orb_feat_select).
-- Page: docs/rtl-description.md.
-- Ports and generics: docs/entities/orb_desc_path.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_pattern_pkg.all;
use work.orb_limits_pkg.all;
use work.orb_fast_pkg.all;

entity orb_desc_path is
  generic (
    LINE_WIDTH_g   : positive range 37 to 4095 := 640;
    FRAME_HEIGHT_g : positive range 37 to 4095 := 480;
    SECTORS_g      : sectors_t                 := 32;  -- orientation sectors in all
    -- false: feat_desc holds the sector-0 table's tests, for one shared orb_desc_rotate
    ROTATE_g : boolean := true
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic;
    -- smoothed stream, tagged like orb_smooth's output
    in_valid : in    std_logic;
    in_x     : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y     : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_data  : in    std_logic_vector(PIXEL_BITS_c - 1 downto 0);
    -- NMS survivors of the same frame, in raster order
    det_valid : in    std_logic;
    det_x     : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    det_y     : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    det_score : in    std_logic_vector(SCORE_BITS_c - 1 downto 0);
    det_low   : in    std_logic;
    det_code  : in    std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
    -- the described features, CAND_LEAD_LAT_c clocks ahead of feat_*
    cand_valid : out   std_logic;
    cand_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    cand_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    cand_low   : out   std_logic;
    cand_code  : out   std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
    -- described features, raster order
    feat_valid  : out   std_logic;
    feat_x      : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    feat_y      : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    feat_score  : out   std_logic_vector(SCORE_BITS_c - 1 downto 0);
    feat_low    : out   std_logic;
    feat_code   : out   std_logic_vector(RESPONSE_BITS_c - 1 downto 0);
    feat_sector : out   std_logic_vector(5 downto 0);
    feat_desc   : out   std_logic_vector(255 downto 0);
    frame_done  : out   std_logic;
    lost        : out   std_logic_vector(31 downto 0)
  );
end entity orb_desc_path;

architecture rtl of orb_desc_path is

  constant BORDER_c   : natural  := 18;   -- descriptor border, and the window's tag offset
  constant WIN_c      : positive := 31;
  constant COL_BITS_c : positive := WIN_c * PIXEL_BITS_c;
  constant N_c        : positive := SECTORS_g / 4;  -- sectors per quadrant (the thesis's N)
  constant ORBIT_c    : positive := SECTORS_g;      -- an orbit: one member per sector
  constant PAT_c      : pattern_t := base_pattern(N_c);
  -- Densest legal NMS output: one feature per 2x2 block, so ceil((W - 36) / 2) per line and
  -- per pair of lines. A feature waits from its detection (at least 4 lines after its own: the
  -- FAST window's centre, then the NMS) to its window (18 lines after): at most 14 lines, which
  -- hold at most 7 feature lines of the densest pattern plus two partial ones; 8 full lines are
  -- allowed, plus 40 entries of pipeline slack (the head register, a push in flight).
  constant ROW_FEATS_c : positive := (LINE_WIDTH_g - 2 * BORDER_c + 1) / 2;
  -- The queue's depth is that bound rounded up to whole 512-entry blocks (a RAMB18E1 holds 512
  -- entries of 36 bits), not to a power of two, so the pointers wrap at QDEPTH_c.
  constant QDEPTH_c : positive := ((8 * ROW_FEATS_c + 40 + 511) / 512) * 512;
  constant QBITS_c  : positive := clog2(QDEPTH_c);
  -- a queue entry: tag x (11 bits) & tag y mod 64 & score & code & low (36 bits: one RAMB18 per
  -- 512 entries); after the match the info: tag y & tag x (12 bits each) & score & code & low
  constant QX_c    : positive := 11;
  constant QY_c    : positive := 6;
  constant PAY_c   : positive := SCORE_BITS_c + RESPONSE_BITS_c + 1;  -- score & code & low
  constant ENTRY_c : positive := QX_c + QY_c + PAY_c;
  constant INFO_c  : positive := 2 * COORD_BITS_c + PAY_c;
  -- clocks from the column stage to the sector: orb_orient_moments, then orb_orient_sector; the
  -- tests are registered 2 clocks after the column stage, so they wait 2 clocks less
  constant ORIENT_LAT_c : positive := ORIENT_MOMENTS_LAT_c + ORIENT_SECTOR_LAT_c;
  constant WAIT_c       : positive := ORIENT_LAT_c - 2;

  subtype coord_t is unsigned(COORD_BITS_c - 1 downto 0);
  subtype entry_t is std_logic_vector(ENTRY_c - 1 downto 0);
  subtype info_t is std_logic_vector(INFO_c - 1 downto 0);
  subtype bits_t is std_logic_vector(255 downto 0);

  type win_t is array (0 to WIN_c - 1) of std_logic_vector(COL_BITS_c - 1 downto 0);
  type queue_t is array (0 to QDEPTH_c - 1) of entry_t;
  type wait_ram_t is array (0 to 15) of std_logic_vector(256 + INFO_c - 1 downto 0);

  -- column stage
  signal col_valid : std_logic;
  signal col_xs    : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal col_data  : std_logic_vector(COL_BITS_c - 1 downto 0);
  signal x_in      : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal y_in      : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal y_dly     : std_logic_vector(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal col_x     : coord_t;
  signal col_y     : coord_t;

  -- feature queue (block RAM) and its head register
  signal queue      : queue_t;
  signal wr_ptr     : unsigned(QBITS_c - 1 downto 0) := (others => '0');
  signal rd_ptr     : unsigned(QBITS_c - 1 downto 0) := (others => '0');
  signal pf         : entry_t := (others => '0');  -- the RAM's read register (prefetch)
  signal pf_valid   : std_logic := '0';
  signal pf2        : entry_t := (others => '0');  -- the entry after the head, in fabric flip-flops
  signal pf2_valid  : std_logic := '0';
  signal head       : entry_t := (others => '0');
  signal head_valid : std_logic := '0';
  signal hm_r       : boolean := false;  -- comparisons made a clock ahead (process `ahead`)
  signal hs_r       : boolean := false;
  signal pm_r       : boolean := false;
  signal ps_r       : boolean := false;
  signal took_r     : boolean := false;  -- the head took pf at the last edge
  signal match      : std_logic;
  signal stale      : std_logic;
  signal count      : unsigned(QBITS_c downto 0) := (others => '0');
  signal lost_q     : unsigned(QBITS_c + 1 downto 0) := (others => '0');
  signal lost_cnt   : unsigned(31 downto 0) := (others => '0');

  -- window stage (the window itself is a variable of the tests process)
  signal w_valid : std_logic := '0';
  signal w_match : std_logic := '0';
  signal w_info  : info_t := (others => '0');

  -- test stage
  signal t_valid : std_logic := '0';
  signal t_info  : info_t := (others => '0');
  signal t_bits  : bits_t := (others => '0');

  -- moments and sector, in step with the column stream
  signal m_valid      : std_logic;
  signal m_x,   m_y   : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal m_m10, m_m01 : std_logic_vector(23 downto 0);
  signal s_valid      : std_logic;
  signal s_x,   s_y   : std_logic_vector(COORD_BITS_c - 1 downto 0);
  signal s_sector     : std_logic_vector(5 downto 0);

  -- the feature flag of each column beside the moments pipeline (the sector is only computed for
  -- features), and the frame's last column beside the whole orientation pipeline
  signal feat_dly : std_logic_vector(1 to ORIENT_MOMENTS_LAT_c) := (others => '0');
  signal last_dly : std_logic_vector(1 to ORIENT_LAT_c)  := (others => '0');
  signal sec_in   : std_logic;

  -- tested features waiting for their sector: a 16-entry ring written at the clock count and
  -- read WAIT_c clocks later (distributed RAM; one write per feature, cheap to simulate too)
  signal wait_valid : std_logic_vector(1 to WAIT_c) := (others => '0');
  signal wait_ram   : wait_ram_t;
  signal wait_cnt   : unsigned(3 downto 0) := (others => '0');
  signal wait_out   : std_logic_vector(256 + INFO_c - 1 downto 0) := (others => '0');

  -- output stages
  signal o1_valid  : std_logic := '0';
  signal o1_last   : std_logic := '0';
  signal o1_info   : info_t;
  signal o1_bits   : bits_t;
  signal o1_sector : unsigned(5 downto 0) := (others => '0');
  signal o2_valid  : std_logic := '0';
  signal o2_last   : std_logic := '0';
  signal o2_info   : info_t := (others => '0');
  signal o2_desc   : bits_t := (others => '0');
  signal o2_sector : std_logic_vector(5 downto 0) := (others => '0');
  signal done_q    : std_logic := '0';

  function pixel (w : win_t; dx, dy : integer) return unsigned is
    constant K_c : natural := WIN_c - 1 - (15 + dy);  -- line-buffer slice: lines above the newest
  begin
    return unsigned(w(15 + dx)((K_c + 1) * PIXEL_BITS_c - 1 downto K_c * PIXEL_BITS_c));
  end function pixel;

  function b2n (b : std_logic) return natural is
  begin
    if b = '1' then
      return 1;
    end if;
    return 0;
  end function b2n;

  -- the queue pointer after p (the queue's depth need not be a power of two)
  function wrap_next (p : unsigned) return unsigned is
  begin
    if p = QDEPTH_c - 1 then
      return to_unsigned(0, p'length);
    end if;
    return p + 1;
  end function wrap_next;

  function pack (tx, ty : unsigned; score, code : std_logic_vector; low : std_logic) return entry_t is
  begin
    return std_logic_vector(tx(QX_c - 1 downto 0)) & std_logic_vector(ty(QY_c - 1 downto 0)) & score & code & low;
  end function pack;

  -- a tag y modulo 64 (hy) against the window's y (cy): the entry's line is before the window's
  -- (stale) when cy - hy mod 64 is 1 .. 31, the same when 0; a waiting feature is never 32 lines
  -- or more before or after the window
  function before (hy, cy : unsigned) return boolean is
    variable d : unsigned(QY_c - 1 downto 0);
  begin
    d := cy(QY_c - 1 downto 0) - hy;
    return d /= 0 and d(QY_c - 1) = '0';
  end function before;

begin

  assert sectors_legal(SECTORS_g)
    report "orb_desc_path: SECTORS_g (sectors in all) must be " & SECTORS_TEXT_c
    severity failure;

  assert 256 mod ORBIT_c = 0
    report "orb_desc_path: 256 tests must split into orbits of SECTORS_g"
    severity failure;

  assert LINE_WIDTH_g <= 2 ** QX_c
    report "orb_desc_path: LINE_WIDTH_g must be at most 2048 (the queue's 11-bit tag x)"
    severity failure;

  -- cand_* is shown at the column stage, feat_* leaves with the sector: the lead is ORIENT_LAT_c
  assert CAND_LEAD_LAT_c = ORIENT_LAT_c
    report "orb_desc_path: CAND_LEAD_LAT_c (orb_latency_pkg) must be the orientation's latency"
    severity failure;

  lines : entity work.orb_line_buffer
    generic map (
      LINE_WIDTH_g => LINE_WIDTH_g,
      LINES_g      => WIN_c - 1,
      DATA_WIDTH_g => PIXEL_BITS_c,
      LATENCY_g    => 2
    )
    port map (
      clk       => clk,
      rst       => rst,
      in_valid  => in_valid,
      in_col    => in_x,
      in_data   => in_data,
      out_valid => col_valid,
      out_col   => col_xs,
      out_data  => col_data
    );

  -- the line tag beside the buffer's two clocks: held over input gaps, then one clock more
  ytag : process (clk) is
  begin
    if rising_edge(clk) then
      if in_valid = '1' then
        x_in <= in_x;
        y_in <= in_y;
      end if;
      y_dly <= y_in;
    end if;
  end process ytag;

  col_x <= unsigned(col_xs);
  col_y <= unsigned(y_dly);

  -- Queue entries hold the window tag at which the feature is centred: (x + 18, y + 18). The
  -- comparisons of the head with the window's column are made one clock ahead, for both entries
  -- that can be the head then (the head itself, or pf2 if the head takes it in this clock),
  -- against the column the window has then (x_in, y_in: the line buffer's output register
  -- follows them by one clock); the clock itself only picks one (no comparator on the path from
  -- the head to the queue's state: docs/synthesis.md, "Timing").
  ahead : process (clk) is
    variable hx : coord_t;
    variable hy : unsigned(QY_c - 1 downto 0);
    variable px : coord_t;
    variable py : unsigned(QY_c - 1 downto 0);
    variable cx : coord_t;
    variable cy : coord_t;
  begin
    if rising_edge(clk) then
      hx    := resize(unsigned(head(ENTRY_c - 1 downto ENTRY_c - QX_c)), COORD_BITS_c);
      hy    := unsigned(head(ENTRY_c - QX_c - 1 downto PAY_c));
      px    := resize(unsigned(pf2(ENTRY_c - 1 downto ENTRY_c - QX_c)), COORD_BITS_c);
      py    := unsigned(pf2(ENTRY_c - QX_c - 1 downto PAY_c));
      cx    := unsigned(x_in);
      cy    := unsigned(y_in);
      hm_r  <= hx = cx and hy = cy(QY_c - 1 downto 0);
      hs_r  <= before(hy, cy) or (hy = cy(QY_c - 1 downto 0) and hx < cx);
      pm_r  <= px = cx and py = cy(QY_c - 1 downto 0);
      ps_r  <= before(py, cy) or (py = cy(QY_c - 1 downto 0) and px < cx);
    end if;
  end process ahead;

  match <= col_valid and head_valid when (took_r and pm_r) or (not took_r and hm_r) else
           '0';
  stale <= col_valid and head_valid when (took_r and ps_r) or (not took_r and hs_r) else
           '0';

  -- `count` is the number of entries in the RAM; the RAM's read register `pf`, the register `pf2`
  -- and the head register hold three more. The RAM's output only ever loads pf2 (no logic follows
  -- the block RAM's clock-to-output time), pf2 only the head, and each refills in the clock its
  -- successor takes it: one pop per clock. `count` is a register so that no pointer arithmetic
  -- sits on the paths of the full and empty decisions; a clock's losses are added to `lost` one
  -- clock later.
  queue_ctrl : process (clk) is
    variable push     : boolean;
    variable pop      : boolean;
    variable write    : boolean;
    variable read     : boolean;
    variable take     : boolean;
    variable take2    : boolean;
    variable lost_inc : unsigned(QBITS_c + 1 downto 0);
    variable dx, dy   : unsigned(COORD_BITS_c - 1 downto 0);
  begin
    if rising_edge(clk) then
      dx       := unsigned(det_x);
      dy       := unsigned(det_y);
      push     := det_valid = '1' and dx >= BORDER_c and dx <= LINE_WIDTH_g - 1 - BORDER_c and
                  dy >= BORDER_c and dy <= FRAME_HEIGHT_g - 1 - BORDER_c;
      pop      := match = '1' or stale = '1';
      write    := push and count < QDEPTH_c - 1;  -- the RAM holds QDEPTH_c - 1 entries, pf, pf2, head 3 more
      read     := false;
      lost_inc := (others => '0');
      if stale = '1' then
        lost_inc := lost_inc + 1;
      end if;
      if push and not write then
        lost_inc := lost_inc + 1;
      end if;
      if write then
        queue(to_integer(wr_ptr)) <= pack(dx + BORDER_c, dy + BORDER_c, det_score, det_code, det_low);
        wr_ptr                    <= wrap_next(wr_ptr);
      end if;
      if col_valid = '1' and col_x = 0 and col_y = 0 then
        -- A new frame reaches the window: whatever still waits belongs to a malformed frame (an
        -- entry written in this clock stays: the read pointer takes the write pointer before it).
        lost_inc   := lost_inc + count + b2n(pf_valid) + b2n(pf2_valid) + b2n(head_valid) - b2n(stale);
        rd_ptr     <= wr_ptr;
        pf_valid   <= '0';
        pf2_valid  <= '0';
        head_valid <= '0';
        took_r     <= false;
        if write then
          count <= to_unsigned(1, count'length);
        else
          count <= (others => '0');
        end if;
      else
        take   := head_valid = '0' or pop;
        take2  := pf2_valid = '0' or take;
        took_r <= take;
        if take then
          head       <= pf2;
          head_valid <= pf2_valid;
        end if;
        if take2 then
          pf2       <= pf;
          pf2_valid <= pf_valid;
        end if;
        if pf_valid = '0' or take2 then
          if count /= 0 then
            pf       <= queue(to_integer(rd_ptr));
            rd_ptr   <= wrap_next(rd_ptr);
            pf_valid <= '1';
            read     := true;
          else
            pf_valid <= '0';
          end if;
        end if;
        if write and not read then
          count <= count + 1;
        elsif read and not write then
          count <= count - 1;
        end if;
      end if;
      lost_q   <= lost_inc;
      lost_cnt <= lost_cnt + lost_q;
      if rst = '1' then
        wr_ptr     <= (others => '0');
        rd_ptr     <= (others => '0');
        count      <= (others => '0');
        pf_valid   <= '0';
        pf2_valid  <= '0';
        head_valid <= '0';
        lost_q     <= (others => '0');
        lost_cnt   <= (others => '0');
      end if;
    end if;
  end process queue_ctrl;

  -- The window slides one column per input column; after the shift it is centred on the column
  -- tag minus 18 (15 for the patch, 3 for the smoothing). The 256 fixed tests of the sector-0
  -- table are evaluated on the window of the previous clock, registered only for a feature's
  -- window. The window is a process variable (31 x 248 flip-flops in hardware; a variable costs
  -- the simulator one copy per clock instead of 7,688 signal updates).
  window_tests : process (clk) is
    variable win : win_t := (others => (others => '0'));
  begin
    if rising_edge(clk) then
      t_valid <= w_valid and w_match;
      if w_valid = '1' and w_match = '1' then
        t_info <= w_info;
        for i in 0 to 255 loop
          if pixel(win, PAT_c(i, 0), PAT_c(i, 1)) < pixel(win, PAT_c(i, 2), PAT_c(i, 3)) then
            t_bits(i) <= '1';
          else
            t_bits(i) <= '0';
          end if;
        end loop;
      end if;
      w_valid <= col_valid;
      if col_valid = '1' then
        win(0 to WIN_c - 2) := win(1 to WIN_c - 1);
        win(WIN_c - 1)      := col_data;
        w_match             <= match;
        -- at a match the column is the feature's tag
        w_info <= std_logic_vector(col_y) & std_logic_vector(col_x) & head(PAY_c - 1 downto 0);
      end if;
      if rst = '1' then
        w_valid <= '0';
        t_valid <= '0';
      end if;
    end if;
  end process window_tests;

  moments : entity work.orb_orient_moments
    port map (
      clk       => clk,
      rst       => rst,
      in_valid  => col_valid,
      in_x      => col_xs,
      in_y      => y_dly,
      in_col    => col_data,
      out_valid => m_valid,
      out_x     => m_x,
      out_y     => m_y,
      out_m10   => m_m10,
      out_m01   => m_m01
    );

  -- Flags in step with the moments and the sector: which column positions are features (only
  -- those go through orb_orient_sector, which is then idle most of the time), and the frame's
  -- last position (frame_done). Like the moments' own delay line, feat_dly is never reset.
  flags : process (clk) is
  begin
    if rising_edge(clk) then
      feat_dly <= match & feat_dly(1 to ORIENT_MOMENTS_LAT_c - 1);
      if col_valid = '1' and col_x = LINE_WIDTH_g - 1 and col_y = FRAME_HEIGHT_g - 1 then
        last_dly <= '1' & last_dly(1 to ORIENT_LAT_c - 1);
      else
        last_dly <= '0' & last_dly(1 to ORIENT_LAT_c - 1);
      end if;
      if rst = '1' then
        last_dly <= (others => '0');
      end if;
    end if;
  end process flags;

  sec_in <= m_valid and feat_dly(ORIENT_MOMENTS_LAT_c);

  sector : entity work.orb_orient_sector
    generic map (
      SECTORS_g => SECTORS_g
    )
    port map (
      clk        => clk,
      rst        => rst,
      in_valid   => sec_in,
      in_x       => m_x,
      in_y       => m_y,
      in_m10     => m_m10,
      in_m01     => m_m01,
      out_valid  => s_valid,
      out_x      => s_x,
      out_y      => s_y,
      out_sector => s_sector
    );

  -- The sector of a column position leaves orb_orient_sector ORIENT_LAT_c clocks after the
  -- column stage, WAIT_c clocks after the tests of that position were registered.
  pending : process (clk) is
  begin
    if rising_edge(clk) then
      wait_cnt   <= wait_cnt + 1;
      wait_valid <= t_valid & wait_valid(1 to WAIT_c - 1);
      if t_valid = '1' then
        wait_ram(to_integer(wait_cnt)) <= t_bits & t_info;
      end if;
      -- the entry written WAIT_c clocks ago, read into the o1 stage with its sector; only when it
      -- holds a position (the o1 stage is read only with o1_valid): a 299-bit register and its
      -- LUT-RAM read that would otherwise change every clock (docs/power.md)
      if wait_valid(WAIT_c) = '1' then
        wait_out  <= wait_ram(to_integer(wait_cnt - WAIT_c));
        o1_sector <= unsigned(s_sector);
      end if;
      o1_valid   <= wait_valid(WAIT_c);
      o1_last    <= last_dly(ORIENT_LAT_c);
      if rst = '1' then
        wait_valid <= (others => '0');
        o1_valid   <= '0';
        o1_last    <= '0';
      end if;
    end if;
  end process pending;

  o1_info <= wait_out(INFO_c - 1 downto 0);
  o1_bits <= wait_out(256 + INFO_c - 1 downto INFO_c);

  -- pragma translate_off
  aligned : process (clk) is
    variable s_tag : std_logic_vector(2 * COORD_BITS_c - 1 downto 0) := (others => '0');
    variable s_ok  : std_logic := '0';
  begin
    if rising_edge(clk) then
      assert o1_valid = '0' or (s_ok = '1' and o1_info(INFO_c - 1 downto PAY_c) = s_tag)
        report "orb_desc_path: sector and tests out of step (ORIENT_LAT_c is wrong)"
        severity failure;
      s_tag := s_y & s_x;  -- what the o1 stage takes with this edge
      s_ok  := s_valid;
    end if;
  end process aligned;
  -- pragma translate_on

  -- Sector s: test j * 4N + k is test j * 4N + (k + s) mod 4N of the sector-0 table.
  rotate : process (clk) is
    variable orbit : unsigned(ORBIT_c - 1 downto 0);
  begin
    if rising_edge(clk) then
      o2_valid <= o1_valid;
      o2_last  <= o1_last;
      if o1_valid = '1' then
        o2_info   <= o1_info;
        o2_sector <= std_logic_vector(o1_sector);
        for j in 0 to 256 / ORBIT_c - 1 loop
          orbit := unsigned(o1_bits((j + 1) * ORBIT_c - 1 downto j * ORBIT_c));
          if ROTATE_g then
            orbit := rotate_right(orbit, to_integer(o1_sector));
          end if;
          o2_desc((j + 1) * ORBIT_c - 1 downto j * ORBIT_c) <= std_logic_vector(orbit);
        end loop;
      end if;
      done_q <= o2_last;
      if rst = '1' then
        o2_valid <= '0';
        o2_last  <= '0';
        done_q   <= '0';
      end if;
    end if;
  end process rotate;

  feat_valid  <= o2_valid;
  feat_x      <= std_logic_vector(unsigned(o2_info(PAY_c + COORD_BITS_c - 1 downto PAY_c)) - BORDER_c);
  feat_y      <= std_logic_vector(unsigned(o2_info(INFO_c - 1 downto PAY_c + COORD_BITS_c)) - BORDER_c);
  feat_score  <= o2_info(PAY_c - 1 downto PAY_c - SCORE_BITS_c);
  feat_code   <= o2_info(RESPONSE_BITS_c downto 1);
  feat_low    <= o2_info(0);
  cand_valid  <= t_valid;
  cand_x      <= std_logic_vector(unsigned(t_info(PAY_c + COORD_BITS_c - 1 downto PAY_c)) - BORDER_c);
  cand_y      <= std_logic_vector(unsigned(t_info(INFO_c - 1 downto PAY_c + COORD_BITS_c)) - BORDER_c);
  cand_code   <= t_info(RESPONSE_BITS_c downto 1);
  cand_low    <= t_info(0);
  feat_sector <= o2_sector;
  feat_desc   <= o2_desc;
  frame_done  <= done_q;
  lost        <= std_logic_vector(lost_cnt);

end architecture rtl;
