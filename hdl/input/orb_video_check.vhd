-- SPDX-License-Identifier: MIT
-- orb_video_check: AXI4-Stream video protocol checker in front of orb_core (8-bit luma in
-- and out, tuser = start of frame, tlast = end of line), so that the detector only ever sees
-- complete, well-formed WIDTH_g x HEIGHT_g frames. A frame opens with a tuser pixel and closes
-- with its WIDTH_g * HEIGHT_g-th pixel; output tuser and tlast are generated from the checker's
-- own position, never copied. A fault inside an open frame (a short line: tlast before
-- x = WIDTH_g - 1; a long line: no tlast at x = WIDTH_g - 1; a tuser before the frame is complete,
-- at a line start or in mid-line) marks the frame bad: the checker completes it with padding pixels
-- of value 0 at one per clock. With IDLE_TIMEOUT_g = 0 (a source that can wait) s_axis_video_tready
-- is low while padding, and a tuser pixel that caused the fault is held and then opens the next
-- frame normally. With IDLE_TIMEOUT_g > 0 (a live source that cannot wait: HDMI through a bridge
-- FIFO) s_axis_video_tready stays high: pixels arriving while padding are discarded, a tuser pixel
-- that caused the fault or arrives while padding too (its frame is lost), and an open frame whose
-- input has been idle for IDLE_TIMEOUT_g clocks is padded at once (the cut frame of an unplugged
-- cable is closed before the video returns). Pixels outside any open frame (after a frame's last
-- pixel or after a fault, before the next tuser; after reset) are discarded and counted. Each frame
-- forwarded ends with a frame_end pulse, together with its last pixel on m_axis_video, carrying
-- frame_bad and frame_fault (bit 0 short line, bit 1 long line, bit 2 tuser at a line start, bit 3
-- tuser in mid-line, bit 4 idle timeout); protocol_errors counts bad frames, discarded_pixels
-- discarded pixels. Latency VIDEO_CHECK_LAT_c = 1 clock (output registers; orb_latency_pkg,
-- docs/latency.md). m_axis_video_tready must stay high (the
-- detector never stalls; a simulation assertion checks it). rst abandons an open frame without a
-- frame_end (the detector, on the same reset, drops its partial frame too) and clears the counters.
-- See docs/video-input.md.
-- Ports and generics: docs/entities/orb_video_check.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;

entity orb_video_check is
  generic (
    WIDTH_g  : positive range 2 to 4095 := 640;
    HEIGHT_g : positive range 2 to 4095 := 480;
    -- 0: the source waits while a frame is padded; 1 to 2**24 - 1: a live source, and the clocks
    -- an open frame's input may be idle before the frame is padded (docs/video-input.md)
    IDLE_TIMEOUT_g : natural range 0 to 16777215 := 0
  );
  port (
    clk                 : in    std_logic;
    rst                 : in    std_logic;
    s_axis_video_tdata  : in    std_logic_vector(PIXEL_BITS_c - 1 downto 0);
    s_axis_video_tvalid : in    std_logic;
    s_axis_video_tready : out   std_logic;
    s_axis_video_tuser  : in    std_logic;
    s_axis_video_tlast  : in    std_logic;
    m_axis_video_tdata  : out   std_logic_vector(PIXEL_BITS_c - 1 downto 0);
    m_axis_video_tvalid : out   std_logic;
    m_axis_video_tready : in    std_logic;
    m_axis_video_tuser  : out   std_logic;
    m_axis_video_tlast  : out   std_logic;
    frame_end           : out   std_logic;
    frame_bad           : out   std_logic;
    frame_fault         : out   std_logic_vector(4 downto 0);
    protocol_errors     : out   std_logic_vector(31 downto 0);
    discarded_pixels    : out   std_logic_vector(31 downto 0)
  );
end entity orb_video_check;

architecture rtl of orb_video_check is

  -- frame_fault bits
  constant SHORT_LINE_c : natural := 0;
  constant LONG_LINE_c  : natural := 1;
  constant FEW_LINES_c  : natural := 2;
  constant EARLY_SOF_c  : natural := 3;
  constant IDLE_c       : natural := 4;

  -- a live source: never held (tready high), the idle timeout on
  constant LIVE_c : boolean := IDLE_TIMEOUT_g > 0;

  subtype data_t is std_logic_vector(PIXEL_BITS_c - 1 downto 0);
  subtype faults_t is std_logic_vector(frame_fault'range);
  subtype count_t is unsigned(protocol_errors'range);

  type pixel_t is record
    data : data_t;
    user : std_logic;
    last : std_logic;
  end record pixel_t;

  -- frame state (process frame_state)
  signal ready     : std_logic := '0';
  signal is_open   : std_logic := '0';                        -- a frame is open on the output
  signal padding   : std_logic := '0';                        -- completing a bad frame
  signal held      : std_logic := '0';                        -- a tuser pixel waits for its frame
  signal held_data : data_t := (others => '0');
  signal held_last : std_logic := '0';
  signal faults    : faults_t := (others => '0');             -- faults of the open frame

  -- this edge's pixel and what it does (process place)
  signal placed      : pixel_t;   -- the pixel placed at this edge (the held one, or the input)
  signal emit        : boolean;   -- a pixel goes out at (x, y): a padding pixel (0) or placed
  signal emit_data   : data_t;
  signal discard     : boolean;   -- placed belongs to no open frame
  signal hold        : boolean;   -- placed is a tuser pixel that ends the open frame early
  signal pad_start   : boolean;   -- live: a tuser pixel ended the open frame, or its idle timeout
  signal taken       : boolean;   -- an input pixel is accepted at this edge
  signal faults_next : faults_t;  -- the open frame's faults with placed's
  signal frame_last  : boolean;   -- emit at the frame's last position

  -- position and outputs (process output), counters (process counters)
  signal idle     : natural range 0 to maximum(IDLE_TIMEOUT_g - 1, 0) := 0;  -- idle clocks of the open frame
  signal x        : natural range 0 to WIDTH_g - 1 := 0;     -- next output position
  signal y        : natural range 0 to HEIGHT_g - 1 := 0;
  signal o_valid  : std_logic := '0';
  signal o_data   : data_t := (others => '0');
  signal o_user   : std_logic := '0';
  signal o_last   : std_logic := '0';
  signal f_end    : std_logic := '0';
  signal f_bad    : std_logic := '0';
  signal f_fault  : faults_t := (others => '0');
  signal err_cnt  : count_t := (others => '0');
  signal disc_cnt : count_t := (others => '0');

begin

  assert WIDTH_g >= 2 and WIDTH_g <= 4095
    report "orb_video_check: WIDTH_g must be 2 to 4095"
    severity failure;
  assert HEIGHT_g >= 2 and HEIGHT_g <= 4095
    report "orb_video_check: HEIGHT_g must be 2 to 4095"
    severity failure;
  assert IDLE_TIMEOUT_g >= 0 and IDLE_TIMEOUT_g <= 16777215
    report "orb_video_check: IDLE_TIMEOUT_g must be 0 (off) or 1 to 16777215 clocks"
    severity failure;

  s_axis_video_tready <= ready;
  m_axis_video_tvalid <= o_valid;
  m_axis_video_tdata  <= o_data;
  m_axis_video_tuser  <= o_user;
  m_axis_video_tlast  <= o_last;
  frame_end           <= f_end;
  frame_bad           <= f_bad;
  frame_fault         <= f_fault;
  protocol_errors     <= std_logic_vector(err_cnt);
  discarded_pixels    <= std_logic_vector(disc_cnt);

  -- The pixel placed at this edge and what it does: while padding, a padding pixel goes out (and a
  -- live source's pixel is discarded); otherwise the held tuser pixel (ready is low: no input at
  -- this edge) or an input pixel opens a frame, continues the open one, is discarded outside any
  -- frame, or (a tuser pixel inside an open frame) is held while the open frame is padded (live:
  -- discarded, and padding starts). An open live frame idle for IDLE_TIMEOUT_g clocks (this edge
  -- the last of them) starts padding. The faults of the open frame gather here.
  place : process (all) is
    variable pixel_v  : pixel_t;
    variable have_v   : boolean;
    variable emit_v   : boolean;
    variable data_v   : data_t;
    variable faults_v : faults_t;
  begin
    have_v   := false;
    emit_v   := false;
    data_v   := (others => '0');
    pixel_v  := (data => s_axis_video_tdata, user => s_axis_video_tuser, last => s_axis_video_tlast);
    faults_v := faults;
    discard   <= false;
    hold      <= false;
    pad_start <= false;
    taken     <= s_axis_video_tvalid = '1' and ready = '1';

    if padding = '1' then
      emit_v := true;
      if LIVE_c and s_axis_video_tvalid = '1' and ready = '1' then
        discard <= true;
      end if;
    elsif held = '1' then
      have_v  := true;
      pixel_v := (data => held_data, user => '1', last => held_last);
    elsif s_axis_video_tvalid = '1' and ready = '1' then
      have_v := true;
    end if;

    if have_v then
      if is_open = '0' then
        if pixel_v.user = '1' then
          -- opens a frame at (0, 0)
          emit_v   := true;
          faults_v := (others => '0');
        else
          discard <= true;
        end if;
      elsif pixel_v.user = '1' then
        -- the next frame starts before this one is complete: pad this one, hold the pixel
        -- (live: discard it, its frame is lost)
        if x = 0 then
          faults_v(FEW_LINES_c) := '1';
        else
          faults_v(EARLY_SOF_c) := '1';
        end if;
        if LIVE_c then
          discard   <= true;
          pad_start <= true;
        else
          hold <= true;
        end if;
      else
        emit_v := true;
      end if;
      if emit_v then
        data_v := pixel_v.data;
        if pixel_v.last = '1' and x /= WIDTH_g - 1 then
          faults_v(SHORT_LINE_c) := '1';
        elsif pixel_v.last = '0' and x = WIDTH_g - 1 then
          faults_v(LONG_LINE_c) := '1';
        end if;
      end if;
    elsif LIVE_c and is_open = '1' and padding = '0' and idle = IDLE_TIMEOUT_g - 1 then
      faults_v(IDLE_c) := '1';
      pad_start        <= true;
    end if;

    placed      <= pixel_v;
    emit        <= emit_v;
    emit_data   <= data_v;
    faults_next <= faults_v;
    frame_last  <= emit_v and x = WIDTH_g - 1 and y = HEIGHT_g - 1;
  end process place;

  -- Frame state: open, padding a bad frame (until its last position), a held tuser pixel, the
  -- open frame's faults; ready low while padding or holding (live: high), the idle clocks.
  frame_state : process (clk) is
    variable open_v    : std_logic;
    variable padding_v : std_logic;
    variable held_v    : std_logic;
  begin
    if rising_edge(clk) then
      open_v    := is_open;
      padding_v := padding;
      held_v    := held;
      if padding = '0' and held = '1' then
        held_v := '0';
      end if;
      if hold then
        held_v    := '1';
        held_data <= placed.data;
        held_last <= placed.last;
        padding_v := '1';
      end if;
      if pad_start then
        padding_v := '1';
      end if;
      if frame_last then
        open_v    := '0';
        padding_v := '0';
      elsif emit then
        open_v := '1';
        if (or faults_next) = '1' then
          padding_v := '1';
        end if;
      end if;

      faults  <= faults_next;
      is_open <= open_v;
      padding <= padding_v;
      held    <= held_v;
      ready   <= not (padding_v or held_v);
      if LIVE_c then
        ready <= '1';
      end if;

      -- idle clocks of an open frame not being padded (none: taken, padding, or the timeout's edge)
      if LIVE_c and is_open = '1' and padding = '0' and not taken and not pad_start then
        idle <= idle + 1;
      else
        idle <= 0;
      end if;

      if rst = '1' then
        ready   <= '0';
        is_open <= '0';
        padding <= '0';
        held    <= '0';
        idle    <= 0;
      end if;
    end if;
  end process frame_state;

  -- Output register and position: the pixel emitted at (x, y) with tuser and tlast from the
  -- position; at the frame's last position the frame_end pulse with the frame's faults.
  output : process (clk) is
  begin
    if rising_edge(clk) then
      o_valid <= '0';
      f_end   <= '0';
      if emit then
        o_valid <= '1';
        o_data  <= emit_data;
        o_user  <= '1' when x = 0 and y = 0 else '0';
        o_last  <= '1' when x = WIDTH_g - 1 else '0';
        if frame_last then
          f_end   <= '1';
          f_bad   <= or faults_next;
          f_fault <= faults_next;
          x       <= 0;
          y       <= 0;
        elsif x = WIDTH_g - 1 then
          x <= 0;
          y <= y + 1;
        else
          x <= x + 1;
        end if;
      end if;
      if rst = '1' then
        x       <= 0;
        y       <= 0;
        o_valid <= '0';
        f_end   <= '0';
      end if;
    end if;
  end process output;

  -- bad frames (at their last position) and discarded pixels
  counters : process (clk) is
  begin
    if rising_edge(clk) then
      if frame_last and (or faults_next) = '1' then
        err_cnt <= err_cnt + 1;
      end if;
      if discard then
        disc_cnt <= disc_cnt + 1;
      end if;
      if rst = '1' then
        err_cnt  <= (others => '0');
        disc_cnt <= (others => '0');
      end if;
    end if;
  end process counters;

  -- The downstream must take every pixel at once (orb_core's tready is high after reset).
  -- pragma translate_off
  no_stall : process (clk) is
  begin
    if rising_edge(clk) then
      assert rst = '1' or o_valid = '0' or m_axis_video_tready = '1'
        report "orb_video_check: m_axis_video_tready low with a pixel on m_axis_video (the output cannot stall)"
        severity error;
    end if;
  end process no_stall;
-- pragma translate_on

end architecture rtl;
