# SPDX-License-Identifier: MIT
# Command-line arguments of vivado/build.tcl and the reader of hdl/manifest.txt (docs/board.md).
# Plain TCL 8.6: also runs in tclsh (the dry run of sw/orb_flow/board/dryrun.py).

proc orb_usage {} {
  return "usage: build.tcl --config NAME --vivado-library DIR --out DIR\
[--board-repo DIR] [--jobs N] [--stop-after project|bd|synth]"
}

# --name value pairs -> dict; every error names the argument
proc orb_parse_args {argv} {
  set opts [dict create config $::orb_board::default_config vivado-library "" out "" \
    board-repo "" jobs 2 stop-after ""]
  if {[llength $argv] % 2} {
    error "orb_board: odd number of arguments: $argv\n[orb_usage]"
  }
  foreach {key value} $argv {
    set name [string range $key 2 end]
    if {[string range $key 0 1] ne "--" || ![dict exists $opts $name]} {
      error "orb_board: unknown argument $key\n[orb_usage]"
    }
    dict set opts $name $value
  }
  set cfg [dict get $opts config]
  if {![dict exists $::orb_board::configs $cfg]} {
    error "orb_board: unknown configuration $cfg (known: [dict keys $::orb_board::configs])"
  }
  foreach need {vivado-library out} {
    if {[dict get $opts $need] eq ""} {
      error "orb_board: --$need is required\n[orb_usage]"
    }
  }
  if {![string is integer -strict [dict get $opts jobs]] || [dict get $opts jobs] < 1} {
    error "orb_board: --jobs must be a positive integer"
  }
  if {[dict get $opts stop-after] ni {"" project bd synth}} {
    error "orb_board: --stop-after must be project, bd or synth"
  }
  return $opts
}

# hdl/manifest.txt: one path per line relative to hdl/, '#' comments, in compile order
proc orb_read_manifest {path} {
  set fh [open $path r]
  set text [read $fh]
  close $fh
  set files {}
  foreach line [split $text "\n"] {
    set line [string trim [lindex [split $line "#"] 0]]
    if {$line ne ""} {
      lappend files $line
    }
  }
  if {[llength $files] == 0} {
    error "orb_board: $path lists no file"
  }
  return $files
}
