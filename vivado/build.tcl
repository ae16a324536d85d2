# SPDX-License-Identifier: MIT
# Batch build of the Zybo Z7-20 design (docs/board.md): HDMI in (Digilent dvi2rgb) -> Xilinx video
# bridges -> orb_accel_zynq (luma, ORB, feature memory, overlay) -> HDMI out (Digilent rgb2dvi), the
# ARM CPU on AXI4-Lite (M_AXI_GP0) with the frame interrupt on IRQ_F2P[0].
# Written for Vivado 2025.1 (ML Standard, the free edition that supports the XC7Z020); IP is created
# by version-less VLNVs so a newer release picks its own IP versions (the build warns on another
# version). NOT RUN HERE: no Vivado on the machines this was written on; the TCL runs in plain tclsh
# against recording stubs (sw/orb_flow/board/dryrun.py, tb/board) and the first user with Vivado
# compares (docs/board.md).
#
# vivado -mode batch -source vivado/build.tcl -tclargs --config 1280x720 --vivado-library DIR
#        --out build/vivado/1280x720 [--board-repo DIR] [--jobs N] [--stop-after project|bd|synth]
# `make bitstream CONFIG=board-720p VIVADO_LIBRARY=DIR` runs this, then sw/orb_flow/board/bitstream.py
# puts the .bit.bin and the PYNQ .dtbo beside the .bit and the .hwh this writes (docs/pynq.md) and
# sw/orb_flow/board/vivado_summary.py summarises.

set orb_vivado_dir [file dirname [file normalize [info script]]]
set orb_repo_root [file dirname $orb_vivado_dir]
source [file join $orb_vivado_dir gen board.tcl]
source [file join $orb_vivado_dir lib args.tcl]
source [file join $orb_vivado_dir lib ip_repo.tcl]
source [file join $orb_vivado_dir lib ps7.tcl]
source [file join $orb_vivado_dir lib bd.tcl]
source [file join $orb_vivado_dir lib constraints.tcl]

set opts [orb_parse_args $argv]
set cfg_name [dict get $opts config]
set cfg [dict get $::orb_board::configs $cfg_name]
set out [file normalize [dict get $opts out]]
set lib [file normalize [dict get $opts vivado-library]]
set top_name "$::orb_board::design_name"
set base_name "${top_name}_${cfg_name}"
file mkdir $out

if {[version -short] ne $::orb_board::vivado_version} {
  puts "WARNING: written for Vivado $::orb_board::vivado_version, running [version -short]: IP versions may differ"
}
puts "orb_board: configuration $cfg_name ([dict get $cfg mode]), core clock [dict get $cfg core_mhz] MHz"

# --- project --------------------------------------------------------------------------------------
set project_dir [file join $out project]
create_project -force -part $::orb_board::part $top_name $project_dir
set_property target_language VHDL [current_project]
set board_part ""
if {[dict get $opts board-repo] ne ""} {
  set_param board.repoPaths [list [file normalize [dict get $opts board-repo]]]
}
set board_part [get_board_parts -quiet -latest_file_version $::orb_board::board_part_glob]
if {$board_part ne ""} {
  set board_part [lindex $board_part 0]
  set_property board_part $board_part [current_project]
  puts "orb_board: board files found, board part $board_part"
} else {
  puts "orb_board: no Zybo Z7-20 board files; the PS7 is configured explicitly (vivado/lib/ps7.tcl)"
}
set_property ip_repo_paths [orb_ip_repo_paths $lib $out [dict get $cfg patched_clk_range]] [current_project]
update_ip_catalog

# the accelerator's sources: hdl/manifest.txt, the one compile list (VHDL-2008), except the flat
# wrapper orb_accel_zynq, plain VHDL, which a block-design module reference needs as its top
set entity [dict get $::orb_board::accel entity]
foreach rel [orb_read_manifest [file join $orb_repo_root hdl manifest.txt]] {
  set path [file join $orb_repo_root hdl $rel]
  add_files -norecurse $path
  if {[file rootname [file tail $rel]] eq $entity} {
    set_property file_type VHDL [get_files $path]
  } else {
    set_property file_type {VHDL 2008} [get_files $path]
  }
}
update_compile_order -fileset sources_1
if {[dict get $opts stop-after] eq "project"} { return }

# --- block design ---------------------------------------------------------------------------------
orb_create_bd $top_name $cfg $board_part
if {[dict get $opts stop-after] eq "bd"} { return }
set bd_file [get_files ${top_name}.bd]
generate_target all $bd_file
set wrapper [make_wrapper -files $bd_file -top]
add_files -norecurse $wrapper
set_property top ${top_name}_wrapper [current_fileset]
update_compile_order -fileset sources_1

# --- constraints: pins (vivado/xdc) and this configuration's clocks (written into the build) --------
add_files -fileset constrs_1 -norecurse [file join $orb_vivado_dir xdc zybo_z7_20.xdc]
set timing_xdc [orb_write_timing_xdc $cfg [file join $out timing_${cfg_name}.xdc]]
add_files -fileset constrs_1 -norecurse $timing_xdc

# --- synthesis, implementation, bitstream ---------------------------------------------------------
set jobs [dict get $opts jobs]
launch_runs synth_1 -jobs $jobs
wait_on_run synth_1
if {[get_property PROGRESS [get_runs synth_1]] ne "100%"} {
  error "orb_board: synthesis failed (see [file join $out project ${top_name}.runs synth_1 runme.log])"
}
if {[dict get $opts stop-after] eq "synth"} { return }
launch_runs impl_1 -to_step write_bitstream -jobs $jobs
wait_on_run impl_1
if {[get_property PROGRESS [get_runs impl_1]] ne "100%"} {
  error "orb_board: implementation failed (see [file join $out project ${top_name}.runs impl_1 runme.log])"
}
open_run impl_1
set reports [file join $out reports]
file mkdir $reports
report_utilization -file [file join $reports utilization.rpt]
report_timing_summary -max_paths 10 -report_unconstrained -file [file join $reports timing_summary.rpt]
report_power -file [file join $reports power.rpt]
report_clocks -file [file join $reports clocks.rpt]
report_cdc -file [file join $reports cdc.rpt]
orb_check_core_clock $cfg [file join $reports core_clock.txt]
set bit [lindex [glob -directory [get_property DIRECTORY [get_runs impl_1]] *.bit] 0]
file copy -force $bit [file join $out ${base_name}.bit]
# the hardware handoff beside the bitstream, same stem: pynq.Overlay("<stem>.bit") reads <stem>.hwh
# (docs/pynq.md). generate_target writes it into the project, as PYNQ's own build scripts copy it.
set hwh [file join $project_dir ${top_name}.gen sources_1 bd $top_name hw_handoff ${top_name}.hwh]
if {![file exists $hwh]} {
  error "orb_board: no hardware handoff at $hwh (generate_target writes it; PYNQ needs it beside the .bit)"
}
file copy -force $hwh [file join $out ${base_name}.hwh]
write_hw_platform -fixed -include_bit -force -file [file join $out ${base_name}.xsa]
puts "orb_board: wrote [file join $out ${base_name}.bit], ${base_name}.hwh, ${base_name}.xsa and reports/"
