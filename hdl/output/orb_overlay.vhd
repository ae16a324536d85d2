-- SPDX-License-Identifier: MIT
-- orb_overlay: marks the previous frame's features on a passing RGB video stream (HDMI demo,
-- docs/spec.md section 13, docs/overlay.md). The feature stream (s_axis_feat, 352-bit words of
-- orb_feat_pkg; only scale, x, y and tlast are used) sets one bit per (block, scale) in the fill
-- bank of two block-RAM bitmap banks: a feature of scale s at (x, y) marks the block of the frame's
-- 2^b x 2^b blocks (b = BLOCK_LOG2_g) that holds its full-resolution centre (x + 0.5) r^s - 0.5,
-- r = STEP_NUM_g / STEP_DEN_g: bx = ((2x + 1) NUM^s - DEN^s) >> (1 + s log2(DEN) + b), likewise by
-- (for 2:1 simply x >> (b - s)). Each bank is one 1-bit-wide
-- simple dual-port RAM per scale, so a mark is a plain write (no read-modify-write) and the marks of a
-- feature frame are an OR, independent of the order in which features or scales arrive. The
-- video stream (24-bit RGB, R in [23:16]) reads the show bank in raster order and draws scale s of
-- a marked block as the one-pixel square outline inset s pixels from the block edge, in the
-- scale's colour; the last pixel of each block clears its bits, so a bank is empty again when a
-- frame has passed. The banks swap at a video start of frame when a complete feature frame waits
-- (its end-of-frame beat taken at an earlier clock edge); a feature frame that begins while
-- another waits is discarded whole. The feature beats are taken OVERLAY_FEAT_LAT_c = 6 clocks
-- after the port (the block pipeline, whose flags are a delay line of that length), and these
-- edges are the ones spec 13.3 counts. Video latency OVERLAY_VIDEO_LAT_c = 3 clocks (the bitmap
-- bits are registered before the colour is chosen); both in orb_latency_pkg, docs/latency.md.
-- Back-pressure passes through (s_axis_video_tready = m_axis_video_tready or not
-- m_axis_video_tvalid); s_axis_feat never stalls.
-- rst resets control state only: the bitmaps are zero at configuration (block RAM default), and
-- after a reset in mid-stream marks of an interrupted frame can show once.
-- Ports and generics: docs/entities/orb_overlay.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_feat_pkg.all;
use work.orb_limits_pkg.all;

entity orb_overlay is
  generic (
    WIDTH_g      : width_t      := 640;
    HEIGHT_g     : height_t     := 480;
    SCALES_g     : scales_t     := 4;
    STEP_NUM_g   : step_num_t   := 2;  -- the pyramid step of the features (orb_core's)
    STEP_DEN_g   : step_den_t   := 1;
    BLOCK_LOG2_g : block_log2_t := 3
  );
  port (
    clk                 : in    std_logic;
    rst                 : in    std_logic;
    s_axis_video_tdata  : in    std_logic_vector(23 downto 0);
    s_axis_video_tvalid : in    std_logic;
    s_axis_video_tready : out   std_logic;
    s_axis_video_tuser  : in    std_logic;
    s_axis_video_tlast  : in    std_logic;
    m_axis_video_tdata  : out   std_logic_vector(23 downto 0);
    m_axis_video_tvalid : out   std_logic;
    m_axis_video_tready : in    std_logic;
    m_axis_video_tuser  : out   std_logic;
    m_axis_video_tlast  : out   std_logic;
    s_axis_feat_tdata   : in    std_logic_vector(FEAT_BITS_c - 1 downto 0);
    s_axis_feat_tvalid  : in    std_logic;
    s_axis_feat_tready  : out   std_logic;
    s_axis_feat_tlast   : in    std_logic
  );
end entity orb_overlay;

architecture rtl of orb_overlay is

  constant BLOCK_c     : positive := 2 ** BLOCK_LOG2_g;
  constant BLOCKS_X_c  : positive := (WIDTH_g + BLOCK_c - 1) / BLOCK_c;
  constant BLOCKS_Y_c  : positive := (HEIGHT_g + BLOCK_c - 1) / BLOCK_c;
  constant BLOCKS_c    : positive := BLOCKS_X_c * BLOCKS_Y_c;
  constant ADDR_BITS_c : positive := clog2(BLOCKS_c);
  constant X_BITS_c    : positive := clog2(WIDTH_g + 1);   -- WIDTH_g means "beyond the line"
  constant Y_BITS_c    : positive := clog2(HEIGHT_g + 1);  -- HEIGHT_g means "no frame / beyond it"
  constant RING_BITS_c : positive := BLOCK_LOG2_g - 1;

  type colour_table_t is array (0 to 7) of std_logic_vector(23 downto 0);

  -- Scale colours (RGB): green, cyan, magenta, yellow, orange, blue, red, white
  -- (golden_model.overlay.SCALE_COLOURS).
  constant COLOURS_c : colour_table_t := (x"00FF00", x"00DCFF", x"FF00FF", x"FFDC00",
                                          x"FF8000", x"4080FF", x"FF3030", x"FFFFFF");

  -- Block of a feature: NUM^s and s log2(DEN) per scale, and the width of (2x + 1) NUM^s.
  type nat_arr_t is array (0 to SCALES_g - 1) of natural;

  function num_powers return nat_arr_t is
    variable p : nat_arr_t;
  begin
    p(0) := 1;
    for k in 1 to SCALES_g - 1 loop
      p(k) := p(k - 1) * STEP_NUM_g;
    end loop;
    return p;
  end function num_powers;

  constant NUM_POW_c   : nat_arr_t := num_powers;
  constant DEN_LOG_c   : natural   := clog2(STEP_DEN_g);
  constant PROD_BITS_c : positive := COORD_BITS_c + 1 + clog2(NUM_POW_c(SCALES_g - 1) + 1);

  type scale_arr_t is array (1 to OVERLAY_FEAT_LAT_c) of unsigned(FEAT_SCALE_BITS_c - 1 downto 0);

  function bit_of (n : natural) return std_logic is
  begin
    if n = 1 then
      return '1';
    end if;
    return '0';
  end function bit_of;

  -- video input side
  signal ce       : std_logic;
  signal v_acc    : std_logic;
  signal cx       : unsigned(X_BITS_c - 1 downto 0)    := (others => '0');
  signal cy       : unsigned(Y_BITS_c - 1 downto 0)    := to_unsigned(HEIGHT_g, Y_BITS_c);
  signal row_base : unsigned(ADDR_BITS_c - 1 downto 0) := (others => '0');
  signal pos_x    : unsigned(X_BITS_c - 1 downto 0);
  signal pos_y    : unsigned(Y_BITS_c - 1 downto 0);
  signal pos_base : unsigned(ADDR_BITS_c - 1 downto 0);
  signal in_frame : std_logic;
  signal rd_addr  : unsigned(ADDR_BITS_c - 1 downto 0);
  signal last_use : std_logic;
  signal ring     : unsigned(RING_BITS_c - 1 downto 0);
  signal swap     : std_logic;
  signal sbank    : std_logic := '0';  -- show bank; the fill bank is the other one
  signal sbank_n  : std_logic;         -- show bank after this edge's start of frame

  -- feature side: the block pipeline (stages 1 to OVERLAY_FEAT_LAT_c), then the frame bookkeeping
  signal waiting  : std_logic := '0';  -- the fill bank holds a complete feature frame
  signal dropping : std_logic := '0';  -- the feature frame in progress is discarded
  signal f_scale  : unsigned(FEAT_SCALE_BITS_c - 1 downto 0);
  -- per stage: the beat's valid and tlast, its scale (a scale >= SCALES_g marks nothing)
  signal fp_valid : std_logic_vector(1 to OVERLAY_FEAT_LAT_c) := (others => '0');
  signal fp_last  : std_logic_vector(1 to OVERLAY_FEAT_LAT_c) := (others => '0');
  signal fp_scale : scale_arr_t := (others => (others => '0'));
  signal fp_ok    : std_logic_vector(1 to OVERLAY_FEAT_LAT_c) := (others => '0');
  -- stage 1: 2x + 1, 2y + 1, NUM^s and DEN^s of the scale
  signal f1_x,  f1_y : unsigned(COORD_BITS_c downto 0) := (others => '0');
  signal f1_mul      : unsigned(PROD_BITS_c - COORD_BITS_c - 2 downto 0) := (others => '0');
  signal f1_sub      : unsigned(PROD_BITS_c - 1 downto 0) := (others => '0');
  -- stage 2: the products; stage 3: minus DEN^s
  signal f2_px, f2_py : unsigned(PROD_BITS_c - 1 downto 0) := (others => '0');
  signal f2_sub       : unsigned(PROD_BITS_c - 1 downto 0) := (others => '0');
  signal f3_px, f3_py : unsigned(PROD_BITS_c - 1 downto 0) := (others => '0');
  -- stage 4: the block (saturated); stage 5: inside the grid, row start; stage 6: the address
  signal f4_bx, f4_by : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal f5_bx        : unsigned(COORD_BITS_c - 1 downto 0) := (others => '0');
  signal f5_row       : unsigned(ADDR_BITS_c - 1 downto 0) := (others => '0');
  signal f6_addr      : unsigned(ADDR_BITS_c - 1 downto 0) := (others => '0');

  -- bitmap write ports: one feature mark and one clear per clock (never in the same bank)
  signal fw_en    : std_logic := '0';
  signal fw_bank  : std_logic := '0';
  signal fw_scale : unsigned(FEAT_SCALE_BITS_c - 1 downto 0) := (others => '0');
  signal fw_addr  : unsigned(ADDR_BITS_c - 1 downto 0) := (others => '0');
  signal clr_en   : std_logic := '0';
  signal clr_bank : std_logic := '0';
  signal clr_addr : unsigned(ADDR_BITS_c - 1 downto 0) := (others => '0');

  -- bit bank * SCALES_g + s: mark of scale s in bank `bank` at the block read last
  signal rd_bits : std_logic_vector(2 * SCALES_g - 1 downto 0);

  -- video pipeline: stage 1 (aligned with rd_bits), stage 2 (rd_bits registered), then the output
  -- register
  signal d1_valid  : std_logic := '0';
  signal d1_data   : std_logic_vector(23 downto 0) := (others => '0');
  signal d1_user   : std_logic := '0';
  signal d1_last   : std_logic := '0';
  signal d1_draw   : std_logic := '0';
  signal d1_bank   : std_logic := '0';
  signal d1_ring   : unsigned(RING_BITS_c - 1 downto 0) := (others => '0');
  signal d2_valid  : std_logic := '0';
  signal d2_data   : std_logic_vector(23 downto 0) := (others => '0');
  signal d2_user   : std_logic := '0';
  signal d2_last   : std_logic := '0';
  signal d2_bits   : std_logic_vector(2 * SCALES_g - 1 downto 0) := (others => '0');
  signal d2_sel    : std_logic_vector(2 * SCALES_g - 1 downto 0) := (others => '0');
  signal d2_colour : std_logic_vector(23 downto 0) := (others => '0');
  signal m_valid   : std_logic := '0';
  signal m_data    : std_logic_vector(23 downto 0) := (others => '0');
  signal m_user    : std_logic := '0';
  signal m_last    : std_logic := '0';

begin

  assert BLOCK_c >= 2 * SCALES_g
    report "orb_overlay: 2 ** BLOCK_LOG2_g must be at least 2 * SCALES_g (one ring per scale in a block)"
    severity failure;

  -- ---- video position: the accepted beat's (x, y), its block address and ring -----------------
  ce    <= m_axis_video_tready or not m_valid;
  v_acc <= s_axis_video_tvalid and ce;

  pos_x    <= (others => '0') when s_axis_video_tuser = '1' else
              cx;
  pos_y    <= (others => '0') when s_axis_video_tuser = '1' else
              cy;
  pos_base <= (others => '0') when s_axis_video_tuser = '1' else
              row_base;
  in_frame <= '1' when pos_x < WIDTH_g and pos_y < HEIGHT_g else
              '0';
  rd_addr  <= pos_base + resize(shift_right(pos_x, BLOCK_LOG2_g), ADDR_BITS_c) when in_frame = '1' else
              (others => '0');
  -- The block's last pixel in raster order (its right column and bottom row, cut by the frame).
  last_use <= '1' when (pos_x(BLOCK_LOG2_g - 1 downto 0) = BLOCK_c - 1 or pos_x = WIDTH_g - 1)
                       and (pos_y(BLOCK_LOG2_g - 1 downto 0) = BLOCK_c - 1 or pos_y = HEIGHT_g - 1) else
              '0';

  ring_of : process (pos_x, pos_y) is
    variable u, v : unsigned(BLOCK_LOG2_g - 1 downto 0);
  begin
    u := pos_x(BLOCK_LOG2_g - 1 downto 0);
    v := pos_y(BLOCK_LOG2_g - 1 downto 0);
    -- distance to the nearer edge: min(u, B-1-u), B-1-u being not u
    if u(BLOCK_LOG2_g - 1) = '1' then
      u := not u;
    end if;
    if v(BLOCK_LOG2_g - 1) = '1' then
      v := not v;
    end if;
    if u < v then
      ring <= u(RING_BITS_c - 1 downto 0);
    else
      ring <= v(RING_BITS_c - 1 downto 0);
    end if;
  end process ring_of;

  swap    <= v_acc and s_axis_video_tuser and waiting;
  sbank_n <= sbank xor swap;

  position : process (clk) is
  begin
    if rising_edge(clk) then
      clr_en <= '0';
      if v_acc = '1' then
        if s_axis_video_tlast = '1' then
          cx <= (others => '0');
          if pos_y < HEIGHT_g then
            cy <= pos_y + 1;
          end if;
          if pos_y(BLOCK_LOG2_g - 1 downto 0) = BLOCK_c - 1 then
            row_base <= pos_base + BLOCKS_X_c;
          else
            row_base <= pos_base;
          end if;
        else
          if pos_x < WIDTH_g then
            cx <= pos_x + 1;
          end if;
          cy       <= pos_y;
          row_base <= pos_base;
        end if;
        sbank    <= sbank_n;
        clr_en   <= in_frame and last_use;
        clr_bank <= sbank_n;
        clr_addr <= rd_addr;
      end if;
      if rst = '1' then
        cx       <= (others => '0');
        cy       <= to_unsigned(HEIGHT_g, Y_BITS_c);  -- pass pixels untouched until a start of frame
        row_base <= (others => '0');
        sbank    <= '0';
        clr_en   <= '0';
      end if;
    end if;
  end process position;

  -- ---- feature side: block, bitmap address, frame bookkeeping - -----------------------------------
  s_axis_feat_tready <= '1';

  f_scale <= unsigned(s_axis_feat_tdata(FEAT_SCALE_LO_c + FEAT_SCALE_BITS_c - 1 downto FEAT_SCALE_LO_c));

  -- Block of a feature: ((2x + 1) NUM^s - DEN^s) >> (1 + s log2(DEN) + b), likewise in y (for 2:1
  -- the same as x >> (b - s)). Scales >= SCALES_g are ignored; a block number too large for
  -- COORD_BITS_c saturates (it is outside the grid either way, never wraps into it). Six stages,
  -- none with more than one adder or one multiplication (docs/synthesis.md, "Timing"): the
  -- operands, the products (DSP48 with input and output registers), minus DEN^s, the shift and
  -- saturation, the grid test with the row's first address, the address.
  block_pipe : process (clk) is
    variable k : natural range 0 to 2 ** FEAT_SCALE_BITS_c - 1;

    function to_block (v : unsigned) return unsigned is
    begin
      if v(v'high downto COORD_BITS_c) /= 0 then
        return to_unsigned(2 ** COORD_BITS_c - 1, COORD_BITS_c);
      end if;
      return v(COORD_BITS_c - 1 downto 0);
    end function to_block;

  begin
    if rising_edge(clk) then
      fp_valid <= s_axis_feat_tvalid & fp_valid(1 to OVERLAY_FEAT_LAT_c - 1);
      fp_last  <= s_axis_feat_tlast & fp_last(1 to OVERLAY_FEAT_LAT_c - 1);
      fp_scale <= f_scale & fp_scale(1 to OVERLAY_FEAT_LAT_c - 1);
      if to_integer(f_scale) < SCALES_g then
        fp_ok <= '1' & fp_ok(1 to OVERLAY_FEAT_LAT_c - 1);
      else
        fp_ok <= '0' & fp_ok(1 to OVERLAY_FEAT_LAT_c - 1);
      end if;
      -- stage 1
      f1_x   <= unsigned(s_axis_feat_tdata(FEAT_X_LO_c + COORD_BITS_c - 1 downto FEAT_X_LO_c)) & '1';
      f1_y   <= unsigned(s_axis_feat_tdata(FEAT_Y_LO_c + COORD_BITS_c - 1 downto FEAT_Y_LO_c)) & '1';
      f1_mul <= (others => '0');
      f1_sub <= (others => '0');
      for j in 0 to SCALES_g - 1 loop
        if to_integer(f_scale) = j then
          f1_mul <= to_unsigned(NUM_POW_c(j), f1_mul'length);
          f1_sub <= to_unsigned(2 ** (j * DEN_LOG_c), PROD_BITS_c);
        end if;
      end loop;
      -- stage 2
      f2_px  <= resize(f1_x * f1_mul, PROD_BITS_c);
      f2_py  <= resize(f1_y * f1_mul, PROD_BITS_c);
      f2_sub <= f1_sub;
      -- stage 3
      f3_px <= f2_px - f2_sub;
      f3_py <= f2_py - f2_sub;
      -- stage 4
      k     := to_integer(fp_scale(3));
      f4_bx <= (others => '1');
      f4_by <= (others => '1');
      for j in 0 to SCALES_g - 1 loop
        if k = j then
          f4_bx <= to_block(shift_right(f3_px, 1 + j * DEN_LOG_c + BLOCK_LOG2_g));
          f4_by <= to_block(shift_right(f3_py, 1 + j * DEN_LOG_c + BLOCK_LOG2_g));
        end if;
      end loop;
      -- stage 5
      if f4_bx >= BLOCKS_X_c or f4_by >= BLOCKS_Y_c then
        fp_ok(5) <= '0';
      else
        fp_ok(5) <= fp_ok(4);
      end if;
      f5_bx  <= f4_bx;
      f5_row <= resize(resize(f4_by, ADDR_BITS_c) * BLOCKS_X_c, ADDR_BITS_c);
      -- stage 6
      f6_addr <= f5_row + resize(f5_bx, ADDR_BITS_c);
      if rst = '1' then
        fp_valid <= (others => '0');
      end if;
    end if;
  end process block_pipe;

  -- The bookkeeping takes the feature stream OVERLAY_FEAT_LAT_c clocks after the port (spec 13.3
  -- counts the beats there). Order within one clock edge: the video start of frame (swap) first,
  -- then the feature beat.
  frames : process (clk) is
    variable waiting_v : std_logic;
  begin
    if rising_edge(clk) then
      waiting_v := waiting and not swap;
      waiting   <= waiting_v;
      fw_en     <= '0';
      if fp_valid(OVERLAY_FEAT_LAT_c) = '1' then
        if fp_last(OVERLAY_FEAT_LAT_c) = '1' then
          if waiting_v = '0' and dropping = '0' then
            waiting <= '1';
          end if;
          dropping <= '0';
        elsif waiting_v = '1' or dropping = '1' then
          dropping <= '1';
        else
          fw_en <= fp_ok(OVERLAY_FEAT_LAT_c);
        end if;
        fw_bank  <= not sbank_n;
        fw_scale <= fp_scale(OVERLAY_FEAT_LAT_c);
        fw_addr  <= f6_addr;
      end if;
      if rst = '1' then
        waiting  <= '0';
        dropping <= '0';
        fw_en    <= '0';
      end if;
    end if;
  end process frames;

  -- ---- bitmap banks: per bank and scale a 1-bit simple dual-port RAM, registered read ----------
  gen_bank : for bank in 0 to 1 generate
    gen_scale : for s in 0 to SCALES_g - 1 generate
      signal q     : std_logic_vector(0 downto 0);
      signal mark  : std_logic;
      signal we    : std_logic;
      signal waddr : unsigned(ADDR_BITS_c - 1 downto 0);
    begin
      mark  <= '1' when fw_en = '1' and fw_bank = bit_of(bank) else
               '0';
      we    <= '1' when (mark = '1' and fw_scale = s) or (clr_en = '1' and clr_bank = bit_of(bank)) else
               '0';
      waddr <= fw_addr when mark = '1' else
               clr_addr;

      -- No initial value: 7-series block RAM configures to zero (INIT default), and a 32K-entry
      -- initialiser makes GHDL's netlist 12 MB. Unwritten bits read 'U' in simulation: not drawn.
      ram : entity work.orb_sdp_ram
        generic map (
          DATA_WIDTH_g => 1,
          DEPTH_g      => BLOCKS_c,
          LATENCY_g    => 1,
          INIT_ZERO_g  => false
        )
        port map (
          clk        => clk,
          wr_en      => we,
          wr_addr    => std_logic_vector(waddr),
          wr_data(0) => mark,
          rd_en      => ce,
          rd_addr    => std_logic_vector(rd_addr),
          out_en     => '1',
          rd_data    => q
        );

      rd_bits(bank * SCALES_g + s) <= q(0);
    end generate gen_scale;
  end generate gen_bank;

  -- pragma translate_off
  one_writer : process (clk) is
  begin
    if rising_edge(clk) then
      assert not (fw_en = '1' and clr_en = '1' and fw_bank = clr_bank)
        report "orb_overlay: a feature mark and a clear in the same bank on one clock"
        severity failure;
    end if;
  end process one_writer;
  -- pragma translate_on

  -- ---- video pipeline: stage 1 beside the RAM read, then the drawn output register -------------
  video : process (clk) is
    variable r : natural range 0 to 2 ** RING_BITS_c + SCALES_g - 1;
  begin
    if rising_edge(clk) then
      if ce = '1' then
        d1_valid <= s_axis_video_tvalid;
        d1_data  <= s_axis_video_tdata;
        d1_user  <= s_axis_video_tuser;
        d1_last  <= s_axis_video_tlast;
        d1_draw  <= in_frame;
        d1_bank  <= sbank_n;
        d1_ring  <= ring;
        -- stage 2: the bitmap bits registered, the one to test as a one-hot mask, the colour
        d2_valid <= d1_valid;
        d2_data  <= d1_data;
        d2_user  <= d1_user;
        d2_last  <= d1_last;
        d2_bits  <= rd_bits;
        d2_sel   <= (others => '0');
        r        := to_integer(d1_ring);
        if r < SCALES_g then
          d2_colour <= COLOURS_c(r);
          if d1_draw = '1' then
            if d1_bank = '1' then
              r := r + SCALES_g;
            end if;
            d2_sel(r) <= '1';
          end if;
        end if;
        -- output register
        m_valid <= d2_valid;
        m_user  <= d2_user;
        m_last  <= d2_last;
        m_data  <= d2_data;
        -- (bits never written read 'U' in simulation: only a '1' draws)
        for i in d2_sel'range loop
          if d2_bits(i) = '1' and d2_sel(i) = '1' then
            m_data <= d2_colour;
          end if;
        end loop;
      end if;
      if rst = '1' then
        d1_valid <= '0';
        d2_valid <= '0';
        m_valid  <= '0';
      end if;
    end if;
  end process video;

  s_axis_video_tready <= ce;
  m_axis_video_tdata  <= m_data;
  m_axis_video_tvalid <= m_valid;
  m_axis_video_tuser  <= m_user;
  m_axis_video_tlast  <= m_last;

end architecture rtl;
