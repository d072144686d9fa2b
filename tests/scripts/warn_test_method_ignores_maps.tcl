# The default method `test` ignores the maps: setting maps without choosing a method warns
# once per render, naming the methods that use them.
# expect: render_btf: the method is still the default 'test', which ignores the colormap and alphamap
volume ../data/formats/cube.hmesh
imagesize 16 16
output $::tmp/t.pfm
colormap preset viridis 0 1
render_btf
