# The pictures of docs/guide.md and README.md, rendered from the example data in examples/:
#
#   cargo run --release -- docs/images/make.tcl      (or: vorang docs/images/make.tcl)
#
# rewrites the PNGs named below in this folder (not viewer.png, a screenshot of the viewer:
# benches/viewer/screenshot.tcl; nor farbraum*.png, gauss.png, nonLinTetra.png, inclusion.png:
# the examples' own scripts). camera.svg is drawn by hand.
#
# The map files are the guide's own blocks (```colormap NAME … ```), read out of ../guide.md,
# so every picture shows exactly the map the guide prints next to it. tests/guide.rs runs this
# script small (setting `scale` and `outdir` before sourcing it) and checks that every map block
# of the guide is rendered here and every picture exists. Set `only` to a list of names to
# render just those.

if {![info exists scale]} { set scale 1.0 }
set here [file dirname [file normalize [info script]]]
if {![info exists outdir]} { set outdir $here }
set ex [file join $here .. .. examples]

# The guide's map blocks, written to a scratch folder.
set maps [file join $outdir .maps]
file mkdir $maps
set f [open [file join $here .. guide.md]]
set block ""
foreach line [split [read $f] \n] {
    if {$block eq ""} {
        regexp {^```(?:colormap|alphamap) (\S+)$} $line -> block
        set text ""
    } elseif {$line eq "```"} {
        set out [open [file join $maps $block] w]
        puts -nonewline $out $text
        close $out
        set block ""
    } else {
        append text $line \n
    }
}
close $f

# `colormap`/`alphamap` of a guide block, remembered for the list of pictures.
set used {}
proc cmap {name} { lappend ::used $name; colormap [file join $::maps $name] }
proc amap {name} { lappend ::used $name; alphamap [file join $::maps $name] }

# Renders one picture W × H (times `scale`) after `setup` to NAME.png; lists it in
# pictures.txt with the map blocks it used (written when all pictures are rendered).
set pictures {}
proc picture {name w h setup} {
    if {[info exists ::only] && $name ni $::only} return
    set ::used {}
    uplevel #0 $setup
    imagesize [expr {max(8, round($w * $::scale))}] [expr {max(8, round($h * $::scale))}]
    output [file join $::outdir $name.png]
    render_btf
    file rename -force [file join $::outdir $name.0001.png] [file join $::outdir $name.png]
    lappend ::pictures [concat $name.png $::used]
}

# The data sets, each with a camera that shows it well; `volume` resets maps and transforms.
proc scene {args} {
    # No lights of an earlier picture (removelight fails when none is left).
    while {![catch {removelight 1}]} {}
    linedraw off
    legend off
    background clear
    set data [lindex $args 0]
    switch $data {
        gauss {
            volume [file join $::ex gauss gauss.hmesh]
            ortho_camera -1.2 1.2 -1.2 1.2 -10 10
            vol_rotate 0 1 0 30
            vol_rotate 1 0 0 20
        }
        farbraum {
            volume [file join $::ex farbraum farbraum.hmesh]
            ortho_camera -1.25 1.25 -0.75 0.75 -10 10
            vol_rotate 0 1 0 -30
            vol_rotate 1 0 0 25
            vol_scale 0.85 0.85 0.85
        }
        inclusion {
            volume [file join $::ex inclusion inclusion.vtu]
            ortho_camera -1.3 1.3 -0.8125 0.8125 -10 10
            vol_rotate 1 0 0 -25
            vol_rotate 0 1 0 20
        }
        nonLinTetra {
            volume [file join $::ex nonLinTetra nonLinTetra.hmesh]
            ortho_camera -0.7 0.7 -0.7 0.7 -10 10
            vol_rotate 1 0 0 -60
            vol_rotate 0 0 1 20
        }
    }
}

# Colour methods.
picture color_constant 256 256 {
    scene gauss; cmap orange.cmap; amap cloud.amap
    background 0 0 0; method exact constEA 0.01 0.5
}
picture color_simple_emitter 256 256 {
    scene gauss; cmap rainbow.cmap; amap cloud.amap
    background 0 0 0; method exact constEA 0.01 3
}
picture color_absorption_weighted 256 256 {
    scene gauss; cmap weighted.cmap; amap cloud.amap
    background 0 0 0; method exact constEA 0.01 1
}
picture color_identity 320 192 {
    scene farbraum; cmap rgb.cmap; amap fog.amap
    method exact linear 0 1
}
picture color_const_cell 320 200 {
    scene inclusion; cmap material.cmap; amap material.amap
    background 0 0 0; method exact linear 0 1.5
}
picture color_lit_emitter 256 256 {
    scene gauss; cmap lit.cmap; amap cloud.amap; addlight 1 1 1 -1 1 1
    background 0 0 0; method exact constEA 0.01 3
}

# Alpha methods.
picture alpha_constant 256 256 {
    scene gauss; cmap rainbow.cmap; amap fog.amap
    method exact constEA 0.01 3
}
picture alpha_simple_absorber 256 256 {
    scene gauss; amap cloud.amap
    method exact constEA 0.01 0
}
picture alpha_bary_shading 256 256 {
    scene nonLinTetra; amap bary3.amap
    linedraw on; method exact constEA 0.004 0
}
picture alpha_const_cell 320 200 {
    scene inclusion; colormap preset inferno 0 0.72 temperature; amap material.amap
    background 0 0 0; method exact linear 0 4
}

# README: the first steps, with the line `vorang info examples/inclusion/inclusion.vtu` suggests
# (the README prints these commands).
picture first_steps 384 240 {
    volume [file join $::ex inclusion inclusion.vtu]; vol_rotate 1 0 0 -25; vol_rotate 0 1 0 20
    imagesize 384 240; view_all; linedraw off; background 0 0 0; legend on
    colormap preset viridis 0 0.715872 0; alphamap ramp 0 0.715872 1.63299 0; method interpolateColor 1.63299
}

if {![info exists only]} {
    set list [open [file join $outdir pictures.txt] w]
    puts $list [join $pictures \n]
    close $list
}
file delete -force $maps
