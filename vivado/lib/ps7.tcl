# SPDX-License-Identifier: MIT
# The Zynq PS7 of the Zybo Z7-20 (docs/board.md). With Digilent's board files the board preset is
# applied; without them these explicit settings give the same peripherals as on the board: DDR3L
# MT41K256M16 RE-125 (1 GiB, 32 bit, 533 MHz) with the board's trace delays, QSPI flash, Ethernet 0
# (RGMII on MIO 16..27, MDIO on 52..53), SD 0 (MIO 40..45, card detect 47), USB 0 (ULPI MIO 28..39,
# reset 46), UART 1 (MIO 48..49, 115200), MIO GPIO, bank voltages 3.3 V / 1.8 V. The values are
# the board's facts as Digilent's Vivado 2023.1 Zybo Z7-20 HDMI demo sets them (vivado/facts/ip/
# xilinx.com_processing_system7.json names the source; tb/board checks each name and value there).
# Then the design's own settings: FCLK0 100 MHz (core-clock reference), FCLK1 200 MHz (dvi2rgb
# RefClk), M_AXI_GP0, one fabric interrupt IRQ_F2P, and for a DDR build (mem_kind ddr) the slave port
# the feature master writes the ring through: S_AXI_HP0, 64 bits (vivado/board.json feat_dma; in
# 64-bit mode the HP port passes the PL's transactions to the PS as they are, UG585 5.3).

proc orb_ps7_board_settings {} {
  return [dict create \
    PCW_PRESET_BANK0_VOLTAGE {LVCMOS 3.3V} \
    PCW_PRESET_BANK1_VOLTAGE {LVCMOS 1.8V} \
    PCW_CRYSTAL_PERIPHERAL_FREQMHZ {33.333333} \
    PCW_APU_PERIPHERAL_FREQMHZ {667} \
    PCW_UIPARAM_DDR_ENABLE {1} \
    PCW_UIPARAM_DDR_MEMORY_TYPE {DDR 3 (Low Voltage)} \
    PCW_UIPARAM_DDR_PARTNO {MT41K256M16 RE-125} \
    PCW_UIPARAM_DDR_BUS_WIDTH {32 Bit} \
    PCW_UIPARAM_DDR_FREQ_MHZ {533.333333} \
    PCW_UIPARAM_DDR_TRAIN_DATA_EYE {1} \
    PCW_UIPARAM_DDR_TRAIN_READ_GATE {1} \
    PCW_UIPARAM_DDR_TRAIN_WRITE_LEVEL {1} \
    PCW_UIPARAM_DDR_USE_INTERNAL_VREF {0} \
    PCW_UIPARAM_DDR_BOARD_DELAY0 {0.221} \
    PCW_UIPARAM_DDR_BOARD_DELAY1 {0.222} \
    PCW_UIPARAM_DDR_BOARD_DELAY2 {0.217} \
    PCW_UIPARAM_DDR_BOARD_DELAY3 {0.244} \
    PCW_UIPARAM_DDR_DQS_TO_CLK_DELAY_0 {-0.050} \
    PCW_UIPARAM_DDR_DQS_TO_CLK_DELAY_1 {-0.044} \
    PCW_UIPARAM_DDR_DQS_TO_CLK_DELAY_2 {-0.035} \
    PCW_UIPARAM_DDR_DQS_TO_CLK_DELAY_3 {-0.100} \
    PCW_QSPI_PERIPHERAL_ENABLE {1} \
    PCW_QSPI_GRP_SINGLE_SS_ENABLE {1} \
    PCW_QSPI_GRP_FBCLK_ENABLE {1} \
    PCW_QSPI_GRP_FBCLK_IO {MIO 8} \
    PCW_SINGLE_QSPI_DATA_MODE {x4} \
    PCW_ENET0_PERIPHERAL_ENABLE {1} \
    PCW_ENET0_ENET0_IO {MIO 16 .. 27} \
    PCW_ENET0_GRP_MDIO_ENABLE {1} \
    PCW_ENET0_GRP_MDIO_IO {MIO 52 .. 53} \
    PCW_ENET0_PERIPHERAL_FREQMHZ {1000 Mbps} \
    PCW_SD0_PERIPHERAL_ENABLE {1} \
    PCW_SD0_SD0_IO {MIO 40 .. 45} \
    PCW_SD0_GRP_CD_ENABLE {1} \
    PCW_SD0_GRP_CD_IO {MIO 47} \
    PCW_SDIO_PERIPHERAL_FREQMHZ {50} \
    PCW_USB0_PERIPHERAL_ENABLE {1} \
    PCW_USB0_USB0_IO {MIO 28 .. 39} \
    PCW_USB0_RESET_ENABLE {1} \
    PCW_USB0_RESET_IO {MIO 46} \
    PCW_UART1_PERIPHERAL_ENABLE {1} \
    PCW_UART1_UART1_IO {MIO 48 .. 49} \
    PCW_UART1_BAUD_RATE {115200} \
    PCW_GPIO_MIO_GPIO_ENABLE {1} \
  ]
}

# the design's settings, applied after the board preset or the explicit board settings; cfg is the
# configuration (vivado/gen/board.tcl)
proc orb_ps7_design_settings {cfg} {
  set settings [dict create \
    PCW_USE_M_AXI_GP0 {1} \
    PCW_FPGA_FCLK0_ENABLE {1} \
    PCW_FPGA0_PERIPHERAL_FREQMHZ $::orb_board::fclk0_mhz \
    PCW_EN_CLK1_PORT {1} \
    PCW_FPGA_FCLK1_ENABLE {1} \
    PCW_FPGA1_PERIPHERAL_FREQMHZ $::orb_board::fclk1_mhz \
    PCW_USE_FABRIC_INTERRUPT {1} \
    PCW_IRQ_F2P_INTR {1} \
  ]
  if {[dict get $cfg mem_kind] eq "ddr"} {
    set dma $::orb_board::feat_dma
    dict set settings PCW_USE_[dict get $dma hp_port] 1
    dict set settings PCW_[dict get $dma hp_port]_DATA_WIDTH [dict get $dma hp_data_width]
  }
  return $settings
}

# The board preset (board files) or the explicit settings; DDR and FIXED_IO made external either way.
proc orb_config_ps7 {cell board_part cfg} {
  if {$board_part ne ""} {
    apply_bd_automation -rule xilinx.com:bd_rule:processing_system7 \
      -config {make_external "FIXED_IO, DDR" apply_board_preset "1" Master "Disable" Slave "Disable"} $cell
  } else {
    set props {}
    dict for {k v} [orb_ps7_board_settings] { lappend props CONFIG.$k $v }
    set_property -dict $props $cell
    create_bd_intf_port -mode Master -vlnv xilinx.com:interface:ddrx_rtl:1.0 DDR
    create_bd_intf_port -mode Master -vlnv xilinx.com:display_processing_system7:fixedio_rtl:1.0 FIXED_IO
    connect_bd_intf_net [get_bd_intf_ports DDR] [get_bd_intf_pins $cell/DDR]
    connect_bd_intf_net [get_bd_intf_ports FIXED_IO] [get_bd_intf_pins $cell/FIXED_IO]
  }
  set props {}
  dict for {k v} [orb_ps7_design_settings $cfg] { lappend props CONFIG.$k $v }
  set_property -dict $props $cell
}
