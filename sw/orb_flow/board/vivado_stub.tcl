# SPDX-License-Identifier: MIT
# tclint-disable redefined-builtin
# Recording stubs of the Vivado TCL commands that vivado/build.tcl uses, for a dry run in plain
# tclsh (sw/orb_flow/board/dryrun.py, docs/board.md "Checked without Vivado"). Each command checks its
# switches the way UG835 documents them (an unknown switch is an error), returns what the build
# needs to go on (object names, "100%" for a run's PROGRESS, ...) and appends one JSON object per
# call to the record file. Nothing here knows the design: the checks are in sw/orb_flow/board/dryrun.py
# and tb/board, against facts read from the VHDL and from the IPs' published definitions.
#
# Settings before sourcing: ::orb_stub::record (path of the JSON-lines record), ::orb_stub::board_part
# (what get_board_parts returns: "" = no board files), ::orb_stub::version, ::orb_stub::run_dir.

namespace eval ::orb_stub {
  variable record
  variable board_part ""
  variable version ""
  variable run_dir ""
  variable xdc_mode 0
  variable core_clk_mhz ""
  variable spec [dict create]
  variable project {}
}

proc ::orb_stub::json_str {s} {
  set map [list "\\" "\\\\" "\"" "\\\"" "\n" "\\n" "\r" "\\r" "\t" "\\t"]
  return "\"[string map $map $s]\""
}

# one record: cmd plus key/value pairs; a value given as [list __list__ a b ...] is a JSON array
proc ::orb_stub::emit {cmd args} {
  set parts [list "\"cmd\": [json_str $cmd]"]
  foreach {k v} $args {
    if {[lindex $v 0] eq "__list__"} {
      set items {}
      foreach item [lrange $v 1 end] { lappend items [json_str $item] }
      lappend parts "[json_str $k]: \[[join $items {, }]\]"
    } else {
      lappend parts "[json_str $k]: [json_str $v]"
    }
  }
  set fh [open $::orb_stub::record a]
  puts $fh "{[join $parts {, }]}"
  close $fh
}

# Switches of each command from vivado/tclint/vivado_commands.json, the command spec tclint uses too
# (::orb_stub::spec: command -> switch -> 1 takes a value / 0 flag, set by sw/orb_flow/board/dryrun.py).
# Returns {opts positionals}.
proc ::orb_stub::parse {cmd argv} {
  if {![dict exists $::orb_stub::spec $cmd]} {
    error "$cmd: not in vivado/tclint/vivado_commands.json"
  }
  set spec [dict get $::orb_stub::spec $cmd]
  set opts [dict create]
  set pos {}
  for {set i 0} {$i < [llength $argv]} {incr i} {
    set a [lindex $argv $i]
    if {[string match -* $a] && ![string is double -strict $a]} {
      if {![dict exists $spec $a]} {
        error "$cmd: unknown switch $a (vivado/tclint/vivado_commands.json, from UG835)"
      }
      if {[dict get $spec $a]} {
        incr i
        if {$i >= [llength $argv]} { error "$cmd: $a needs a value" }
        dict set opts $a [lindex $argv $i]
      } else {
        dict set opts $a 1
      }
    } else {
      lappend pos $a
    }
  }
  return [list $opts $pos]
}

proc ::orb_stub::opt {opts name {default ""}} {
  if {[dict exists $opts $name]} { return [dict get $opts $name] }
  return $default
}

proc ::orb_stub::objs {v} {
  return [list __list__ {*}$v]
}

# --- project, files, runs ----------------------------------------------------------------------------
proc version {args} { ::orb_stub::parse version $args; return $::orb_stub::version }
proc set_param {args} {
  lassign [::orb_stub::parse set_param $args] o p
  ::orb_stub::emit set_param name [lindex $p 0] value [lindex $p 1]
}
proc create_project {args} {
  lassign [::orb_stub::parse create_project $args] o p
  ::orb_stub::emit create_project name [lindex $p 0] dir [lindex $p 1] part [::orb_stub::opt $o -part]
  set ::orb_stub::project [list [lindex $p 0] [lindex $p 1]]
  return [lindex $p 0]
}
proc current_project {args} { ::orb_stub::parse current_project $args; return project }
proc current_fileset {args} { ::orb_stub::parse current_fileset $args; return sources_1 }
proc get_board_parts {args} {
  ::orb_stub::parse get_board_parts $args
  return $::orb_stub::board_part
}
proc update_ip_catalog {args} { ::orb_stub::parse update_ip_catalog $args; ::orb_stub::emit update_ip_catalog }
proc update_compile_order {args} { ::orb_stub::parse update_compile_order $args }
proc add_files {args} {
  lassign [::orb_stub::parse add_files $args] o p
  set fileset [::orb_stub::opt $o -fileset sources_1]
  foreach f [join $p] {
    ::orb_stub::emit add_files fileset $fileset file $f
    if {$fileset eq "constrs_1"} {
      if {![file exists $f]} { error "add_files: no such file $f" }
      set ::orb_stub::xdc_mode 1
      set ::orb_stub::xdc_file $f
      uplevel #0 [list source $f]
      set ::orb_stub::xdc_mode 0
    }
  }
}
proc get_files {args} {
  lassign [::orb_stub::parse get_files $args] o p
  return [lindex $p 0]
}
# Vivado writes a block design's hardware handoff when it generates its targets, at
# <project dir>/<project>.gen/sources_1/bd/<bd>/hw_handoff/<bd>.hwh (the path PYNQ's own build scripts
# copy it from, Xilinx/PYNQ v3.1 boards/Pynq-Z2/base/build_bitstream.tcl); the stub writes a stand-in there
proc generate_target {args} {
  lassign [::orb_stub::parse generate_target $args] o p
  ::orb_stub::emit generate_target what [lindex $p 0] object [lindex $p 1]
  set bd [file rootname [file tail [lindex $p 1]]]
  lassign $::orb_stub::project name dir
  set handoff [file join $dir ${name}.gen sources_1 bd $bd hw_handoff]
  file mkdir $handoff
  set fh [open [file join $handoff ${bd}.hwh] w]
  puts $fh "<!-- dry-run stand-in for the hardware handoff of $bd -->"
  close $fh
}
proc make_wrapper {args} {
  lassign [::orb_stub::parse make_wrapper $args] o p
  set bd [::orb_stub::opt $o -files]
  return [file join $::orb_stub::run_dir "[file rootname [file tail $bd]]_wrapper.vhd"]
}
proc launch_runs {args} {
  lassign [::orb_stub::parse launch_runs $args] o p
  ::orb_stub::emit launch_runs run [lindex $p 0] to_step [::orb_stub::opt $o -to_step]
}
proc wait_on_run {args} { ::orb_stub::parse wait_on_run $args }
proc get_runs {args} { lassign [::orb_stub::parse get_runs $args] o p; return [lindex $p 0] }
proc open_run {args} { lassign [::orb_stub::parse open_run $args] o p; ::orb_stub::emit open_run run [lindex $p 0] }
proc report_utilization {args} { ::orb_stub::parse report_utilization $args; ::orb_stub::emit report what utilization }
proc report_timing_summary {args} {
  ::orb_stub::parse report_timing_summary $args
  ::orb_stub::emit report what timing_summary
}
proc report_power {args} { ::orb_stub::parse report_power $args; ::orb_stub::emit report what power }
proc report_clocks {args} { ::orb_stub::parse report_clocks $args; ::orb_stub::emit report what clocks }
proc report_cdc {args} { ::orb_stub::parse report_cdc $args; ::orb_stub::emit report what cdc }
proc write_hw_platform {args} {
  lassign [::orb_stub::parse write_hw_platform $args] o p
  ::orb_stub::emit write_hw_platform file [::orb_stub::opt $o -file]
}

# set_property in both worlds: block-design objects (/cell, /cell/pin) and XDC objects (port:...)
proc set_property {args} {
  lassign [::orb_stub::parse set_property $args] o p
  if {[dict exists $o -dict]} {
    set pairs [dict get $o -dict]
    set objs [join $p]
  } else {
    set pairs [list [lindex $p 0] [lindex $p 1]]
    set objs [join [lrange $p 2 end]]
  }
  if {[llength $pairs] % 2} { error "set_property: odd -dict list" }
  if {[llength $objs] == 0} { error "set_property: no object for $pairs" }
  foreach {k v} $pairs {
    if {$k eq "CONFIG.CLKOUT1_REQUESTED_OUT_FREQ"} { set ::orb_stub::core_clk_mhz $v }
    foreach obj $objs {
      if {$::orb_stub::xdc_mode} {
        ::orb_stub::emit xdc_property file $::orb_stub::xdc_file object $obj name $k value $v
      } else {
        ::orb_stub::emit set_property object $obj name $k value $v
      }
    }
  }
}
proc get_property {args} {
  lassign [::orb_stub::parse get_property $args] o p
  lassign $p name obj
  switch -- $name {
    PROGRESS { return "100%" }
    DIRECTORY { return $::orb_stub::run_dir }
    PERIOD { return [expr {1000.0 / $::orb_stub::core_clk_mhz}] }
    NAME { return $obj }
    default { error "get_property: the stub does not know $name" }
  }
}

# --- block design --------------------------------------------------------------------------------------
proc create_bd_design {args} {
  lassign [::orb_stub::parse create_bd_design $args] o p
  ::orb_stub::emit create_bd_design name [lindex $p 0]
}
proc current_bd_design {args} { lassign [::orb_stub::parse current_bd_design $args] o p; return [lindex $p 0] }
proc create_bd_cell {args} {
  lassign [::orb_stub::parse create_bd_cell $args] o p
  set name [lindex $p 0]
  ::orb_stub::emit create_bd_cell name $name type [::orb_stub::opt $o -type] \
    vlnv [::orb_stub::opt $o -vlnv] reference [::orb_stub::opt $o -reference]
  return "/$name"
}
proc create_bd_port {args} {
  lassign [::orb_stub::parse create_bd_port $args] o p
  set name [lindex $p 0]
  ::orb_stub::emit create_bd_port name $name dir [::orb_stub::opt $o -dir] from [::orb_stub::opt $o -from] \
    to [::orb_stub::opt $o -to] type [::orb_stub::opt $o -type] freq_hz [::orb_stub::opt $o -freq_hz]
  return "/$name"
}
proc create_bd_intf_port {args} {
  lassign [::orb_stub::parse create_bd_intf_port $args] o p
  set name [lindex $p 0]
  ::orb_stub::emit create_bd_intf_port name $name mode [::orb_stub::opt $o -mode] vlnv [::orb_stub::opt $o -vlnv]
  return "/$name"
}
proc ::orb_stub::getter {kind args} {
  lassign [::orb_stub::parse $kind $args] o p
  set out {}
  foreach n $p {
    set path [expr {[string match /* $n] ? $n : "/$n"}]
    lappend out $path
  }
  return $out
}
proc get_bd_cells {args} { return [::orb_stub::getter get_bd_cells {*}$args] }
proc get_bd_pins {args} { return [::orb_stub::getter get_bd_pins {*}$args] }
proc get_bd_intf_pins {args} { return [::orb_stub::getter get_bd_intf_pins {*}$args] }
proc get_bd_ports {args} { return [::orb_stub::getter get_bd_ports {*}$args] }
proc get_bd_intf_ports {args} { return [::orb_stub::getter get_bd_intf_ports {*}$args] }
proc get_bd_addr_spaces {args} { return [::orb_stub::getter get_bd_addr_spaces {*}$args] }
proc get_bd_addr_segs {args} { return [::orb_stub::getter get_bd_addr_segs {*}$args] }
proc connect_bd_net {args} {
  lassign [::orb_stub::parse connect_bd_net $args] o p
  ::orb_stub::emit connect_bd_net ends [::orb_stub::objs [join $p]]
}
proc connect_bd_intf_net {args} {
  lassign [::orb_stub::parse connect_bd_intf_net $args] o p
  ::orb_stub::emit connect_bd_intf_net ends [::orb_stub::objs [join $p]]
}
proc apply_bd_automation {args} {
  lassign [::orb_stub::parse apply_bd_automation $args] o p
  ::orb_stub::emit apply_bd_automation rule [::orb_stub::opt $o -rule] config [::orb_stub::opt $o -config] \
    object [lindex $p 0]
  # the processing_system7 rule's make_external "FIXED_IO, DDR": two external interface ports
  if {[string match *processing_system7 [::orb_stub::opt $o -rule]]} {
    set cell [lindex $p 0]
    create_bd_intf_port -mode Master -vlnv xilinx.com:interface:ddrx_rtl:1.0 DDR
    create_bd_intf_port -mode Master -vlnv xilinx.com:display_processing_system7:fixedio_rtl:1.0 FIXED_IO
    connect_bd_intf_net /DDR $cell/DDR
    connect_bd_intf_net /FIXED_IO $cell/FIXED_IO
  }
}
proc assign_bd_address {args} {
  lassign [::orb_stub::parse assign_bd_address $args] o p
  ::orb_stub::emit assign_bd_address offset [::orb_stub::opt $o -offset] range [::orb_stub::opt $o -range] \
    space [::orb_stub::opt $o -target_address_space] segment [lindex $p 0]
}
proc validate_bd_design {args} { ::orb_stub::parse validate_bd_design $args; ::orb_stub::emit validate_bd_design }
proc save_bd_design {args} { ::orb_stub::parse save_bd_design $args; ::orb_stub::emit save_bd_design }

# --- netlist and XDC objects -------------------------------------------------------------------------
proc get_ports {args} {
  lassign [::orb_stub::parse get_ports $args] o p
  set out {}
  foreach n [join $p] {
    ::orb_stub::emit xdc_port name $n
    lappend out "port:$n"
  }
  return $out
}
proc get_pins {args} {
  lassign [::orb_stub::parse get_pins $args] o p
  return [list "pin:[::orb_stub::opt $o -filter [join $p]]"]
}
proc get_clocks {args} {
  lassign [::orb_stub::parse get_clocks $args] o p
  if {[dict exists $o -of_objects]} { return [list clk_out1_core_clk] }
  return [list "clock:[join $p]"]
}
proc create_clock {args} {
  lassign [::orb_stub::parse create_clock $args] o p
  ::orb_stub::emit create_clock name [::orb_stub::opt $o -name] period [::orb_stub::opt $o -period] \
    objects [::orb_stub::objs [join $p]]
}
proc set_clock_groups {args} {
  set groups {}
  set rest {}
  for {set i 0} {$i < [llength $args]} {incr i} {
    if {[lindex $args $i] eq "-group"} {
      incr i
      lappend groups [lindex $args $i]
    } else {
      lappend rest [lindex $args $i]
    }
  }
  ::orb_stub::parse set_clock_groups $rest
  ::orb_stub::emit set_clock_groups groups [::orb_stub::objs $groups]
}
