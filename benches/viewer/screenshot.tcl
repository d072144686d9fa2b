# The viewer's screenshot in docs/images/viewer.png: the 150k-cell box turned by a drag, taken
# with xwd once the refined frame is shown (convert the .xwd to PNG with any tool). Run from a
# folder holding box150k.bin (`vorang generate box150k.bin --tets 150000 --binary`):
#
#   xvfb-run -a -s "-screen 0 1280x1024x24" vorang path/to/benches/viewer/screenshot.tcl

volume [file join [pwd] box150k.bin]
colormap box.cmap
alphamap box.amap
linedraw off
imagesize 320 320
method interpolateCoeff linear 1.5
vol_rotate 1 1 0 30

set w .vorang_view.image
proc when_refined {script} {
    if {[string match "*·  refined  ·*" $::vorang::view_status]} {
        uplevel #0 $script
    } else {
        after 20 [list when_refined $script]
    }
}
after 200 {
    event generate $w <ButtonPress-1> -x 100 -y 100
    event generate $w <Motion> -x 140 -y 90 -state 256
    event generate $w <ButtonRelease-1> -x 140 -y 90
    event generate $w <Button-4> -x 160 -y 160
    after 100 {when_refined {
        update
        exec xwd -silent -id [winfo id .vorang_view] -out [file join [pwd] viewer.xwd]
        event generate .vorang_view <KeyPress> -keysym q
    }}
}
view
