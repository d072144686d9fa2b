# expect: fail_collection_missing_file.tcl:8: missing_step.pvd:2:
set f [open $::tmp/missing_step.pvd w]
puts $f {<VTKFile type="Collection"><Collection>
<DataSet timestep="0" file="a.vtu"/>
</Collection></VTKFile>}
close $f
# line 7
volume $::tmp/missing_step.pvd
