#!/bin/sh
# SPDX-License-Identifier: MIT
# Which of the external tools this project uses are installed, with versions, and the exact
# command to install what is missing (Debian 12 package names).
#
#   scripts/flow/check_tools.sh              report every tool; exit 0 (`make tools`)
#   scripts/flow/check_tools.sh ghdl yosys   require these; print the install command and exit 1 if one
#                                       is missing (used by `make synth` / `make lint`)
# Tool names: ghdl (any back end), ghdl-mcode, ghdl-llvm, yosys, tclsh, dtc, cxx (g++ and make, for the
# fast simulation's Verilator build), python3, ros (Debian's ROS 1
# packages of sw/orb_ros/debian-packages.txt: roscore, rosbag, genpy, the message packages).

ROS_PACKAGES=$(cat "$(dirname "$0")/../../sw/orb_ros/debian-packages.txt")

first_line() { "$@" 2>/dev/null | head -n 1; }

# ghdl --version prints the back end on its third line ("mcode code generator", "llvm code ...").
ghdl_backend() { "$1" --version 2>/dev/null | sed -n 's/^ *\([a-z]*\) code generator.*/\1/p' | head -n 1; }

version_of() {
  case "$1" in
    ghdl)
      for b in ghdl ghdl-llvm ghdl-mcode ghdl-gcc; do
        if command -v "$b" >/dev/null 2>&1; then
          v=$(first_line "$b" --version) && [ -n "$v" ] && { echo "$v, $(ghdl_backend "$b") back end ($b)"; return 0; }
        fi
      done
      return 1 ;;
    ghdl-mcode | ghdl-llvm)
      command -v "$1" >/dev/null 2>&1 || return 1
      first_line "$1" --version ;;
    yosys)
      command -v yosys >/dev/null 2>&1 || return 1
      first_line yosys -V ;;
    tclsh)
      command -v tclsh >/dev/null 2>&1 || return 1
      echo "puts [info patchlevel]" | tclsh ;;
    dtc)
      command -v dtc >/dev/null 2>&1 || return 1
      first_line dtc --version ;;
    cxx)
      command -v g++ >/dev/null 2>&1 && command -v make >/dev/null 2>&1 || return 1
      echo "$(first_line g++ --version), $(first_line make --version)" ;;
    ros)
      command -v roscore >/dev/null 2>&1 && command -v rosbag >/dev/null 2>&1 || return 1
      [ -f /usr/lib/genpy/genmsg_py.py ] && [ -d /usr/share/std_msgs/msg ] || return 1
      /usr/bin/python3 -c 'import rospy, rosbag, std_srvs.srv, diagnostic_msgs.msg' 2>/dev/null || return 1
      echo "ROS 1 from Debian: rospy $(/usr/bin/python3 -c 'import importlib.metadata as m; print(m.version("rospy"))' \
        2>/dev/null || echo '?'), roscore, rosbag, genpy" ;;
    python3)
      command -v python3 >/dev/null 2>&1 || return 1
      python3 -c 'import sys; sys.exit(sys.version_info < (3, 11))' 2>/dev/null || {
        echo "$(first_line python3 --version) (too old: make's venv needs 3.11 or newer)"; return 2; }
      first_line python3 --version ;;
    *) echo "unknown tool '$1'" >&2; return 1 ;;
  esac
}

install_cmd() {
  case "$1" in
    ghdl | ghdl-llvm) echo "apt-get install ghdl-llvm" ;;
    ghdl-mcode) echo "apt-get install ghdl-mcode" ;;
    yosys) echo "apt-get install yosys" ;;
    python3) echo "apt-get install python3 python3-venv" ;;
    tclsh) echo "apt-get install tcl" ;;
    dtc) echo "apt-get install device-tree-compiler" ;;
    cxx) echo "apt-get install g++ make" ;;
    ros) echo "apt-get install $ROS_PACKAGES" ;;
  esac
}

missing=""
check() {
  if v=$(version_of "$1"); then
    printf '  %-11s %s\n' "$1" "$v"
  else
    [ -n "$v" ] && printf '  %-11s %s\n' "$1" "$v" || printf '  %-11s MISSING\n' "$1"
    missing="$missing $1"
  fi
}

if [ $# -gt 0 ]; then
  status=0
  for t in "$@"; do
    v=$(version_of "$t") && continue
    status=1
    if [ -n "$v" ]; then
      echo "error: $t: $v; install a newer one with: $(install_cmd "$t")" >&2
    else
      echo "error: $t is not installed; install it with: $(install_cmd "$t")" >&2
    fi
  done
  exit $status
fi

echo "External tools:"
check_optional() {
  if v=$(version_of "$1"); then printf '  %-11s %s\n' "$1" "$v"; else printf '  %-11s not installed\n' "$1"; fi
}
check_optional ghdl-mcode
check_optional ghdl-llvm
version_of ghdl >/dev/null || missing="$missing ghdl"
check yosys
check tclsh
check dtc
check cxx
check ros
check python3
venv="$(dirname "$0")/../../.venv/bin"
for t in ruff vsg; do
  if [ -x "$venv/$t" ]; then
    printf '  %-11s %s (.venv)\n' "$t" "$(first_line "$venv/$t" --version)"
  else
    printf '  %-11s not in .venv (make setup installs it)\n' "$t"
  fi
done
if [ -n "$missing" ]; then
  echo "Missing; install with:"
  for t in $missing; do echo "  $(install_cmd "$t")"; done
else
  echo "All external tools are present."
fi
if ! command -v ghdl-llvm >/dev/null 2>&1 && version_of ghdl >/dev/null; then
  echo "Optional: apt-get install ghdl-llvm (native-code back end: faster cocotb simulation)"
fi
exit 0
