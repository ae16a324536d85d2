-- SPDX-License-Identifier: MIT
-- orb_video_check: AXI4-Stream video protocol checker in front of orb_core (8-bit luma in
-- and out, tuser = start of frame, tlast = end of line), so that the detector only ever sees
-- complete, well-formed WIDTH_g x HEIGHT_g frames. A frame opens with a tuser pixel and closes
-- with its WIDTH_g * HEIGHT_g-th pixel; output tuser and tlast are generated from the checker's
-- own position, never copied. A fault inside an open frame (a short line: tlast before
-- x = WIDTH_g - 1; a long line: no tlast at x = WIDTH_g - 1; a tuser before the frame is complete,
-- at a line start or in mid-line) marks the frame bad: the checker completes it with padding pixels
-- of value 0 at one per clock while s_axis_video_tready is low, and a tuser pixel that caused the
-- fault is held and then opens the next frame normally. Pixels outside any open frame (after a
-- frame's last pixel or after a fault, before the next tuser; after reset) are discarded and
-- counted. Each frame forwarded ends with a frame_end pulse, together with its last pixel on
-- m_axis_video, carrying frame_bad and frame_fault (bit 0 short line, bit 1 long line, bit 2 tuser
-- at a line start, bit 3 tuser in mid-line); protocol_errors counts bad frames, discarded_pixels
-- discarded pixels. Latency VIDEO_CHECK_LAT_c = 1 clock (output registers; orb_latency_pkg,
-- docs/latency.md). m_axis_video_tready must stay high (the
-- detector never stalls; a simulation assertion checks it). rst abandons an open frame without a
-- frame_end (the detector, on the same reset, drops its partial frame too) and clears the counters.
-- See docs/video-input.md.
-- Ports and generics: docs/entities/orb_video_check.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

entity orb_video_check is
  generic (
    WIDTH_g  : positive range 2 to 4095 := 640;
    HEIGHT_g : positive range 2 to 4095 := 480
  );
  port (
    clk                 : in    std_logic;
    rst                 : in    std_logic;
    s_axis_video_tdata  : in    std_logic_vector(7 downto 0);
    s_axis_video_tvalid : in    std_logic;
    s_axis_video_tready : out   std_logic;
    s_axis_video_tuser  : in    std_logic;
    s_axis_video_tlast  : in    std_logic;
    m_axis_video_tdata  : out   std_logic_vector(7 downto 0);
    m_axis_video_tvalid : out   std_logic;
    m_axis_video_tready : in    std_logic;
    m_axis_video_tuser  : out   std_logic;
    m_axis_video_tlast  : out   std_logic;
    frame_end           : out   std_logic;
    frame_bad           : out   std_logic;
    frame_fault         : out   std_logic_vector(3 downto 0);
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

  signal ready     : std_logic := '0';
  signal is_open   : std_logic := '0';                        -- a frame is open on the output
  signal padding   : std_logic := '0';                        -- completing a bad frame
  signal held      : std_logic := '0';                        -- a tuser pixel waits for its frame
  signal held_data : std_logic_vector(7 downto 0) := (others => '0');
  signal held_last : std_logic := '0';
  signal x         : natural range 0 to WIDTH_g - 1 := 0;     -- next output position
  signal y         : natural range 0 to HEIGHT_g - 1 := 0;
  signal faults    : std_logic_vector(3 downto 0) := (others => '0');
  signal o_valid   : std_logic := '0';
  signal o_data    : std_logic_vector(7 downto 0) := (others => '0');
  signal o_user    : std_logic := '0';
  signal o_last    : std_logic := '0';
  signal f_end     : std_logic := '0';
  signal f_bad     : std_logic := '0';
  signal f_fault   : std_logic_vector(3 downto 0) := (others => '0');
  signal err_cnt   : unsigned(31 downto 0) := (others => '0');
  signal disc_cnt  : unsigned(31 downto 0) := (others => '0');

begin

  assert WIDTH_g >= 2 and WIDTH_g <= 4095
    report "orb_video_check: WIDTH_g must be 2 to 4095"
    severity failure;
  assert HEIGHT_g >= 2 and HEIGHT_g <= 4095
    report "orb_video_check: HEIGHT_g must be 2 to 4095"
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

  check : process (clk) is
    variable have      : boolean;                      -- a pixel to place at this edge
    variable p_data    : std_logic_vector(7 downto 0);
    variable p_user    : std_logic;
    variable p_last    : std_logic;
    variable emit      : boolean;                      -- a pixel goes out at (x, y)
    variable e_data    : std_logic_vector(7 downto 0);
    variable f         : std_logic_vector(3 downto 0); -- faults of the open frame
    variable open_n    : std_logic;
    variable padding_n : std_logic;
    variable held_n    : std_logic;
  begin
    if rising_edge(clk) then
      o_valid   <= '0';
      f_end     <= '0';
      have      := false;
      emit      := false;
      e_data    := (others => '0');
      p_data    := s_axis_video_tdata;
      p_user    := s_axis_video_tuser;
      p_last    := s_axis_video_tlast;
      f         := faults;
      open_n    := is_open;
      padding_n := padding;
      held_n    := held;

      if padding = '1' then
        -- a padding pixel (value 0)
        emit := true;
      elsif held = '1' then
        -- the held tuser pixel (ready is low: no input at this edge)
        have   := true;
        p_data := held_data;
        p_user := '1';
        p_last := held_last;
        held_n := '0';
      elsif s_axis_video_tvalid = '1' and ready = '1' then
        have := true;
      end if;

      if have then
        if is_open = '0' then
          if p_user = '1' then
            -- opens a frame at (0, 0)
            emit := true;
            f    := (others => '0');
          else
            -- belongs to no open frame
            disc_cnt <= disc_cnt + 1;
          end if;
        elsif p_user = '1' then
          -- the next frame starts before this one is complete: pad this one, hold the pixel
          if x = 0 then
            f(FEW_LINES_c) := '1';
          else
            f(EARLY_SOF_c) := '1';
          end if;
          held_n    := '1';
          held_data <= p_data;
          held_last <= p_last;
          padding_n := '1';
        else
          emit := true;
        end if;
        if emit then
          e_data := p_data;
          if p_last = '1' and x /= WIDTH_g - 1 then
            f(SHORT_LINE_c) := '1';
          elsif p_last = '0' and x = WIDTH_g - 1 then
            f(LONG_LINE_c) := '1';
          end if;
        end if;
      end if;

      if emit then
        o_valid <= '1';
        o_data  <= e_data;
        o_user  <= '1' when x = 0 and y = 0 else '0';
        o_last  <= '1' when x = WIDTH_g - 1 else '0';
        if x = WIDTH_g - 1 and y = HEIGHT_g - 1 then
          -- the frame's last pixel
          f_end     <= '1';
          f_bad     <= or f;
          f_fault   <= f;
          err_cnt   <= err_cnt + 1 when (or f) = '1' else err_cnt;
          open_n    := '0';
          padding_n := '0';
          x         <= 0;
          y         <= 0;
        else
          open_n := '1';
          if (or f) = '1' then
            padding_n := '1';
          end if;
          if x = WIDTH_g - 1 then
            x <= 0;
            y <= y + 1;
          else
            x <= x + 1;
          end if;
        end if;
      end if;

      faults  <= f;
      is_open <= open_n;
      padding <= padding_n;
      held    <= held_n;
      ready   <= not (padding_n or held_n);

      if rst = '1' then
        ready    <= '0';
        is_open  <= '0';
        padding  <= '0';
        held     <= '0';
        x        <= 0;
        y        <= 0;
        o_valid  <= '0';
        f_end    <= '0';
        err_cnt  <= (others => '0');
        disc_cnt <= (others => '0');
      end if;
    end if;
  end process check;

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
