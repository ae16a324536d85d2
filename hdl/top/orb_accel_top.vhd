-- SPDX-License-Identifier: MIT
-- orb_accel_top: the complete accelerator (docs/accelerator.md). Video in (AXI4-Stream, 24-bit
-- RGB, dvi2rgb's RBG packing or 8-bit luma, INPUT_g) is broadcast to the overlay and to the
-- feature path: orb_rgb_luma -> orb_frame_gate (CTRL.enable, sampled at each start of frame) ->
-- orb_video_check (the detector only ever sees complete frames; faulty ones are padded and
-- flagged) -> orb_core (SCALES_g scales of the STEP_NUM_g:STEP_DEN_g pyramid, SECTORS_g
-- orientation sectors, orb or fast mode) ->
-- the feature memory (MEM_KIND_g "BRAM": orb_feat_mem, two banks the CPU reads over AXI4-Lite;
-- "DDR": orb_feat_dma, a ring of frame buffers in DDR written through the AXI4 master m_axi_feat,
-- docs/feature-dma.md; a frame flagged bad by the checker is aborted there, never published) and
-- orb_overlay (the previous frame's features drawn on the
-- passing video, m_axis_video, in the input's packing). orb_axil_regs holds the registers
-- (docs/registers.md) and forwards reads at MEM_BASE_c and above to the feature memory. rst
-- resets everything (the AXI4 master at once); CTRL.soft_reset resets the video and feature path
-- (not the registers; a burst under way on m_axi_feat is finished), the
-- overlay once m_axis_video holds no beat waiting for the sink (a soft reset never withdraws a
-- beat without its handshake: AXI4-Stream, docs/formal.md).
-- Ports and generics: docs/entities/orb_accel_top.md

library ieee;
use ieee.std_logic_1164.all;
use ieee.numeric_std.all;

use work.orb_util_pkg.all;
use work.orb_latency_pkg.all;
use work.orb_feat_pkg.all;
use work.orb_regs_pkg.all;
use work.orb_limits_pkg.all;
use work.orb_configs_pkg.all;

entity orb_accel_top is
  generic (
    -- defaults: the named configuration TOPS_DEFAULT_c (docs/configurations.md); legal values:
    -- orb_limits_pkg (docs/limits.md)
    WIDTH_g      : width_t      := TOPS_DEFAULT_c.width;      -- frame width
    HEIGHT_g     : height_t     := TOPS_DEFAULT_c.height;     -- frame height
    SCALES_g     : scales_t     := TOPS_DEFAULT_c.scales;     -- scales (pyramid levels)
    STEP_NUM_g   : step_num_t   := TOPS_DEFAULT_c.step_num;   -- pyramid step STEP_NUM_g:STEP_DEN_g
    STEP_DEN_g   : step_den_t   := TOPS_DEFAULT_c.step_den;   -- (2:1: the box)
    SECTORS_g    : sectors_t    := TOPS_DEFAULT_c.sectors;    -- orientation sectors in all
    MEM_DEPTH_g  : mem_depth_t  := TOPS_DEFAULT_c.mem_depth;  -- feature slots per bank
    INPUT_g      : string       := "RGB";                     -- "RGB", "RBG" (dvi2rgb) or "LUMA"
    BLOCK_LOG2_g : block_log2_t := TOPS_DEFAULT_c.block_log2; -- overlay block size 2^BLOCK_LOG2_g
    -- orb_video_check's: 0 a source that waits while a faulty frame is padded; > 0 a live source
    -- (HDMI), never held, and the clocks an open frame's input may be idle (docs/video-input.md)
    IDLE_TIMEOUT_g : natural range 0 to 16777215 := 0;
    -- the feature memory: "BRAM" (two banks the CPU reads over AXI4-Lite, docs/feature-memory.md)
    -- or "DDR" (a ring of frame buffers in DDR written through m_axi_feat, docs/feature-dma.md)
    MEM_KIND_g    : string                    := "BRAM";
    DMA_FIFO_g    : positive range 16 to 4096 := 256; -- "DDR": slots the burst FIFO holds
    WIN_BASE_MB_g : natural range 0 to 4095   := 0;   -- "DDR": the window the ring must lie in, MiB
    WIN_SIZE_MB_g : positive range 1 to 4096  := 4096
  );
  port (
    clk : in    std_logic;
    rst : in    std_logic;
    -- video in
    s_axis_video_tdata  : in    std_logic_vector(8 + 16 * boolean'pos(INPUT_g /= "LUMA") - 1 downto 0);
    s_axis_video_tvalid : in    std_logic;
    s_axis_video_tready : out   std_logic;
    s_axis_video_tuser  : in    std_logic;
    s_axis_video_tlast  : in    std_logic;
    -- video out with the overlay (24 bit, the input's packing; grey as R = G = B for LUMA)
    m_axis_video_tdata  : out   std_logic_vector(23 downto 0);
    m_axis_video_tvalid : out   std_logic;
    m_axis_video_tready : in    std_logic;
    m_axis_video_tuser  : out   std_logic;
    m_axis_video_tlast  : out   std_logic;
    -- AXI4-Lite control and feature memory
    s_axil_awaddr  : in    std_logic_vector(maximum(18, clog2(MEM_BASE_c + 2 * 64 * MEM_DEPTH_g)) - 1 downto 0);
    s_axil_awprot  : in    std_logic_vector(2 downto 0);
    s_axil_awvalid : in    std_logic;
    s_axil_awready : out   std_logic;
    s_axil_wdata   : in    std_logic_vector(31 downto 0);
    s_axil_wstrb   : in    std_logic_vector(3 downto 0);
    s_axil_wvalid  : in    std_logic;
    s_axil_wready  : out   std_logic;
    s_axil_bresp   : out   std_logic_vector(1 downto 0);
    s_axil_bvalid  : out   std_logic;
    s_axil_bready  : in    std_logic;
    s_axil_araddr  : in    std_logic_vector(maximum(18, clog2(MEM_BASE_c + 2 * 64 * MEM_DEPTH_g)) - 1 downto 0);
    s_axil_arprot  : in    std_logic_vector(2 downto 0);
    s_axil_arvalid : in    std_logic;
    s_axil_arready : out   std_logic;
    s_axil_rdata   : out   std_logic_vector(31 downto 0);
    s_axil_rresp   : out   std_logic_vector(1 downto 0);
    s_axil_rvalid  : out   std_logic;
    s_axil_rready  : in    std_logic;
    irq            : out   std_logic;
    -- AXI4 write master of the "DDR" feature memory (idle for "BRAM", its inputs unused there)
    m_axi_feat_awid    : out   std_logic_vector(0 downto 0);
    m_axi_feat_awaddr  : out   std_logic_vector(31 downto 0);
    m_axi_feat_awlen   : out   std_logic_vector(7 downto 0);
    m_axi_feat_awsize  : out   std_logic_vector(2 downto 0);
    m_axi_feat_awburst : out   std_logic_vector(1 downto 0);
    m_axi_feat_awcache : out   std_logic_vector(3 downto 0);
    m_axi_feat_awprot  : out   std_logic_vector(2 downto 0);
    m_axi_feat_awvalid : out   std_logic;
    m_axi_feat_awready : in    std_logic;
    m_axi_feat_wdata   : out   std_logic_vector(63 downto 0);
    m_axi_feat_wstrb   : out   std_logic_vector(7 downto 0);
    m_axi_feat_wlast   : out   std_logic;
    m_axi_feat_wvalid  : out   std_logic;
    m_axi_feat_wready  : in    std_logic;
    m_axi_feat_bid     : in    std_logic_vector(0 downto 0);
    m_axi_feat_bresp   : in    std_logic_vector(1 downto 0);
    m_axi_feat_bvalid  : in    std_logic;
    m_axi_feat_bready  : out   std_logic
  );
end entity orb_accel_top;

architecture rtl of orb_accel_top is

  constant ADDR_BITS_c : positive := maximum(18, clog2(MEM_BASE_c + 2 * 64 * MEM_DEPTH_g));
  constant MEM_BITS_c  : positive := clog2(MEM_DEPTH_g) + 7;  -- byte offset into both banks
  -- the levels' selection slots, laid out one after the other (orb_core's scale paths)
  constant SEL_SLOTS_c : positive := maximum(2, level_base(MEM_DEPTH_g - 1, STEP_NUM_g, STEP_DEN_g, SCALES_g, SCALES_g));
  constant LUMA_c      : boolean  := INPUT_g = "LUMA";
  constant RBG_c       : boolean  := INPUT_g = "RBG";
  constant DDR_c       : boolean  := MEM_KIND_g = "DDR";

  -- resets
  signal soft_reset : std_logic;
  signal core_rst   : std_logic := '1';
  signal hard_rst   : std_logic := '1';  -- rst, one clock later like core_rst
  signal ov_soft    : std_logic := '0';  -- a soft reset the overlay has not had yet
  signal ov_rst     : std_logic;         -- the overlay's reset

  -- registers
  signal enable   : std_logic;
  signal mode_orb : std_logic;
  signal thr_lo   : std_logic_vector(7 downto 0);
  signal sel_grid : std_logic;
  signal sel_cols : std_logic_vector(GRID_BITS_c - 1 downto 0);
  signal sel_rows : std_logic_vector(GRID_BITS_c - 1 downto 0);
  signal budget   : std_logic_vector(SEL_SLOT_BITS_c - 1 downto 0);
  signal thresh   : std_logic_vector(7 downto 0);

  -- video broadcast
  signal in_ready   : std_logic;
  signal luma_ready : std_logic;
  signal ov_ready   : std_logic;
  signal ov_data    : std_logic_vector(23 downto 0);
  signal ov_out     : std_logic_vector(23 downto 0);

  -- luma stream, frame gate, checked stream
  signal l_data          : std_logic_vector(7 downto 0);
  signal l_valid         : std_logic;
  signal l_ready         : std_logic;
  signal l_user          : std_logic;
  signal l_last          : std_logic;
  signal g_valid         : std_logic;
  signal g_ready         : std_logic;
  signal c_data          : std_logic_vector(7 downto 0);
  signal c_valid         : std_logic;
  signal c_ready         : std_logic;
  signal c_user          : std_logic;
  signal c_last          : std_logic;
  signal frame_end       : std_logic;
  signal frame_bad       : std_logic;
  signal frame_abort     : std_logic;
  signal protocol_errors : std_logic_vector(31 downto 0);
  signal discarded       : std_logic_vector(31 downto 0);

  -- features
  signal f_data    : std_logic_vector(FEAT_BITS_c - 1 downto 0);
  signal f_valid   : std_logic;
  signal f_ready   : std_logic;
  signal f_last    : std_logic;
  signal mem_ready : std_logic;
  signal ovf_ready : std_logic;
  signal dropped   : std_logic_vector(31 downto 0);
  signal desc_lost : std_logic_vector(31 downto 0);
  signal frames    : unsigned(31 downto 0) := (others => '0');

  -- feature memory status and read port
  signal release_valid  : std_logic;
  signal release_bank   : std_logic_vector(BANK_RELEASE_BANK_MSB_c - BANK_RELEASE_BANK_LSB_c downto 0);
  signal mem_frame_done : std_logic;
  signal bank_ready     : std_logic_vector(1 downto 0);
  signal last_bank      : std_logic;
  signal bank0_count    : std_logic_vector(15 downto 0);
  signal bank0_frame    : std_logic_vector(15 downto 0);
  signal bank1_count    : std_logic_vector(15 downto 0);
  signal bank1_frame    : std_logic_vector(15 downto 0);
  signal overrun        : std_logic_vector(31 downto 0);
  signal overflow_count : std_logic_vector(31 downto 0);
  signal overflow       : std_logic;
  signal mem_rd_en      : std_logic;
  signal mem_rd_addr    : std_logic_vector(ADDR_BITS_c - 1 downto 0);
  signal mem_rd_data    : std_logic_vector(31 downto 0);
  signal error_pulse    : std_logic;

  -- the DDR ring (docs/feature-dma.md)
  signal ring_base    : std_logic_vector(31 downto 0);
  signal ring_stride  : std_logic_vector(31 downto 0);
  signal ring_count   : std_logic_vector(4 downto 0);
  signal ring_rel     : std_logic;
  signal ring_rel_idx : std_logic_vector(3 downto 0);
  signal ring_ready   : std_logic_vector(15 downto 0) := (others => '0');
  signal ring_last    : std_logic_vector(3 downto 0) := (others => '0');
  signal ring_error   : std_logic_vector(3 downto 0) := (others => '0');
  signal ring_busy    : std_logic := '0';
  signal ring_lcount  : std_logic_vector(15 downto 0) := (others => '0');
  signal ring_lframe  : std_logic_vector(15 downto 0) := (others => '0');
  signal dma_dropped  : std_logic_vector(31 downto 0) := (others => '0');
  signal dma_bus_err  : std_logic_vector(31 downto 0) := (others => '0');
  signal dma_beats    : std_logic_vector(31 downto 0) := (others => '0');
  signal dma_error    : std_logic := '0';

begin

  assert INPUT_g = "RGB" or INPUT_g = "RBG" or INPUT_g = "LUMA"
    report "orb_accel_top: INPUT_g must be ""RGB"", ""RBG"" or ""LUMA"""
    severity failure;

  assert sectors_legal(SECTORS_g)
    report "orb_accel_top: SECTORS_g (sectors in all) must be " & SECTORS_TEXT_c
    severity failure;

  assert mem_depth_legal(MEM_DEPTH_g)
    report "orb_accel_top: MEM_DEPTH_g must be " & MEM_DEPTH_TEXT_c
    severity failure;

  assert MEM_KIND_g = "BRAM" or MEM_KIND_g = "DDR"
    report "orb_accel_top: MEM_KIND_g must be ""BRAM"" or ""DDR"""
    severity failure;

  -- The soft reset (a register pulse) resets the video and feature path for one clock after it;
  -- the overlay in that clock too unless m_axis_video holds a beat the sink has not taken: then in
  -- the clock that takes it (the luma path is reset already; the input waits, ov_ready being 0).
  -- rst resets the overlay from its own clock on (and the clock after, with the rest).
  resets : process (clk) is
  begin
    if rising_edge(clk) then
      core_rst <= rst or soft_reset;
      hard_rst <= rst;
      if soft_reset = '1' then
        ov_soft <= '1';
      elsif ov_rst = '1' then
        ov_soft <= '0';
      end if;
      if rst = '1' then
        ov_soft <= '0';
      end if;
    end if;
  end process resets;

  -- rst itself too, so that no beat of before a reset is offered on m_axis_video after it
  ov_rst <= rst or hard_rst or (ov_soft and (m_axis_video_tready or not m_axis_video_tvalid));

  regs : entity work.orb_axil_regs
    generic map (
      WIDTH_g       => WIDTH_g,
      HEIGHT_g      => HEIGHT_g,
      SCALES_g      => SCALES_g,
      STEP_NUM_g    => STEP_NUM_g,
      STEP_DEN_g    => STEP_DEN_g,
      SECTORS_g     => SECTORS_g,
      MEM_DEPTH_g   => MEM_DEPTH_g,
      MEM_LATENCY_g => FEAT_MEM_READ_LAT_c,
      ADDR_BITS_g   => ADDR_BITS_c,
      MEM_DDR_g     => boolean'pos(DDR_c),
      WIN_BASE_MB_g => WIN_BASE_MB_g,
      WIN_SIZE_MB_g => WIN_SIZE_MB_g
    )
    port map (
      clk                => clk,
      rst                => rst,
      s_axil_awaddr      => s_axil_awaddr,
      s_axil_awprot      => s_axil_awprot,
      s_axil_awvalid     => s_axil_awvalid,
      s_axil_awready     => s_axil_awready,
      s_axil_wdata       => s_axil_wdata,
      s_axil_wstrb       => s_axil_wstrb,
      s_axil_wvalid      => s_axil_wvalid,
      s_axil_wready      => s_axil_wready,
      s_axil_bresp       => s_axil_bresp,
      s_axil_bvalid      => s_axil_bvalid,
      s_axil_bready      => s_axil_bready,
      s_axil_araddr      => s_axil_araddr,
      s_axil_arprot      => s_axil_arprot,
      s_axil_arvalid     => s_axil_arvalid,
      s_axil_arready     => s_axil_arready,
      s_axil_rdata       => s_axil_rdata,
      s_axil_rresp       => s_axil_rresp,
      s_axil_rvalid      => s_axil_rvalid,
      s_axil_rready      => s_axil_rready,
      enable             => enable,
      soft_reset         => soft_reset,
      mode_orb           => mode_orb,
      threshold          => thresh,
      threshold_lo       => thr_lo,
      select_grid        => sel_grid,
      grid_cols          => sel_cols,
      grid_rows          => sel_rows,
      budget             => budget,
      frame_count        => std_logic_vector(frames),
      dropped            => dropped,
      proto_errors       => protocol_errors,
      bank_ready         => bank_ready,
      last_bank          => last_bank,
      overflow           => overflow,
      bank0_count        => bank0_count,
      bank0_frame        => bank0_frame,
      bank1_count        => bank1_count,
      bank1_frame        => bank1_frame,
      overrun            => overrun,
      overflow_count     => overflow_count,
      desc_lost          => desc_lost,
      discarded          => discarded,
      frame_done_pulse   => mem_frame_done,
      error_pulse        => error_pulse,
      irq                => irq,
      release_valid      => release_valid,
      release_bank       => release_bank,
      ring_base          => ring_base,
      ring_stride        => ring_stride,
      ring_count         => ring_count,
      ring_release_valid => ring_rel,
      ring_release_index => ring_rel_idx,
      ring_ready         => ring_ready,
      ring_last          => ring_last,
      ring_error         => ring_error,
      ring_busy          => ring_busy,
      ring_last_count    => ring_lcount,
      ring_last_frame    => ring_lframe,
      dma_dropped        => dma_dropped,
      dma_bus_errors     => dma_bus_err,
      dma_beats          => dma_beats,
      mem_rd_en          => mem_rd_en,
      mem_rd_addr        => mem_rd_addr,
      mem_rd_data        => mem_rd_data
    );

  -- Video broadcast: a beat is taken when both the luma path and the overlay can take it.
  in_ready            <= luma_ready and ov_ready;
  s_axis_video_tready <= in_ready;

  luma : entity work.orb_rgb_luma
    generic map (
      INPUT_g => INPUT_g
    )
    port map (
      clk                 => clk,
      rst                 => core_rst,
      s_axis_video_tdata  => s_axis_video_tdata,
      s_axis_video_tvalid => s_axis_video_tvalid and ov_ready,
      s_axis_video_tready => luma_ready,
      s_axis_video_tuser  => s_axis_video_tuser,
      s_axis_video_tlast  => s_axis_video_tlast,
      m_axis_video_tdata  => l_data,
      m_axis_video_tvalid => l_valid,
      m_axis_video_tready => l_ready,
      m_axis_video_tuser  => l_user,
      m_axis_video_tlast  => l_last
    );

  -- Frame gate: CTRL.enable is sampled with each start of frame; the frames of a disabled
  -- accelerator are taken and ignored (the overlay still passes them). Out of reset the gate is
  -- open, so pixels of a frame cut by a (soft) reset reach orb_video_check and are counted there
  -- as pixels without a start of frame (docs/frame-gate.md). Data, tuser and tlast pass through
  -- the gate unchanged, so the checker takes them straight from the luma stream.
  gate : entity work.orb_frame_gate
    generic map (
      DATA_WIDTH_g => 8
    )
    port map (
      clk                 => clk,
      rst                 => core_rst,
      enable              => enable,
      s_axis_video_tdata  => l_data,
      s_axis_video_tvalid => l_valid,
      s_axis_video_tready => l_ready,
      s_axis_video_tuser  => l_user,
      s_axis_video_tlast  => l_last,
      m_axis_video_tdata  => open,
      m_axis_video_tvalid => g_valid,
      m_axis_video_tready => g_ready,
      m_axis_video_tuser  => open,
      m_axis_video_tlast  => open
    );

  check : entity work.orb_video_check
    generic map (
      WIDTH_g        => WIDTH_g,
      HEIGHT_g       => HEIGHT_g,
      IDLE_TIMEOUT_g => IDLE_TIMEOUT_g
    )
    port map (
      clk                 => clk,
      rst                 => core_rst,
      s_axis_video_tdata  => l_data,
      s_axis_video_tvalid => g_valid,
      s_axis_video_tready => g_ready,
      s_axis_video_tuser  => l_user,
      s_axis_video_tlast  => l_last,
      m_axis_video_tdata  => c_data,
      m_axis_video_tvalid => c_valid,
      m_axis_video_tready => c_ready,
      m_axis_video_tuser  => c_user,
      m_axis_video_tlast  => c_last,
      frame_end           => frame_end,
      frame_bad           => frame_bad,
      frame_fault         => open,
      protocol_errors     => protocol_errors,
      discarded_pixels    => discarded
    );

  -- A frame the checker had to pad is discarded by the feature memory (its end-of-frame beat
  -- leaves the detector after its last pixel, so the frame being written is this one).
  frame_abort <= frame_end and frame_bad;

  detect : entity work.orb_core
    generic map (
      WIDTH_g      => WIDTH_g,
      HEIGHT_g     => HEIGHT_g,
      SCALES_g     => SCALES_g,
      STEP_NUM_g   => STEP_NUM_g,
      STEP_DEN_g   => STEP_DEN_g,
      SECTORS_g    => SECTORS_g,
      DESC_g       => true,
      BUDGET_MAX_g => MEM_DEPTH_g - 1
    )
    port map (
      clk                 => clk,
      rst                 => core_rst,
      s_axis_video_tdata  => c_data,
      s_axis_video_tvalid => c_valid,
      s_axis_video_tready => c_ready,
      s_axis_video_tuser  => c_user,
      s_axis_video_tlast  => c_last,
      threshold           => thresh,
      threshold_lo        => thr_lo,
      mode_orb            => mode_orb,
      select_grid         => sel_grid,
      budget              => budget,
      grid_cols           => sel_cols,
      grid_rows           => sel_rows,
      m_axis_feat_tdata   => f_data,
      m_axis_feat_tvalid  => f_valid,
      m_axis_feat_tready  => f_ready,
      m_axis_feat_tlast   => f_last,
      dropped             => dropped,
      bad_pixels          => open,
      desc_lost           => desc_lost
    );

  -- Feature broadcast (both sinks always take a beat; the AND keeps it correct if one did not).
  f_ready <= mem_ready and ovf_ready;

  count_frames : process (clk) is
  begin
    if rising_edge(clk) then
      if f_valid = '1' and f_ready = '1' and f_last = '1' then
        frames <= frames + 1;
      end if;
      if core_rst = '1' then
        frames <= (others => '0');
      end if;
    end if;
  end process count_frames;

  error_pulse <= frame_abort or dma_error;

  -- The block-RAM feature memory: two banks the CPU reads through the register block's window.
  gen_bram : if not DDR_c generate
    mem : entity work.orb_feat_mem
      generic map (
        DEPTH_g     => MEM_DEPTH_g,
        SEL_SLOTS_g => SEL_SLOTS_c
      )
      port map (
        clk                => clk,
        rst                => core_rst,
        s_axis_feat_tdata  => f_data,
        s_axis_feat_tvalid => f_valid and ovf_ready,
        s_axis_feat_tready => mem_ready,
        s_axis_feat_tlast  => f_last,
        frame_abort        => frame_abort,
        release_valid      => release_valid,
        release_bank       => release_bank(0),
        frame_done         => mem_frame_done,
        bank_ready         => bank_ready,
        bank_truncated     => open,
        last_bank          => last_bank,
        bank0_count        => bank0_count,
        bank0_frame        => bank0_frame,
        bank0_dropped      => open,
        bank0_trunc        => open,
        bank1_count        => bank1_count,
        bank1_frame        => bank1_frame,
        bank1_dropped      => open,
        bank1_trunc        => open,
        overrun            => overrun,
        overflow           => overflow_count,
        aborted            => open,
        mem_rd_en          => mem_rd_en,
        mem_rd_addr        => mem_rd_addr(MEM_BITS_c - 1 downto 0),
        mem_rd_data        => mem_rd_data
      );

    m_axi_feat_awid    <= (others => '0');
    m_axi_feat_awaddr  <= (others => '0');
    m_axi_feat_awlen   <= (others => '0');
    m_axi_feat_awsize  <= (others => '0');
    m_axi_feat_awburst <= (others => '0');
    m_axi_feat_awcache <= (others => '0');
    m_axi_feat_awprot  <= (others => '0');
    m_axi_feat_awvalid <= '0';
    m_axi_feat_wdata   <= (others => '0');
    m_axi_feat_wstrb   <= (others => '0');
    m_axi_feat_wlast   <= '0';
    m_axi_feat_wvalid  <= '0';
    m_axi_feat_bready  <= '0';
  end generate gen_bram;

  -- The DDR feature memory: the ring of frame buffers, written through m_axi_feat; the soft reset
  -- never cuts a burst (core_rst), the AXI reset (rst) resets the master at once.
  gen_ddr : if DDR_c generate
    dma : entity work.orb_feat_dma
      generic map (
        DEPTH_g       => MEM_DEPTH_g,
        SEL_SLOTS_g   => SEL_SLOTS_c,
        FIFO_DEPTH_g  => DMA_FIFO_g,
        OUTSTANDING_g => 4,
        WIN_BASE_MB_g => WIN_BASE_MB_g,
        WIN_SIZE_MB_g => WIN_SIZE_MB_g
      )
      port map (
        clk                => clk,
        rst                => core_rst,
        bus_rst            => rst,
        s_axis_feat_tdata  => f_data,
        s_axis_feat_tvalid => f_valid and ovf_ready,
        s_axis_feat_tready => mem_ready,
        s_axis_feat_tlast  => f_last,
        frame_abort        => frame_abort,
        ring_base          => ring_base,
        ring_stride        => ring_stride,
        ring_count         => ring_count,
        release_valid      => ring_rel,
        release_index      => ring_rel_idx,
        frame_done         => mem_frame_done,
        dma_error          => dma_error,
        ring_ready         => ring_ready,
        ring_last          => ring_last,
        ring_error         => ring_error,
        busy               => ring_busy,
        last_count         => ring_lcount,
        last_frame         => ring_lframe,
        overrun            => overrun,
        overflow           => overflow_count,
        aborted            => open,
        dma_dropped        => dma_dropped,
        bus_errors         => dma_bus_err,
        beats              => dma_beats,
        m_axi_feat_awid    => m_axi_feat_awid,
        m_axi_feat_awaddr  => m_axi_feat_awaddr,
        m_axi_feat_awlen   => m_axi_feat_awlen,
        m_axi_feat_awsize  => m_axi_feat_awsize,
        m_axi_feat_awburst => m_axi_feat_awburst,
        m_axi_feat_awcache => m_axi_feat_awcache,
        m_axi_feat_awprot  => m_axi_feat_awprot,
        m_axi_feat_awvalid => m_axi_feat_awvalid,
        m_axi_feat_awready => m_axi_feat_awready,
        m_axi_feat_wdata   => m_axi_feat_wdata,
        m_axi_feat_wstrb   => m_axi_feat_wstrb,
        m_axi_feat_wlast   => m_axi_feat_wlast,
        m_axi_feat_wvalid  => m_axi_feat_wvalid,
        m_axi_feat_wready  => m_axi_feat_wready,
        m_axi_feat_bid     => m_axi_feat_bid,
        m_axi_feat_bresp   => m_axi_feat_bresp,
        m_axi_feat_bvalid  => m_axi_feat_bvalid,
        m_axi_feat_bready  => m_axi_feat_bready
      );

    bank_ready  <= (others => '0');
    last_bank   <= '0';
    bank0_count <= (others => '0');
    bank0_frame <= (others => '0');
    bank1_count <= (others => '0');
    bank1_frame <= (others => '0');
    mem_rd_data <= (others => '0');
  end generate gen_ddr;

  overflow <= '1' when unsigned(overflow_count) /= 0 else
              '0';

  -- The overlay works on R [23:16], G [15:8], B [7:0]; other packings are reordered around it.
  gen_luma : if LUMA_c generate
    ov_data <= s_axis_video_tdata(7 downto 0) & s_axis_video_tdata(7 downto 0) & s_axis_video_tdata(7 downto 0);
  end generate gen_luma;

  gen_rbg : if RBG_c generate
    ov_data            <= s_axis_video_tdata(23 downto 16) & s_axis_video_tdata(7 downto 0) &
                          s_axis_video_tdata(15 downto 8);
    m_axis_video_tdata <= ov_out(23 downto 16) & ov_out(7 downto 0) & ov_out(15 downto 8);
  end generate gen_rbg;

  gen_rgb : if not RBG_c generate
    m_axis_video_tdata <= ov_out;
  end generate gen_rgb;

  gen_rgb_in : if not LUMA_c and not RBG_c generate
    ov_data <= s_axis_video_tdata;
  end generate gen_rgb_in;

  overlay : entity work.orb_overlay
    generic map (
      WIDTH_g      => WIDTH_g,
      HEIGHT_g     => HEIGHT_g,
      SCALES_g     => SCALES_g,
      STEP_NUM_g   => STEP_NUM_g,
      STEP_DEN_g   => STEP_DEN_g,
      BLOCK_LOG2_g => BLOCK_LOG2_g
    )
    port map (
      clk                 => clk,
      rst                 => ov_rst,
      s_axis_video_tdata  => ov_data,
      s_axis_video_tvalid => s_axis_video_tvalid and luma_ready,
      s_axis_video_tready => ov_ready,
      s_axis_video_tuser  => s_axis_video_tuser,
      s_axis_video_tlast  => s_axis_video_tlast,
      m_axis_video_tdata  => ov_out,
      m_axis_video_tvalid => m_axis_video_tvalid,
      m_axis_video_tready => m_axis_video_tready,
      m_axis_video_tuser  => m_axis_video_tuser,
      m_axis_video_tlast  => m_axis_video_tlast,
      s_axis_feat_tdata   => f_data,
      s_axis_feat_tvalid  => f_valid and mem_ready,
      s_axis_feat_tready  => ovf_ready,
      s_axis_feat_tlast   => f_last
    );

end architecture rtl;
