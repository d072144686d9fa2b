# Interactive frame rates of the viewer (docs/performance.md): drives `view` with synthetic
# drags — 40 mouse moves 25 ms apart, then still until the refined frame is shown — five times,
# and prints the frame times the viewer measured (VORANG_TIMING). Run from a folder holding the
# mesh:
#
#   vorang generate box150k.bin --tets 150000 --binary
#   VORANG_TIMING=1 xvfb-run -a -s "-screen 0 1280x1024x24" vorang path/to/benches/viewer/viewer.tcl
#
# VORANG_MESH (default box150k.bin, relative to the current folder), VORANG_METHOD (default
# "interpolateCoeff linear 1") and VORANG_SIZE (default "512 512") choose the scene.

proc setting {name default} {
    global env
    expr {[info exists env($name)] ? $env($name) : $default}
}
volume [file join [pwd] [setting VORANG_MESH box150k.bin]]
colormap box.cmap
alphamap box.amap
linedraw off
imagesize {*}[setting VORANG_SIZE "512 512"]
method {*}[setting VORANG_METHOD "interpolateCoeff linear 1"]
vol_rotate 1 1 0 30

set w .vorang_view.image
set cycles 5

proc when_refined {script} {
    if {[string match "*·  refined  ·*" $::vorang::view_status]} {
        uplevel #0 $script
    } else {
        after 20 [list when_refined $script]
    }
}

proc drag {step} {
    global w
    if {$step == 0} {
        event generate $w <ButtonPress-1> -x 100 -y 100
    }
    if {$step < 40} {
        event generate $w <Motion> -x [expr {100 + 3 * $step}] -y [expr {100 + $step}] -state 256
        after 25 [list drag [incr step]]
    } else {
        event generate $w <ButtonRelease-1> -x 220 -y 140
        after 50 {when_refined next_cycle}
    }
}

proc next_cycle {} {
    global cycles
    if {[incr cycles -1] >= 0} {
        drag 0
    } else {
        event generate .vorang_view <KeyPress> -keysym q
    }
}

after 200 {when_refined next_cycle}
view
