# expect: fail_timestep_out_of_range.tcl:4: has 3 time steps (0 … 2)
volume ../data/series/flow.vtu.series
timestep 2
timestep 3
