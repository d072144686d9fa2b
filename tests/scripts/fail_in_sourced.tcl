# expect: lib_bad_colormap.tcl:3: datafield7.map:2: DataField 7: the volume
volume ../data/two_tets_data.hmesh
data ../data/two_tets_fields.dat
source lib_bad_colormap.tcl
