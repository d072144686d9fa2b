# Sourced by tcl_language.tcl: its path is relative to the sourcing script's folder.
set sourced_value 42
