# Sourced by fail_in_sourced.tcl: after 'data' only fields 0 and 1 remain.
set unused 1
colormap datafield7.map
