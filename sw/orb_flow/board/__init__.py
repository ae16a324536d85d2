"""The Zybo Z7-20 board build: Vivado run, dry run, report summary, .bit.bin (docs/board.md)."""
