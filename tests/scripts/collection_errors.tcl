# Bad collections: a missing file is named at its line, pieces whose arrays disagree name both
# pieces, an empty collection says so, and the loaded volume stays.
set here [file normalize [file dirname [info script]]]
set series $here/../data/series
proc write {name text} {
    set f [open $::tmp/$name w]
    puts -nonewline $f $text
    close $f
}
volume $series/flow.pvd
write missing.pvd "<?xml version=\"1.0\"?>
<VTKFile type=\"Collection\" version=\"0.1\">
  <Collection>
    <DataSet timestep=\"0\" file=\"$series/flow_0.vtu\"/>
    <DataSet timestep=\"1\" file=\"nothere.vtu\"/>
  </Collection>
</VTKFile>
"
expect_error {volume $::tmp/missing.pvd} {*missing.pvd:5: *nothere.vtu: no such file}
write missing.pvtu "<VTKFile type=\"PUnstructuredGrid\">
<PUnstructuredGrid>
<Piece Source=\"$series/flow_0.vtu\"/>
<Piece Source=\"gone/piece_1.vtu\"/>
</PUnstructuredGrid>
</VTKFile>
"
expect_error {volume $::tmp/missing.pvtu} {*missing.pvtu:4: *gone/piece_1.vtu: no such file}
write disagree.pvtu "<VTKFile type=\"PUnstructuredGrid\">
<PUnstructuredGrid>
<Piece Source=\"$series/flow_0.vtu\"/>
<Piece Source=\"$here/../data/formats/cube_ascii.vtu\"/>
</PUnstructuredGrid>
</VTKFile>
"
expect_error {volume $::tmp/disagree.pvtu} {*disagree.pvtu:4: the pieces' arrays disagree: point array 1 is "temperature" (1 component, Float64) in *cube_ascii.vtu but "T" (1 component, Float64) in *flow_0.vtu (*disagree.pvtu:3)*}
write empty.pvd "<VTKFile type=\"Collection\">\n<Collection>\n</Collection>\n</VTKFile>\n"
expect_error {volume $::tmp/empty.pvd} {*empty.pvd:1: the collection is empty*}
write empty.vtu.series {{"file-series-version": "1.0",
 "files": []}}
expect_error {volume $::tmp/empty.vtu.series} {*empty.vtu.series:2: the collection is empty*}
write self.vtm "<VTKFile type=\"vtkMultiBlockDataSet\"><vtkMultiBlockDataSet>
<DataSet index=\"0\" file=\"self.vtm\"/>
</vtkMultiBlockDataSet></VTKFile>"
expect_error {volume $::tmp/self.vtm} {*self.vtm:2: *self.vtm: collections nested more than 8 deep (does one list itself?)}
write nested.pvd "<VTKFile type=\"Collection\"><Collection>
<DataSet timestep=\"0\" file=\"$series/flow.pvd\"/>
</Collection></VTKFile>"
expect_error {volume $::tmp/nested.pvd} {*nested.pvd:2: *flow.pvd: a .pvd collection is a time series; it cannot be one part of a step}
# Nothing changed: the first collection is still loaded, at its step 0.
assert {[timesteps] eq {0 0.5 1.25}}
assert {[timestep] eq {0 0}}
