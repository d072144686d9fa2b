# expect: fail_proc_command.tcl:5: render_btf: no volume loaded: use 'volume file' first
proc go {} \
{
    imagesize 8 8
    render_btf
}
go
