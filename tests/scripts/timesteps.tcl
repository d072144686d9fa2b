# Time series (docs/formats.md, "Time series and collections"): a collection loads step 0;
# timestep shows another by number, by time (the nearest; the earlier on a tie) or the last;
# timesteps lists the times; out-of-range steps and bad words are errors naming the range.
set here [file normalize [file dirname [info script]]]
set series $here/../data/series
assert {[volume ../data/series/flow.pvd] eq "64 nodes, 162 tetrahedra, 3 fields; 3 time steps, t = 0 … 1.25"}
assert {[timesteps] eq {0 0.5 1.25}}
assert {[llength [timesteps]] == 3}
assert {[timestep] eq {0 0}}
imagesize 16 16
linedraw off
colormap preset viridis 1 3 0
method interpolateColor 1
assert {[timestep 2] eq {2 1.25}}
assert {[timestep] eq {2 1.25}}
assert {[timestep -time 0.25] eq {0 0}}
assert {[timestep -time 0.3] eq {1 0.5}}
assert {[timestep -time -7] eq {0 0}}
assert {[timestep -time 1e9] eq {2 1.25}}
assert {[timestep last] eq {2 1.25}}
expect_error {timestep 3} {timestep: step 3 is out of range: *flow.pvd has 3 time steps (0 … 2)}
expect_error {timestep -1} {timestep: expected a step number 0 … 2, 'last' or '-time T', found "-1"}
expect_error {timestep soon} {timestep: expected a step number 0 … 2, 'last' or '-time T', found "soon"}
expect_error {timestep -time now} {timestep: expected a number for "T" but got "now"}
expect_error {timestep 1 2} {wrong # args: should be "timestep ?N|last|-time T?"}
expect_error {timesteps 1} {wrong # args: should be "timesteps"}
# The maps, the method and the image settings stayed: a loop renders every step.
output $::tmp/steps/flow.png
label "t = %.3g s, step %d"
foreach t [timesteps] {
    timestep -time $t
    render_btf
}
label off
foreach n {0001 0002 0003} {
    assert {[file exists $::tmp/steps/flow.$n.png]} $n
}
expect_error {label "t = %s"} {label: unknown conversion '%s' in "t = %s": *}
# Every collection format, and a file that is no collection (one step at time 0).
foreach {file steps} {flow.vtu.series 3 flow_p.pvd 3 flow_m.vtm.series 3 flow_p_0.pvtu 1 parts.pvd 2 moving.pvd 3} {
    volume $series/$file
    assert {[llength [timesteps]] == $steps} $file
    timestep last
}
volume ../data/series/flow_1.vtu
assert {[timesteps] eq {0}}
assert {[timestep] eq {0 0}}
assert {[timestep 0] eq {0 0}}
expect_error {timestep 1} {timestep: step 1 is out of range: the volume is one step (0 … 0)*}
