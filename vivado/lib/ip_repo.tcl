# SPDX-License-Identifier: MIT
# Digilent's vivado-library (dvi2rgb 2.0, rgb2dvi 1.4) as the IP repository (docs/board.md).
# The user's checkout is used as it is. Only for a configuration whose pixel clock is below 40 MHz
# (640x480@60, 25.175 MHz) the two IPs are copied into the build directory and their kClkRange
# choice lists gain the values 4 and 5: the packaged IP offers 1..3 (MMCM multiplier 5*kClkRange,
# 3 covers 40..80 MHz), while its own HDL documents 4 (>= 30 MHz) and 5 (>= 25 MHz) (TMDS_Clocking.vhd
# and ClockGen.vhd: "MULT_F = kClkRange*5 (... >=30MHz=4, >=25MHz=5)"); at 25.175 MHz, 5 puts the
# VCO at 629 MHz, inside the XC7Z020-1 MMCM's 600..1200 MHz. Nothing is copied into the repository;
# the copy sits in build/ and comes first in ip_repo_paths, so Vivado takes it over the original.

proc orb_check_vivado_library {lib} {
  foreach need {ip/dvi2rgb/component.xml ip/rgb2dvi/component.xml if/tmds_v1_0} {
    if {![file exists [file join $lib $need]]} {
      error "orb_board: $lib is not Digilent's vivado-library (no $need): see docs/board.md"
    }
  }
}

# Adds kClkRange 4 and 5 to the choice list of one component.xml (text in, text out); the list is
# recognised by its entry for 3 ("< 80 MHz (720p)" in dvi2rgb, "< 80MHz (720p)" in rgb2dvi).
proc orb_extend_clk_range {xml} {
  set pattern {(<spirit:enumeration spirit:text="&lt; ?80 ?MHz \(720p\)">3</spirit:enumeration>)}
  set extra "\n      <spirit:enumeration spirit:text=\"&gt;=30 MHz\">4</spirit:enumeration>"
  append extra "\n      <spirit:enumeration spirit:text=\"&gt;=25 MHz (640x480)\">5</spirit:enumeration>"
  set n [regexp -all $pattern $xml]
  if {$n != 1} {
    error "orb_board: kClkRange choice list not found exactly once (found $n) in component.xml"
  }
  # (not regsub: "&" in the inserted XML would stand for the match there)
  regexp -indices $pattern $xml whole
  set end [lindex $whole 1]
  return "[string range $xml 0 $end]$extra[string range $xml [expr {$end + 1}] end]"
}

# The ip_repo_paths for a configuration: the user's checkout, after a copy with the extended
# kClkRange list when the pixel clock needs it.
proc orb_ip_repo_paths {lib out patched} {
  orb_check_vivado_library $lib
  if {!$patched} {
    return [list $lib]
  }
  set copy [file join $out iprepo]
  file delete -force $copy
  file mkdir [file join $copy ip]
  foreach ip {dvi2rgb rgb2dvi} {
    file copy [file join $lib ip $ip] [file join $copy ip $ip]
    set path [file join $copy ip $ip component.xml]
    set fh [open $path r]
    set xml [read $fh]
    close $fh
    set fh [open $path w]
    puts -nonewline $fh [orb_extend_clk_range $xml]
    close $fh
  }
  return [list $copy $lib]
}
