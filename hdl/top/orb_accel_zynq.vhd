-- SPDX-License-Identifier: MIT
-- orb_accel_zynq: flat top-level wrapper of orb_accel_top for the Vivado block design
-- (docs/accelerator.md, "Flat wrapper for Vivado"). Xilinx-style port names (aclk, aresetn,
-- s_axi_ctrl_*, s_axis_video_*, m_axis_video_*, irq) and X_INTERFACE_INFO / X_INTERFACE_PARAMETER
-- attributes let Vivado infer the clock, reset, AXI4-Lite, AXI4-Stream and interrupt interfaces.
-- This file is kept to plain VHDL-93 constructs (integer and string generics, no expressions in
-- port maps, no VHDL-2008-only syntax) so Vivado can use it as a block-design module reference;
-- orb_accel_top below it stays VHDL-2008.
--
-- aresetn is synchronous and active low; orb_accel_top's rst is its inverse and, registered, one
-- clock more: the accelerator is reset at every edge that samples aresetn low (a one-clock pulse
-- too) and at the first edge that samples it high again, the edge after which AXI lets the
-- masters raise a valid. s_axis_video_tdata is
-- always 24 bits (the interface's TDATA width does not depend on INPUT_g); for INPUT_g = "LUMA"
-- the grey value is bits [7:0] and bits [23:8] are ignored. The AXI4-Lite address is
-- C_S_AXI_CTRL_ADDR_WIDTH bits; orb_accel_top decodes the low max(18, clog2(0x10000 +
-- 128 * MEM_DEPTH_g)) of them (20 for MEM_DEPTH_g = 4096), the bits above are ignored.
-- MEM_KIND_g "DDR" writes the features into a ring of DDR buffers through m_axi_feat (64-bit AXI4,
-- write only, for the PS7's S_AXI_HP0; docs/feature-dma.md) instead of the block-RAM banks; its
-- inputs are unused for "BRAM".
-- IDLE_TIMEOUT_g > 0 makes the video checker treat the input as a live source (HDMI through
-- v_vid_in_axi4s, which loses pixels when its FIFO is full): never held, pixels arriving while a
-- faulty frame is padded discarded, and an open frame idle IDLE_TIMEOUT_g clocks padded at once,
-- so that a frame cut by an unplugged cable is closed before the video returns; the default 4,096
-- clocks is longer than a line's blanking in every board mode (docs/board.md, "Recovery").
-- Ports and generics: docs/entities/orb_accel_zynq.md

library ieee;
use ieee.std_logic_1164.all;

-- Generic defaults: the named configuration orb_configs_pkg.TOPS_DEFAULT_c (docs/configurations.md),
-- written as literals for Vivado's module reference; tb/common/test_orb_configs_pkg.py checks them.
-- Legal generic values: docs/limits.md (orb_accel_top's generics have the orb_limits_pkg subtypes).
-- C_S_AXI_CTRL_ADDR_WIDTH: Xilinx's name for an AXI4-Lite address width, not the NAME_g style
-- vsg_off generic_600
entity orb_accel_zynq is
  generic (
    WIDTH_g                 : integer := 640;    -- frame width
    HEIGHT_g                : integer := 480;    -- frame height
    SCALES_g                : integer := 2;      -- scales (pyramid levels)
    STEP_NUM_g              : integer := 2;      -- pyramid step STEP_NUM_g:STEP_DEN_g
    STEP_DEN_g              : integer := 1;
    SECTORS_g               : integer := 32;     -- orientation sectors in all
    MEM_DEPTH_g             : integer := 1024;   -- feature slots per bank
    INPUT_g                 : string  := "RBG";  -- "RGB", "RBG" (Digilent dvi2rgb) or "LUMA"
    BLOCK_LOG2_g            : integer := 3;      -- overlay block size 2^BLOCK_LOG2_g
    IDLE_TIMEOUT_g          : integer := 4096;   -- HDMI: an open frame idle this many clocks is padded
    MEM_KIND_g              : string  := "BRAM"; -- "BRAM" (banks read over s_axi_ctrl) or "DDR" (m_axi_feat)
    WIN_BASE_MB_g           : integer := 0;      -- "DDR": the DDR window the ring must lie in, MiB
    WIN_SIZE_MB_g           : integer := 1024;   -- (the Zybo Z7-20's 1 GiB at 0)
    C_S_AXI_CTRL_ADDR_WIDTH : integer := 20      -- s_axi_ctrl address bits (at least 18)
  );
  -- vsg_on generic_600
  port (
    aclk    : in    std_logic;
    aresetn : in    std_logic;
    -- AXI4-Lite slave: registers below 0x10000, the feature memory above (docs/registers.md)
    s_axi_ctrl_awaddr  : in    std_logic_vector(C_S_AXI_CTRL_ADDR_WIDTH - 1 downto 0);
    s_axi_ctrl_awprot  : in    std_logic_vector(2 downto 0);
    s_axi_ctrl_awvalid : in    std_logic;
    s_axi_ctrl_awready : out   std_logic;
    s_axi_ctrl_wdata   : in    std_logic_vector(31 downto 0);
    s_axi_ctrl_wstrb   : in    std_logic_vector(3 downto 0);
    s_axi_ctrl_wvalid  : in    std_logic;
    s_axi_ctrl_wready  : out   std_logic;
    s_axi_ctrl_bresp   : out   std_logic_vector(1 downto 0);
    s_axi_ctrl_bvalid  : out   std_logic;
    s_axi_ctrl_bready  : in    std_logic;
    s_axi_ctrl_araddr  : in    std_logic_vector(C_S_AXI_CTRL_ADDR_WIDTH - 1 downto 0);
    s_axi_ctrl_arprot  : in    std_logic_vector(2 downto 0);
    s_axi_ctrl_arvalid : in    std_logic;
    s_axi_ctrl_arready : out   std_logic;
    s_axi_ctrl_rdata   : out   std_logic_vector(31 downto 0);
    s_axi_ctrl_rresp   : out   std_logic_vector(1 downto 0);
    s_axi_ctrl_rvalid  : out   std_logic;
    s_axi_ctrl_rready  : in    std_logic;
    -- AXI4-Stream video in (tuser = start of frame, tlast = end of line)
    s_axis_video_tdata  : in    std_logic_vector(23 downto 0);
    s_axis_video_tvalid : in    std_logic;
    s_axis_video_tready : out   std_logic;
    s_axis_video_tuser  : in    std_logic;
    s_axis_video_tlast  : in    std_logic;
    -- AXI4-Stream video out with the feature overlay (the input's packing; grey for "LUMA")
    m_axis_video_tdata  : out   std_logic_vector(23 downto 0);
    m_axis_video_tvalid : out   std_logic;
    m_axis_video_tready : in    std_logic;
    m_axis_video_tuser  : out   std_logic;
    m_axis_video_tlast  : out   std_logic;
    -- interrupt (level, active high)
    irq : out   std_logic;
    -- AXI4 write master to DDR (the PS7's S_AXI_HP0) of the "DDR" feature memory (docs/feature-dma.md);
    -- idle for "BRAM"
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

  -- Interface attributes for Vivado's IP integrator (UG994, "HDL Parameters for Interface
  -- Inference"). GHDL 2.0's synthesis crashes on any attribute of an input port
  -- (synth-vhdl_decls.adb:224, an assertion; output ports are fine), and `make lint` synthesises
  -- every entity with GHDL, and VHDL allows port attributes only here, so the two input-port
  -- pairs are left as comments below. The board build sets the same parameters on the module
  -- reference's pins instead (vivado/lib/bd.tcl: CONFIG.ASSOCIATED_BUSIF and ASSOCIATED_RESET on
  -- aclk, CONFIG.POLARITY ACTIVE_LOW on aresetn; docs/board.md), and tb/board checks they are set.
  --
  -- attribute x_interface_info of aclk         : signal is "xilinx.com:signal:clock:1.0 aclk CLK";
  -- attribute x_interface_parameter of aclk    : signal is
  --   "ASSOCIATED_BUSIF s_axi_ctrl:s_axis_video:m_axis_video:m_axi_feat, ASSOCIATED_RESET aresetn";
  -- attribute x_interface_info of aresetn      : signal is "xilinx.com:signal:reset:1.0 aresetn RST";
  -- attribute x_interface_parameter of aresetn : signal is "POLARITY ACTIVE_LOW";

  attribute x_interface_info      : string;
  attribute x_interface_parameter : string;

  attribute x_interface_info of irq      : signal is "xilinx.com:signal:interrupt:1.0 irq INTERRUPT";
  attribute x_interface_parameter of irq : signal is "SENSITIVITY LEVEL_HIGH";

  -- m_axi_feat: the master's outputs name the interface (its inputs cannot carry attributes here,
  -- above; Vivado infers the interface from the m_axi_feat_ prefix and these)
  attribute x_interface_info of m_axi_feat_awaddr       : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat AWADDR";
  attribute x_interface_parameter of m_axi_feat_awaddr  : signal is
    "PROTOCOL AXI4, DATA_WIDTH 64, ADDR_WIDTH 32, ID_WIDTH 1, READ_WRITE_MODE WRITE_ONLY, " &
    "MAX_BURST_LENGTH 8, NUM_WRITE_OUTSTANDING 4, NUM_READ_OUTSTANDING 0";
  attribute x_interface_info of m_axi_feat_awid    : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat AWID";
  attribute x_interface_info of m_axi_feat_awlen   : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat AWLEN";
  attribute x_interface_info of m_axi_feat_awsize  : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat AWSIZE";
  attribute x_interface_info of m_axi_feat_awburst : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat AWBURST";
  attribute x_interface_info of m_axi_feat_awcache : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat AWCACHE";
  attribute x_interface_info of m_axi_feat_awprot  : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat AWPROT";
  attribute x_interface_info of m_axi_feat_awvalid : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat AWVALID";
  attribute x_interface_info of m_axi_feat_wdata   : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat WDATA";
  attribute x_interface_info of m_axi_feat_wstrb   : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat WSTRB";
  attribute x_interface_info of m_axi_feat_wlast   : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat WLAST";
  attribute x_interface_info of m_axi_feat_wvalid  : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat WVALID";
  attribute x_interface_info of m_axi_feat_bready  : signal is "xilinx.com:interface:aximm:1.0 m_axi_feat BREADY";

end entity orb_accel_zynq;

architecture rtl of orb_accel_zynq is

  -- ceil(log2(n)) for n >= 1
  function ceil_log2 (n : positive) return natural is
    variable bits : natural;
    variable size : positive;
  begin
    bits := 0;
    size := 1;
    while size < n loop
      bits := bits + 1;
      size := size * 2;
    end loop;
    return bits;
  end function ceil_log2;

  -- orb_accel_top's AXI4-Lite address width: max(18, clog2(MEM_BASE + 2 banks * 64 bytes * depth))
  function top_addr_bits (depth : positive) return positive is
  begin
    if ceil_log2(16#10000# + 128 * depth) > 18 then
      return ceil_log2(16#10000# + 128 * depth);
    end if;
    return 18;
  end function top_addr_bits;

  -- orb_accel_top's s_axis_video_tdata width: 8 bits for "LUMA", else 24
  function top_data_bits (input : string) return positive is
  begin
    if input = "LUMA" then
      return 8;
    end if;
    return 24;
  end function top_data_bits;

  constant ADDR_BITS_c : positive := top_addr_bits(MEM_DEPTH_g);
  constant DATA_BITS_c : positive := top_data_bits(INPUT_g);

  signal rst_q      : std_logic := '1';  -- aresetn low a clock ago
  signal rst        : std_logic;
  signal top_awaddr : std_logic_vector(ADDR_BITS_c - 1 downto 0);
  signal top_araddr : std_logic_vector(ADDR_BITS_c - 1 downto 0);
  signal top_tdata  : std_logic_vector(DATA_BITS_c - 1 downto 0);

begin

  assert C_S_AXI_CTRL_ADDR_WIDTH >= ADDR_BITS_c
    report "orb_accel_zynq: C_S_AXI_CTRL_ADDR_WIDTH must be at least max(18, clog2(0x10000 + 128 * MEM_DEPTH_g))"
    severity failure;

  -- aresetn (synchronous, active low) to orb_accel_top's rst (synchronous, active high): at once, so that
  -- the accelerator is reset at the edge that samples aresetn low (AXI: no response is offered during a
  -- reset, however short), and one clock longer, registered
  reset_sync : process (aclk) is
  begin
    if rising_edge(aclk) then
      rst_q <= not aresetn;
    end if;
  end process reset_sync;

  rst <= (not aresetn) or rst_q;

  top_awaddr <= s_axi_ctrl_awaddr(ADDR_BITS_c - 1 downto 0);
  top_araddr <= s_axi_ctrl_araddr(ADDR_BITS_c - 1 downto 0);
  top_tdata  <= s_axis_video_tdata(DATA_BITS_c - 1 downto 0);

  accel : entity work.orb_accel_top
    generic map (
      WIDTH_g        => WIDTH_g,
      HEIGHT_g       => HEIGHT_g,
      SCALES_g       => SCALES_g,
      STEP_NUM_g     => STEP_NUM_g,
      STEP_DEN_g     => STEP_DEN_g,
      SECTORS_g      => SECTORS_g,
      MEM_DEPTH_g    => MEM_DEPTH_g,
      INPUT_g        => INPUT_g,
      BLOCK_LOG2_g   => BLOCK_LOG2_g,
      IDLE_TIMEOUT_g => IDLE_TIMEOUT_g,
      MEM_KIND_g     => MEM_KIND_g,
      WIN_BASE_MB_g  => WIN_BASE_MB_g,
      WIN_SIZE_MB_g  => WIN_SIZE_MB_g
    )
    port map (
      clk                 => aclk,
      rst                 => rst,
      s_axis_video_tdata  => top_tdata,
      s_axis_video_tvalid => s_axis_video_tvalid,
      s_axis_video_tready => s_axis_video_tready,
      s_axis_video_tuser  => s_axis_video_tuser,
      s_axis_video_tlast  => s_axis_video_tlast,
      m_axis_video_tdata  => m_axis_video_tdata,
      m_axis_video_tvalid => m_axis_video_tvalid,
      m_axis_video_tready => m_axis_video_tready,
      m_axis_video_tuser  => m_axis_video_tuser,
      m_axis_video_tlast  => m_axis_video_tlast,
      s_axil_awaddr       => top_awaddr,
      s_axil_awprot       => s_axi_ctrl_awprot,
      s_axil_awvalid      => s_axi_ctrl_awvalid,
      s_axil_awready      => s_axi_ctrl_awready,
      s_axil_wdata        => s_axi_ctrl_wdata,
      s_axil_wstrb        => s_axi_ctrl_wstrb,
      s_axil_wvalid       => s_axi_ctrl_wvalid,
      s_axil_wready       => s_axi_ctrl_wready,
      s_axil_bresp        => s_axi_ctrl_bresp,
      s_axil_bvalid       => s_axi_ctrl_bvalid,
      s_axil_bready       => s_axi_ctrl_bready,
      s_axil_araddr       => top_araddr,
      s_axil_arprot       => s_axi_ctrl_arprot,
      s_axil_arvalid      => s_axi_ctrl_arvalid,
      s_axil_arready      => s_axi_ctrl_arready,
      s_axil_rdata        => s_axi_ctrl_rdata,
      s_axil_rresp        => s_axi_ctrl_rresp,
      s_axil_rvalid       => s_axi_ctrl_rvalid,
      s_axil_rready       => s_axi_ctrl_rready,
      irq                 => irq,
      m_axi_feat_awid     => m_axi_feat_awid,
      m_axi_feat_awaddr   => m_axi_feat_awaddr,
      m_axi_feat_awlen    => m_axi_feat_awlen,
      m_axi_feat_awsize   => m_axi_feat_awsize,
      m_axi_feat_awburst  => m_axi_feat_awburst,
      m_axi_feat_awcache  => m_axi_feat_awcache,
      m_axi_feat_awprot   => m_axi_feat_awprot,
      m_axi_feat_awvalid  => m_axi_feat_awvalid,
      m_axi_feat_awready  => m_axi_feat_awready,
      m_axi_feat_wdata    => m_axi_feat_wdata,
      m_axi_feat_wstrb    => m_axi_feat_wstrb,
      m_axi_feat_wlast    => m_axi_feat_wlast,
      m_axi_feat_wvalid   => m_axi_feat_wvalid,
      m_axi_feat_wready   => m_axi_feat_wready,
      m_axi_feat_bid      => m_axi_feat_bid,
      m_axi_feat_bresp    => m_axi_feat_bresp,
      m_axi_feat_bvalid   => m_axi_feat_bvalid,
      m_axi_feat_bready   => m_axi_feat_bready
    );

end architecture rtl;
