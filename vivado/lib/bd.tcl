# SPDX-License-Identifier: MIT
# The block design (docs/board.md, "Block design"). Clock domains:
#   core   clk_wiz from FCLK0 (100 MHz) at the configuration's core clock: orb_accel_zynq, its
#          AXI4-Lite (M_AXI_GP0 and the interconnect), the AXI4-Stream sides of both video bridges,
#          and in a DDR build its AXI4 write master m_axi_feat, the interconnect feat_ic and the
#          PS7's S_AXI_HP0 (S_AXI_HP0_ACLK: the HP port's FIFOs cross into the PS inside the PS7).
#          It never stops while the PS runs, so a CPU access always completes, cable or not.
#   pixel  dvi2rgb's PixelClk, recovered from the HDMI input: v_tc, the video sides of the bridges,
#          rgb2dvi (which makes its own 5x serial clock). It stops when the cable is pulled.
#   ref    FCLK1 200 MHz: dvi2rgb's RefClk (IDELAYCTRL) only.
# The bridges' asynchronous FIFOs are the only crossings between pixel and core (C_HAS_ASYNC_CLK).
# A frame cut by a lost link is discarded and counted by orb_accel_zynq's checker when the next
# start of frame arrives (docs/frame-gate.md); the video sides are held in reset while dvi2rgb
# has no lock (pLocked), the core side keeps running.

proc orb_cell {vlnv name {props {}}} {
  set cell [create_bd_cell -type ip -vlnv $vlnv $name]
  if {[llength $props]} {
    set_property -dict $props $cell
  }
  return $cell
}

proc orb_net {args} {
  set pins {}
  foreach p $args {
    if {[string match "port:*" $p]} {
      lappend pins [get_bd_ports [string range $p 5 end]]
    } else {
      lappend pins [get_bd_pins $p]
    }
  }
  connect_bd_net {*}$pins
}

proc orb_intf {a b} {
  set ends {}
  foreach p [list $a $b] {
    if {[string match "port:*" $p]} {
      lappend ends [get_bd_intf_ports [string range $p 5 end]]
    } else {
      lappend ends [get_bd_intf_pins $p]
    }
  }
  connect_bd_intf_net {*}$ends
}

# MiB as the hexadecimal byte address assign_bd_address takes
proc orb_mb_hex {mb} {
  return [format 0x%08X [expr {$mb * 1048576}]]
}

proc orb_create_bd {design cfg board_part} {
  set acc $::orb_board::accel
  set dma $::orb_board::feat_dma
  # a DDR build: the feature memory writes its ring into DDR through m_axi_feat -> feat_ic -> S_AXI_HP0
  set ddr [expr {[dict get $cfg mem_kind] eq "ddr"}]
  create_bd_design $design
  current_bd_design $design

  # --- processing system, clocks and resets ---------------------------------------------------
  set ps7 [orb_cell xilinx.com:ip:processing_system7 ps7]
  orb_config_ps7 $ps7 $board_part $cfg
  orb_cell xilinx.com:ip:clk_wiz core_clk [list \
    CONFIG.PRIM_IN_FREQ $::orb_board::fclk0_mhz \
    CONFIG.PRIM_SOURCE {No_buffer} \
    CONFIG.CLKOUT1_REQUESTED_OUT_FREQ [dict get $cfg core_mhz] \
    CONFIG.USE_RESET {false} \
    CONFIG.USE_LOCKED {true} \
  ]
  orb_cell xilinx.com:ip:proc_sys_reset core_rst
  orb_cell xilinx.com:ip:proc_sys_reset ref_rst
  orb_cell xilinx.com:ip:proc_sys_reset pix_rst
  orb_cell xilinx.com:ip:xlconstant one [list CONFIG.CONST_VAL {1} CONFIG.CONST_WIDTH {1}]

  # --- HDMI in, video in, timing, video out, HDMI out -----------------------------------------
  orb_cell digilentinc.com:ip:dvi2rgb hdmi_in [list \
    CONFIG.kEmulateDDC {true} \
    CONFIG.kRstActiveHigh {false} \
    CONFIG.kAddBUFG {true} \
    CONFIG.kClkRange [dict get $cfg kClkRange] \
    CONFIG.kEdidFileName [dict get $cfg edid] \
    CONFIG.kDebug {false} \
  ]
  orb_cell xilinx.com:ip:v_vid_in_axi4s vid_in [list \
    CONFIG.C_HAS_ASYNC_CLK {1} \
    CONFIG.C_ADDR_WIDTH {12} \
  ]
  orb_cell xilinx.com:ip:v_tc vtc [list \
    CONFIG.HAS_AXI4_LITE {false} \
    CONFIG.HAS_INTC_IF {false} \
    CONFIG.enable_detection {true} \
    CONFIG.enable_generation {true} \
    CONFIG.auto_generation_mode {true} \
  ]
  orb_cell xilinx.com:ip:v_axi4s_vid_out vid_out [list \
    CONFIG.C_HAS_ASYNC_CLK {1} \
    CONFIG.C_VTG_MASTER_SLAVE {1} \
    CONFIG.C_ADDR_WIDTH {12} \
  ]
  orb_cell digilentinc.com:ip:rgb2dvi hdmi_out [list \
    CONFIG.kGenerateSerialClk {true} \
    CONFIG.kClkPrimitive {MMCM} \
    CONFIG.kClkRange [dict get $cfg kClkRange] \
    CONFIG.kRstActiveHigh {false} \
  ]

  # --- the accelerator: module reference to the flat VHDL wrapper ------------------------------
  set accel [dict get $acc cell]
  create_bd_cell -type module -reference [dict get $acc entity] $accel
  set_property -dict [list \
    CONFIG.WIDTH_g [dict get $cfg width] \
    CONFIG.HEIGHT_g [dict get $cfg height] \
    CONFIG.SCALES_g [dict get $cfg scales] \
    CONFIG.STEP_NUM_g [dict get $cfg step_num] \
    CONFIG.STEP_DEN_g [dict get $cfg step_den] \
    CONFIG.SECTORS_g [dict get $cfg sectors] \
    CONFIG.MEM_DEPTH_g [dict get $cfg mem_depth] \
    CONFIG.INPUT_g [dict get $acc input] \
    CONFIG.BLOCK_LOG2_g [dict get $cfg block_log2] \
    CONFIG.MEM_KIND_g [string toupper [dict get $cfg mem_kind]] \
    CONFIG.WIN_BASE_MB_g [dict get $dma win_base_mb] \
    CONFIG.WIN_SIZE_MB_g [dict get $dma win_size_mb] \
    CONFIG.C_S_AXI_CTRL_ADDR_WIDTH [dict get $acc addr_width] \
  ] [get_bd_cells $accel]
  # The interface parameters GHDL 2.0 cannot carry as port attributes (orb_accel_zynq.vhd): aclk
  # clocks the four interfaces, aresetn is active low.
  set_property CONFIG.ASSOCIATED_BUSIF {s_axi_ctrl:s_axis_video:m_axis_video:m_axi_feat} [get_bd_pins $accel/aclk]
  set_property CONFIG.ASSOCIATED_RESET {aresetn} [get_bd_pins $accel/aclk]
  set_property CONFIG.POLARITY {ACTIVE_LOW} [get_bd_pins $accel/aresetn]
  orb_cell xilinx.com:ip:axi_interconnect ctrl_ic [list CONFIG.NUM_MI {1}]
  # m_axi_feat (AXI4, 64 bits, write only, 8-bit AWLEN) -> S_AXI_HP0 (AXI3, 64 bits, WID): one master,
  # one slave, so no crossbar; the interconnect converts AXI4 to AXI3 (docs/board.md, "Features to DDR")
  set feat_ic [dict get $dma interconnect]
  if {$ddr} {
    orb_cell xilinx.com:ip:axi_interconnect $feat_ic [list CONFIG.NUM_SI {1} CONFIG.NUM_MI {1}]
  }
  orb_cell xilinx.com:ip:xlconcat leds [list CONFIG.NUM_PORTS {4}]

  # --- external ports (vivado/xdc/zybo_z7_20.xdc) ---------------------------------------------------
  # (the wrapper names an interface port's members <port>_<member>: hdmi_rx_clk_p, hdmi_rx_data_p[0],
  # hdmi_rx_ddc_scl_io, as in Digilent's own HDMI demo; the XDC uses those names)
  create_bd_intf_port -mode Slave -vlnv digilentinc.com:interface:tmds_rtl:1.0 hdmi_rx
  create_bd_intf_port -mode Master -vlnv xilinx.com:interface:iic_rtl:1.0 hdmi_rx_ddc
  create_bd_port -dir O hdmi_rx_hpd
  create_bd_intf_port -mode Master -vlnv digilentinc.com:interface:tmds_rtl:1.0 hdmi_tx
  create_bd_port -dir O -from 3 -to 0 led

  # --- connections ------------------------------------------------------------------------------
  # clocks (the HP port and feat_ic on the accelerator's clock: no crossing in the fabric)
  set hp [dict get $dma hp_port]
  set core_loads [list ps7/M_AXI_GP0_ACLK ctrl_ic/ACLK ctrl_ic/S00_ACLK ctrl_ic/M00_ACLK \
    core_rst/slowest_sync_clk $accel/aclk vid_in/aclk vid_out/aclk]
  set ic_resets [list ctrl_ic/ARESETN]
  set peripheral_resets [list ctrl_ic/S00_ARESETN ctrl_ic/M00_ARESETN]
  if {$ddr} {
    lappend core_loads ps7/${hp}_ACLK $feat_ic/ACLK $feat_ic/S00_ACLK $feat_ic/M00_ACLK
    lappend ic_resets $feat_ic/ARESETN
    lappend peripheral_resets $feat_ic/S00_ARESETN $feat_ic/M00_ARESETN
  }
  orb_net ps7/FCLK_CLK0 core_clk/clk_in1
  orb_net core_clk/clk_out1 {*}$core_loads
  orb_net ps7/FCLK_CLK1 hdmi_in/RefClk ref_rst/slowest_sync_clk
  orb_net hdmi_in/PixelClk pix_rst/slowest_sync_clk vid_in/vid_io_in_clk vtc/clk vid_out/vid_io_out_clk \
    hdmi_out/PixelClk
  # resets
  orb_net ps7/FCLK_RESET0_N core_rst/ext_reset_in ref_rst/ext_reset_in pix_rst/ext_reset_in
  orb_net core_clk/locked core_rst/dcm_locked leds/In2
  orb_net core_rst/interconnect_aresetn {*}$ic_resets
  orb_net core_rst/peripheral_aresetn {*}$peripheral_resets $accel/aresetn vid_in/aresetn vid_out/aresetn
  orb_net ref_rst/peripheral_aresetn hdmi_in/aRst_n
  orb_net hdmi_in/pLocked pix_rst/aux_reset_in hdmi_out/aRst_n leds/In0
  orb_net pix_rst/peripheral_reset vid_in/vid_io_in_reset vid_out/vid_io_out_reset
  orb_net pix_rst/peripheral_aresetn vtc/resetn
  # clock enables and constants
  orb_net one/dout vid_in/vid_io_in_ce vid_in/aclken vid_in/axis_enable vtc/clken vtc/det_clken \
    vid_out/aclken vid_out/vid_io_out_ce port:hdmi_rx_hpd
  orb_net vid_out/vtg_ce vtc/gen_clken
  # HDMI: the TMDS pins belong to the IPs' TMDS bus interfaces, so they are reached through them
  orb_intf port:hdmi_rx hdmi_in/TMDS
  orb_intf hdmi_out/TMDS port:hdmi_tx
  orb_intf port:hdmi_rx_ddc hdmi_in/DDC
  # video
  orb_intf hdmi_in/RGB vid_in/vid_io_in
  orb_intf vid_in/video_out $accel/s_axis_video
  orb_intf vid_in/vtiming_out vtc/vtiming_in
  orb_intf $accel/m_axis_video vid_out/video_in
  orb_intf vtc/vtiming_out vid_out/vtiming_in
  orb_intf vid_out/vid_io_out hdmi_out/RGB
  # CPU
  orb_intf ps7/M_AXI_GP0 ctrl_ic/S00_AXI
  orb_intf ctrl_ic/M00_AXI $accel/s_axi_ctrl
  orb_net $accel/irq ps7/IRQ_F2P
  # features to DDR (a BRAM build leaves m_axi_feat unconnected: its master never raises a valid)
  if {$ddr} {
    orb_intf $accel/m_axi_feat $feat_ic/S00_AXI
    orb_intf $feat_ic/M00_AXI ps7/$hp
  }
  # status LEDs: LD0 HDMI in locked, LD1 HDMI out locked, LD2 core clock locked, LD3 input FIFO overflow
  orb_net vid_out/locked leds/In1
  orb_net vid_in/overflow leds/In3
  orb_net leds/dout port:led

  # --- address map: the accelerator at its one address (vivado/board.json) -----------------------
  assign_bd_address -offset [dict get $acc base] -range [dict get $acc range] \
    -target_address_space [get_bd_addr_spaces ps7/Data] [get_bd_addr_segs $accel/s_axi_ctrl/reg0]
  # and in a DDR build the master's view of DDR through the HP port: exactly the window the
  # accelerator checks the ring against (WIN_BASE_MB_g, WIN_SIZE_MB_g above)
  if {$ddr} {
    assign_bd_address -offset [orb_mb_hex [dict get $dma win_base_mb]] \
      -range [orb_mb_hex [dict get $dma win_size_mb]] -target_address_space [get_bd_addr_spaces $accel/m_axi_feat] \
      [get_bd_addr_segs ps7/$hp/[dict get $dma hp_segment]]
  }

  validate_bd_design
  save_bd_design
}
