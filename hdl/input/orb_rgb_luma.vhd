-- SPDX-License-Identifier: MIT
-- orb_rgb_luma: AXI4-Stream video colour converter in front of the accelerator. Each beat of
-- s_axis_video (tuser = start of frame, tlast = end of line) becomes one 8-bit luma beat of
-- m_axis_video with the same tuser and tlast, Y = (77 R + 150 G + 29 B + 128) >> 8 (docs/spec.md
-- section 2, bit-exact with golden_model.luma.rgb_to_luma), the constant products built as
-- shift-add trees (no DSP). INPUT_g selects the input: "RGB" (24 bits, R [23:16], G [15:8],
-- B [7:0]), "RBG" (24 bits, R [23:16], B [15:8], G [7:0]: Digilent dvi2rgb's vid_pData) or "LUMA"
-- (8 bits, passed through unchanged), so the accelerator takes either kind of source through the
-- same block; s_axis_video_tdata is 24 or 8 bits wide accordingly. Full AXI4-Stream handshake at
-- one beat per clock: an input skid buffer makes s_axis_video_tready a register (no combinational
-- path from m_axis_video_tready to s_axis_video_tready), then two pipeline stages (per-channel
-- products, their sum) that advance whenever the output register is empty or being taken. Latency
-- RGB_LUMA_LAT_c = 3 clocks (orb_latency_pkg, docs/latency.md): a beat accepted at clock edge n is
-- on m_axis_video after edge n + 2, so taken at n + 3 at the earliest (skid register, products,
-- output register).
-- tready is low in reset and high from the first clock after it while the skid buffer is empty.
-- Ports and generics: docs/entities/orb_rgb_luma.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_latency_pkg.all;

entity orb_rgb_luma is
  generic (
    INPUT_g : string := "RGB"   -- "RGB", "RBG" or "LUMA"
  );
  port (
    clk                 : in    std_logic;
    rst                 : in    std_logic;
    s_axis_video_tdata  : in    std_logic_vector(8 + 16 * boolean'pos(INPUT_g /= "LUMA") - 1 downto 0);
    s_axis_video_tvalid : in    std_logic;
    s_axis_video_tready : out   std_logic;
    s_axis_video_tuser  : in    std_logic;
    s_axis_video_tlast  : in    std_logic;
    m_axis_video_tdata  : out   std_logic_vector(7 downto 0);
    m_axis_video_tvalid : out   std_logic;
    m_axis_video_tready : in    std_logic;
    m_axis_video_tuser  : out   std_logic;
    m_axis_video_tlast  : out   std_logic
  );
end entity orb_rgb_luma;

architecture rtl of orb_rgb_luma is

  constant IN_BITS_c : positive := s_axis_video_tdata'length;

  -- a beat: tdata, then tuser and tlast above it
  subtype beat_t is std_logic_vector(IN_BITS_c + 1 downto 0);

  -- input skid buffer: a_* feeds the pipeline, b_* catches the beat accepted while a_* stalls
  signal a_valid : std_logic := '0';
  signal a_beat  : beat_t := (others => '0');
  signal b_valid : std_logic := '0';
  signal b_beat  : beat_t := (others => '0');
  signal ready   : std_logic := '0';

  -- stage 1: the three weighted channels (or the luma byte), stage 2: the output register
  signal p_valid : std_logic := '0';
  signal p_r     : unsigned(14 downto 0) := (others => '0');  -- 77 R  <= 19635
  signal p_g     : unsigned(15 downto 0) := (others => '0');  -- 150 G <= 38250
  signal p_b     : unsigned(12 downto 0) := (others => '0');  -- 29 B  <= 7395
  signal p_user  : std_logic := '0';
  signal p_last  : std_logic := '0';
  signal o_valid : std_logic := '0';
  signal o_data  : std_logic_vector(7 downto 0) := (others => '0');
  signal o_user  : std_logic := '0';
  signal o_last  : std_logic := '0';

begin

  -- the registers from input to output: skid register, products, output register
  assert RGB_LUMA_LAT_c = 3
    report "orb_rgb_luma: RGB_LUMA_LAT_c (orb_latency_pkg) must be this pipeline's 3 clocks"
    severity failure;

  assert INPUT_g = "RGB" or INPUT_g = "RBG" or INPUT_g = "LUMA"
    report "orb_rgb_luma: INPUT_g must be ""RGB"", ""RBG"" or ""LUMA"""
    severity failure;

  s_axis_video_tready <= ready;
  m_axis_video_tvalid <= o_valid;
  m_axis_video_tdata  <= o_data;
  m_axis_video_tuser  <= o_user;
  m_axis_video_tlast  <= o_last;

  pipe : process (clk) is
    variable adv     : boolean; -- the pipeline moves on at this edge
    variable free_a  : boolean; -- a_* is empty or handed on at this edge
    variable take    : boolean; -- a beat is accepted at this edge
    variable r, g, b : unsigned(7 downto 0);
    variable sum     : unsigned(15 downto 0);
    variable b_next  : std_logic;
  begin
    if rising_edge(clk) then
      adv    := o_valid = '0' or m_axis_video_tready = '1';
      take   := s_axis_video_tvalid = '1' and ready = '1';
      free_a := a_valid = '0' or adv;
      b_next := b_valid;

      -- output register: Y = (77 R + 150 G + 29 B + 128) >> 8, or the luma byte (in p_g)
      if adv then
        o_valid <= p_valid;
        o_user  <= p_user;
        o_last  <= p_last;
        if INPUT_g = "LUMA" then
          o_data <= std_logic_vector(p_g(7 downto 0));
        else
          sum    := p_g + resize(p_r, 16) + resize(p_b, 16) + 128;
          o_data <= std_logic_vector(sum(15 downto 8));
        end if;
      end if;

      -- stage 1: the weighted channels as shift-add trees
      if adv then
        p_valid <= a_valid;
        p_user  <= a_beat(IN_BITS_c + 1);
        p_last  <= a_beat(IN_BITS_c);
        if INPUT_g = "LUMA" then
          p_g <= resize(unsigned(a_beat(7 downto 0)), 16);
        else
          r := unsigned(a_beat(23 downto 16));
          if INPUT_g = "RBG" then
            b := unsigned(a_beat(15 downto 8));
            g := unsigned(a_beat(7 downto 0));
          else
            g := unsigned(a_beat(15 downto 8));
            b := unsigned(a_beat(7 downto 0));
          end if;
          -- 77 = 64 + 8 + 4 + 1, 150 = 128 + 16 + 4 + 2, 29 = 16 + 8 + 4 + 1
          p_r <= shift_left(resize(r, 15), 6) + shift_left(resize(r, 15), 3)
                 + shift_left(resize(r, 15), 2) + resize(r, 15);
          p_g <= shift_left(resize(g, 16), 7) + shift_left(resize(g, 16), 4)
                 + shift_left(resize(g, 16), 2) + shift_left(resize(g, 16), 1);
          p_b <= shift_left(resize(b, 13), 4) + shift_left(resize(b, 13), 3)
                 + shift_left(resize(b, 13), 2) + resize(b, 13);
        end if;
      end if;

      -- input skid buffer (a beat is only accepted while b_* is empty)
      if free_a then
        if b_valid = '1' then
          a_beat  <= b_beat;
          a_valid <= '1';
          b_next  := '0';
        elsif take then
          a_beat  <= s_axis_video_tuser & s_axis_video_tlast & s_axis_video_tdata;
          a_valid <= '1';
        else
          a_valid <= '0';
        end if;
      elsif take then
        b_beat <= s_axis_video_tuser & s_axis_video_tlast & s_axis_video_tdata;
        b_next := '1';
      end if;
      b_valid <= b_next;
      ready   <= not b_next;

      if rst = '1' then
        a_valid <= '0';
        b_valid <= '0';
        ready   <= '0';
        p_valid <= '0';
        o_valid <= '0';
      end if;
    end if;
  end process pipe;

end architecture rtl;
