-- SPDX-License-Identifier: MIT
-- orb_resampler: the num:den pyramid step (docs/spec.md section 3, "Pyramid step"; model
-- golden_model.scaler.resample): the centre-aligned, fixed-phase bilinear sample of the input at
-- ((x + 0.5) NUM/DEN - 0.5, (y + 0.5) NUM/DEN - 0.5), all weights integers in units of 1/D,
-- D = 2 DEN, rounded half up once. Streaming, no frame buffer: the horizontal sum of each output
-- column (D - a) p(i) + a p(i + 1) is formed when input pixel i + 1 arrives, one line of them
-- waits in a read-first RAM, and the output row that needs input rows j and j + 1 is formed while
-- row j + 1 streams in. At most one output per input pixel (NUM > DEN). DEN_g must be a power of
-- two, so the division by D*D is a shift. Seven pipeline stages, none with more than one weighted
-- tap (a balanced shift-add, no DSP48) or one adder of three terms behind a register
-- (docs/synthesis.md, "Timing"): the taps, their weights, the horizontal sum, the line RAM, the
-- RAM's word registered, the vertical products, their sum and the rounding. Latency: the output
-- leaves RESAMPLER_LAT_c = 7 clocks after the input pixel that completes it (orb_latency_pkg,
-- docs/latency.md). For NUM:DEN = 2:1 it is the 2x2 box of orb_scaler, bit for bit;
-- orb_core uses orb_scaler for 2:1 and this entity for every other step.
-- Ports and generics: docs/entities/orb_resampler.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;

entity orb_resampler is
  generic (
    LINE_WIDTH_g : positive range 2 to 4096 := 640;
    LINE_COUNT_g : positive range 2 to 4096 := 480;
    NUM_g        : positive range 2 to 16   := 5;
    DEN_g        : positive range 1 to 8    := 4
  );
  port (
    clk       : in    std_logic;
    rst       : in    std_logic;
    in_valid  : in    std_logic;
    in_x      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_y      : in    std_logic_vector(COORD_BITS_c - 1 downto 0);
    in_data   : in    std_logic_vector(PIXEL_BITS_c - 1 downto 0);
    out_valid : out   std_logic;
    out_x     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_y     : out   std_logic_vector(COORD_BITS_c - 1 downto 0);
    out_data  : out   std_logic_vector(PIXEL_BITS_c - 1 downto 0)
  );
end entity orb_resampler;

architecture rtl of orb_resampler is

  constant D_c      : positive := 2 * DEN_g;
  constant LOG_D_c  : natural  := clog2(D_c);
  constant OUT_W_c  : natural  := LINE_WIDTH_g * DEN_g / NUM_g;
  constant OUT_H_c  : natural  := LINE_COUNT_g * DEN_g / NUM_g;
  constant H_BITS_c : positive := PIXEL_BITS_c + LOG_D_c + 1;       -- a horizontal sum, <= D * 255
  constant S_BITS_c : positive := PIXEL_BITS_c + 2 * LOG_D_c + 1;   -- the 2x2 sum, <= D * D * 255
  -- the phase step from one output to the next: P grows by 2 NUM, i.e. STEP_I_c whole pixels and
  -- STEP_A_c units of 1/D
  constant STEP_I_c  : natural := (2 * NUM_g) / D_c;
  constant STEP_A_c  : natural := (2 * NUM_g) mod D_c;
  constant START_I_c : natural := (NUM_g - DEN_g) / D_c;               -- P(0) = NUM - DEN
  constant START_A_c : natural := (NUM_g - DEN_g) mod D_c;

  subtype coord_t is unsigned(COORD_BITS_c - 1 downto 0);
  subtype phase_t is natural range 0 to D_c - 1;
  type hline_t is array (0 to OUT_W_c) of unsigned(H_BITS_c - 1 downto 0);

  -- column state: the next output column xo, its left tap i and weight a
  signal xo : coord_t := (others => '0');
  signal ci : coord_t := (others => '0');
  signal ca : phase_t := 0;
  -- row state: the next output row yo, its upper tap j and weight b; the row streaming now
  signal yo     : coord_t := (others => '0');
  signal rj     : coord_t := (others => '0');
  signal rb     : phase_t := 0;
  signal last_y : coord_t := (others => '0');
  -- precomputed: rj + 1 and yo < OUT_H_c (updated with rj and yo), ci + 1 (with ci), and the
  -- row state an output row advances to (nx_*, formed from rj, rb, yo one clock after they
  -- change; used only at a row's first pixel, at least two clocks after any change)
  signal rj_p1   : coord_t := to_unsigned(1, COORD_BITS_c);
  signal cur_lt  : boolean := OUT_H_c > 0;
  signal ci_p1   : coord_t := to_unsigned(1, COORD_BITS_c);
  signal nx_j    : coord_t := (others => '0');
  signal nx_j1   : coord_t := (others => '0');
  signal nx_b    : phase_t := 0;
  signal nx_yo   : coord_t := (others => '0');
  signal nx_lt   : boolean := false;
  signal prev_px : unsigned(PIXEL_BITS_c - 1 downto 0) := (others => '0');
  -- stage 1 -> 2: a horizontal sum for column s1_x of row s1_y
  signal s1_v   : std_logic := '0';
  signal s1_out : std_logic := '0';                                  -- the row is an output row
  signal s1_x   : coord_t := (others => '0');
  signal s1_y   : coord_t := (others => '0');                        -- the output row
  signal s1_b   : phase_t := 0;
  signal s1_p0  : unsigned(PIXEL_BITS_c - 1 downto 0) := (others => '0');  -- the column's taps
  signal s1_p1  : unsigned(PIXEL_BITS_c - 1 downto 0) := (others => '0');
  signal s1_a   : phase_t := 0;
  -- stage 1p: the weighted taps; stage 1h: the horizontal sum
  signal hp_v   : std_logic := '0';
  signal hp_out : std_logic := '0';
  signal hp_x   : coord_t := (others => '0');
  signal hp_y   : coord_t := (others => '0');
  signal hp_b   : phase_t := 0;
  signal hp_0   : unsigned(H_BITS_c - 1 downto 0) := (others => '0');
  signal hp_1   : unsigned(H_BITS_c - 1 downto 0) := (others => '0');
  signal h_v    : std_logic := '0';
  signal h_out  : std_logic := '0';
  signal h_x    : coord_t := (others => '0');
  signal h_y    : coord_t := (others => '0');
  signal h_b    : phase_t := 0;
  signal s1_h   : unsigned(H_BITS_c - 1 downto 0) := (others => '0');
  -- stage 2 -> 3: with the previous row's sum of the column
  signal mem   : hline_t;
  signal s2_v  : std_logic := '0';
  signal s2_x  : coord_t := (others => '0');
  signal s2_y  : coord_t := (others => '0');
  signal s2_b  : phase_t := 0;
  signal s2_h  : unsigned(H_BITS_c - 1 downto 0) := (others => '0');
  signal s2_up : unsigned(H_BITS_c - 1 downto 0) := (others => '0');
  -- stage 2r: the RAM's word registered, the weights; stage 3p: the vertical products
  signal r_v     : std_logic := '0';
  signal r_x     : coord_t := (others => '0');
  signal r_y     : coord_t := (others => '0');
  signal r_up    : unsigned(H_BITS_c - 1 downto 0) := (others => '0');
  signal r_h     : unsigned(H_BITS_c - 1 downto 0) := (others => '0');
  signal r_wu    : unsigned(LOG_D_c downto 0) := (others => '0');
  signal r_wh    : unsigned(LOG_D_c downto 0) := (others => '0');
  signal p_v     : std_logic := '0';
  signal p_x     : coord_t := (others => '0');
  signal p_y     : coord_t := (others => '0');
  signal p_up    : unsigned(S_BITS_c - 1 downto 0) := (others => '0');
  signal p_h     : unsigned(S_BITS_c - 1 downto 0) := (others => '0');
  signal o_valid : std_logic := '0';
  signal o_x     : coord_t := (others => '0');
  signal o_y     : coord_t := (others => '0');
  signal o_data  : unsigned(PIXEL_BITS_c - 1 downto 0) := (others => '0');

  -- w * v for a weight of at most LOG_D_c + 1 bits as a balanced sum of shifted copies of v (no
  -- DSP48: a multiplier's cascade with the next adder was the longest path of the 5:4 pyramid)
  function weigh (w : unsigned; v : unsigned; width : positive) return unsigned is
    type     terms_t is array (0 to 7) of unsigned(width - 1 downto 0);
    variable t : terms_t := (others => (others => '0'));
  begin
    for i in 0 to w'length - 1 loop
      if w(w'low + i) = '1' then
        t(i) := shift_left(resize(v, width), i);
      end if;
    end loop;
    return ((t(0) + t(1)) + (t(2) + t(3))) + ((t(4) + t(5)) + (t(6) + t(7)));
  end function weigh;

begin

  -- the seven stages of processes horizontal, hsum, line and vertical (the header lists them)
  assert RESAMPLER_LAT_c = 7
    report "orb_resampler: RESAMPLER_LAT_c (orb_latency_pkg) must be this pipeline's 7 clocks"
    severity failure;

  assert NUM_g > DEN_g
    report "orb_resampler: NUM_g must be larger than DEN_g (a reduction)"
    severity failure;
  assert 2 ** clog2(DEN_g) = DEN_g
    report "orb_resampler: DEN_g must be a power of two (the final division is a shift)"
    severity failure;

  -- Stage 1: positions and the horizontal sum. An output column is complete when input pixel
  -- i + 1 of its row arrives (i + 1 <= W - 1 always holds for NUM > DEN).
  horizontal : process (clk) is
    variable x, y       : coord_t;
    variable na         : natural range 0 to 2 * D_c;
    variable ni         : coord_t;
    variable b          : natural;
    variable row        : coord_t;
    variable first, adv : boolean;
    variable is_out     : boolean;

    -- the next tap and weight: P grows by 2 NUM, STEP_I_c whole pixels and STEP_A_c units of 1/D
    procedure advance (
      i             : coord_t;
      a             : phase_t;
      variable ni_o : out coord_t;
      variable na_o : out natural
    ) is
      variable s : natural range 0 to 2 * D_c;
    begin
      s := a + STEP_A_c;
      if s >= D_c then
        na_o := s - D_c;
        ni_o := i + STEP_I_c + 1;
      else
        na_o := s;
        ni_o := i + STEP_I_c;
      end if;
    end procedure advance;

  begin
    if rising_edge(clk) then
      -- the row state an output row advances to
      advance(rj, rb, ni, na);
      nx_j  <= ni;
      nx_j1 <= ni + 1;
      nx_b  <= na;
      nx_yo <= yo + 1;
      nx_lt <= yo + 1 < OUT_H_c;
      s1_v  <= '0';
      if in_valid = '1' then
        x     := unsigned(in_x);
        y     := unsigned(in_y);
        first := x = 0 and y = 0;
        adv   := x = 0 and y /= 0 and last_y = rj_p1;
        if x = 0 then
          -- a new row: the column state restarts; the row state advances past an output row
          xo    <= (others => '0');
          ci    <= to_unsigned(START_I_c, COORD_BITS_c);
          ci_p1 <= to_unsigned(START_I_c + 1, COORD_BITS_c);
          ca    <= START_A_c;
          if first then
            yo     <= (others => '0');
            rj     <= to_unsigned(START_I_c, COORD_BITS_c);
            rj_p1  <= to_unsigned(START_I_c + 1, COORD_BITS_c);
            rb     <= START_A_c;
            cur_lt <= OUT_H_c > 0;
          elsif adv then
            yo     <= nx_yo;
            rj     <= nx_j;
            rj_p1  <= nx_j1;
            rb     <= nx_b;
            cur_lt <= nx_lt;
          end if;
          last_y <= y;
        elsif x = ci_p1 and xo < OUT_W_c then
          -- column xo completes with (prev, this) as its taps
          s1_v  <= '1';
          s1_x  <= xo;
          s1_p0 <= prev_px;
          s1_p1 <= unsigned(in_data);
          s1_a  <= ca;
          xo    <= xo + 1;
          advance(ci, ca, ni, na);
          ci    <= ni;
          ci_p1 <= ni + 1;
          ca    <= na;
        end if;
        -- the row of this pixel: at x = 0 the registers above still hold the previous row's
        -- state, so the same decision is made here from the values the row will have
        if first then
          b      := START_A_c;
          row    := (others => '0');
          is_out := y = START_I_c + 1 and OUT_H_c > 0;
        elsif adv then
          b      := nx_b;
          row    := nx_yo;
          is_out := y = nx_j1 and nx_lt;
        else
          b      := rb;
          row    := yo;
          is_out := y = rj_p1 and cur_lt;
        end if;
        s1_out  <= '1' when is_out else '0';
        s1_y    <= row;
        s1_b    <= b;
        prev_px <= unsigned(in_data);
      end if;
      if rst = '1' then
        s1_v <= '0';
      end if;
    end if;
  end process horizontal;

  -- Stages 1p and 1h: the two weighted taps, then the horizontal sum (D - a) p(i) + a p(i + 1).
  hsum : process (clk) is
  begin
    if rising_edge(clk) then
      hp_v <= s1_v;
      if s1_v = '1' then
        hp_out <= s1_out;
        hp_x   <= s1_x;
        hp_y   <= s1_y;
        hp_b   <= s1_b;
        hp_0   <= weigh(to_unsigned(D_c - s1_a, LOG_D_c + 1), s1_p0, H_BITS_c);
        hp_1   <= weigh(to_unsigned(s1_a, LOG_D_c + 1), s1_p1, H_BITS_c);
      end if;
      h_v <= hp_v;
      if hp_v = '1' then
        h_out <= hp_out;
        h_x   <= hp_x;
        h_y   <= hp_y;
        h_b   <= hp_b;
        s1_h  <= hp_0 + hp_1;
      end if;
      if rst = '1' then
        hp_v <= '0';
        h_v  <= '0';
      end if;
    end if;
  end process hsum;

  -- Stage 2: the column's sum of the previous row (read-first), this row's sum written in its
  -- place. Every row writes, so the line always holds the row above the one streaming.
  line : process (clk) is
    variable addr : natural range 0 to OUT_W_c;
  begin
    if rising_edge(clk) then
      s2_v <= '0';
      if h_v = '1' then
        addr  := to_integer(h_x);
        s2_up <= mem(addr);
        mem(addr) <= s1_h;
        s2_v  <= h_out;
        s2_x  <= h_x;
        s2_y  <= h_y;
        s2_b  <= h_b;
        s2_h  <= s1_h;
      end if;
      if rst = '1' then
        s2_v <= '0';
      end if;
    end if;
  end process line;

  -- Stages 2r, 3p and 3: the RAM's word registered with the vertical weights, the two products,
  -- then their sum and the one rounding (half up), a shift since D is a power of two.
  vertical : process (clk) is
    variable s : unsigned(S_BITS_c - 1 downto 0);
  begin
    if rising_edge(clk) then
      r_v <= s2_v;
      if s2_v = '1' then
        r_x  <= s2_x;
        r_y  <= s2_y;
        r_up <= s2_up;
        r_h  <= s2_h;
        r_wu <= to_unsigned(D_c - s2_b, LOG_D_c + 1);
        r_wh <= to_unsigned(s2_b, LOG_D_c + 1);
      end if;
      p_v <= r_v;
      if r_v = '1' then
        p_x  <= r_x;
        p_y  <= r_y;
        p_up <= weigh(r_wu, r_up, S_BITS_c);
        p_h  <= weigh(r_wh, r_h, S_BITS_c);
      end if;
      o_valid <= '0';
      if p_v = '1' then
        s := p_up + p_h + to_unsigned(D_c * D_c / 2, S_BITS_c);
        o_valid <= '1';
        o_x     <= p_x;
        o_y     <= p_y;
        o_data  <= resize(shift_right(s, 2 * LOG_D_c), PIXEL_BITS_c);
      end if;
      if rst = '1' then
        r_v     <= '0';
        p_v     <= '0';
        o_valid <= '0';
      end if;
    end if;
  end process vertical;

  out_valid <= o_valid;
  out_x     <= std_logic_vector(o_x);
  out_y     <= std_logic_vector(o_y);
  out_data  <= std_logic_vector(o_data);

end architecture rtl;
