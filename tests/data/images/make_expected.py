#!/usr/bin/env python3
"""Decodes VoRANG's sample images with independent readers; tests/image_formats.rs compares.

The files `small.EXT` and `wide.EXT` here are what VoRANG's hand-written writers
(crates/vorang/src/framebuffer/codec/) produce for two sample pictures; `VORANG_BLESS=1 cargo test --test
image_formats` rewrites them. This script decodes each with the readers named in CHECKED
below and writes every decoding as a binary 8-bit PPM `expected/NAME.EXT.READER.ppm`. The Rust
test then checks that those decodings hold the pixels the writer meant, so the formats are
checked by readers VoRANG had no part in. Run it by hand (not in CI) after changing a writer:

    apt-get install imagemagick ghostscript netpbm     # Debian 12: IM 6.9.11, gs 10.0, Netpbm 11.01
    python3 -m venv /tmp/venv && /tmp/venv/bin/pip install Pillow==13.0.0
    VORANG_BLESS=1 cargo test --test image_formats writers_still_produce_the_checked_files
    /tmp/venv/bin/python tests/data/images/make_expected.py
    cargo test --test image_formats

It also writes `foreign/`: the small picture written by Netpbm and ImageMagick in the formats
VoRANG reads itself, in their own variants (colour maps, run lengths, X10 bitmaps …), which the
Rust test reads with VoRANG's readers and compares with `foreign/reference.ppm` (colour) or
`foreign/reference_bw.ppm` (the 1-bit picture). Both references are decodings from `expected/`
that the Rust test proves equal to the intended pixels.

Every reader is asked for 8-bit RGB; Pillow only turns their output (PNM) into RGB bytes, so a
decoding is the named reader's alone. A reader that fails stops the script with its message.
"""

import io
import pathlib
import subprocess
import sys

from PIL import Image, features

HERE = pathlib.Path(__file__).resolve().parent

# ImageMagick's name for each format (the extension alone is not enough for headerless ones).
IM_NAME = {"x": "avs", "iff": "iff", "pict": "pict", "ras": "sun", "rgb": "sgi"}
# Netpbm's converter for each format.
NETPBM = {
    "rgb": ["sgitopnm"],
    "xbm": ["xbmtopbm"],
    "xwd": ["xwdtopnm"],
    "ras": ["rasttopnm"],
    "pcx": ["pcxtoppm"],
    "iff": ["ilbmtoppm"],
    "rle": ["rletopnm"],
}

CHECKED = {
    "rgb": ["pillow", "imagemagick", "netpbm"],
    "pbm": ["pillow", "imagemagick"],
    "xbm": ["pillow", "imagemagick", "netpbm"],
    "xwd": ["imagemagick", "netpbm"],
    "ras": ["pillow", "imagemagick", "netpbm"],
    "pcx": ["pillow", "imagemagick", "netpbm"],
    "eps": ["pillow", "ghostscript"],
    "ps": ["ghostscript"],
    "pict": ["imagemagick"],
    "iff": ["netpbm"],
    "x": ["imagemagick"],
    "viff": ["imagemagick"],
    "rle": ["imagemagick", "netpbm"],
}


def run(cmd, data=None):
    r = subprocess.run(cmd, input=data, capture_output=True)
    if r.returncode != 0:
        sys.exit(f"{' '.join(cmd)} failed: {r.stderr.decode(errors='replace')}")
    return r.stdout


def pnm_to_rgb(pnm: bytes) -> Image.Image:
    return Image.open(io.BytesIO(pnm)).convert("RGB")


def decode(path: pathlib.Path, ext: str, reader: str) -> Image.Image:
    if reader == "pillow":
        with Image.open(path) as im:
            if im.format == "EPS":
                im.load(scale=1)  # one pixel per point, through Ghostscript
            return im.convert("RGB")
    if reader == "imagemagick":
        name = IM_NAME.get(ext, ext)
        return pnm_to_rgb(run(["convert", f"{name}:{path}", "-depth", "8", "ppm:-"]))
    if reader == "netpbm":
        return pnm_to_rgb(run(NETPBM[ext] + [str(path)]))
    if reader == "ghostscript":
        # 72 dpi: one device pixel per point, i.e. per image pixel; no interpolation.
        args = ["gs", "-q", "-dSAFER", "-dBATCH", "-dNOPAUSE", "-sDEVICE=ppmraw", "-r72"]
        args += ["-dNOINTERPOLATE", "-sOutputFile=-"]
        if ext == "eps":
            args.append("-dEPSCrop")
        return pnm_to_rgb(run(args + [str(path)]))
    raise ValueError(reader)


def versions() -> str:
    im = run(["convert", "-version"]).decode().splitlines()[0]
    gs = run(["gs", "--version"]).decode().strip()
    netpbm = subprocess.run(["pnmtopnm", "-version"], capture_output=True).stderr.decode()
    netpbm = next((l for l in netpbm.splitlines() if "Version" in l), "netpbm").strip()
    return f"Pillow {features.version('PIL') or Image.__version__}; {im}; Ghostscript {gs}; {netpbm}"


# Files written by other programs: (name, command) with {ref} / {bw} for the reference PPMs.
FOREIGN = [
    ("netpbm_rle.sgi", "pnmtosgi -rle {ref}"),
    ("netpbm_verbatim.sgi", "pnmtosgi -verbatim {ref}"),
    ("netpbm_pseudocolor.xwd", "pnmtoxwd {ref}"),
    ("netpbm_colormap.ras", "pnmtorast {ref}"),
    ("netpbm_rle.ras", "pnmtorast -rle {ref}"),
    ("netpbm_24bit.pcx", "ppmtopcx -24bit {ref}"),
    ("netpbm_palette.pcx", "ppmtopcx {ref}"),
    ("netpbm_cmap.iff", "ppmtoilbm {ref}"),
    ("netpbm_24bit.iff", "ppmtoilbm -24force {ref}"),
    ("netpbm_x11.xbm", "pbmtoxbm {bwpbm}"),
    ("netpbm_x10.xbm", "pbmtoxbm -x10 {bwpbm}"),
    ("imagemagick.xwd", "convert {ref} xwd:-"),
    ("imagemagick.pcx", "convert {ref} pcx:-"),
    ("imagemagick.ras", "convert {ref} sun:-"),
    ("imagemagick.pict", "convert {ref} pict:-"),
    ("imagemagick.sgi", "convert {ref} sgi:-"),
    ("imagemagick.x", "convert {ref} avs:-"),
    ("imagemagick.xbm", "convert {bw} xbm:-"),
    ("imagemagick.viff", "convert {ref} viff:-"),
    ("netpbm.rle", "pnmtorle {ref}"),
]


def foreign():
    out = HERE / "foreign"
    out.mkdir(exist_ok=True)
    ref, bw = out / "reference.ppm", out / "reference_bw.ppm"
    ref.write_bytes((HERE / "expected/small.rgb.netpbm.ppm").read_bytes())
    bw.write_bytes((HERE / "expected/small.xbm.netpbm.ppm").read_bytes())
    bwpbm = out / "reference_bw.pbm"
    bwpbm.write_bytes(run(["pgmtopbm", "-threshold"], run(["ppmtopgm", str(bw)])))
    for name, cmd in FOREIGN:
        args = cmd.format(ref=ref, bw=bw, bwpbm=bwpbm).split()
        (out / name).write_bytes(run(args))
        print(f"foreign/{name}")
    bwpbm.unlink()


def main():
    out = HERE / "expected"
    out.mkdir(exist_ok=True)
    for name in ["small", "wide"]:
        for ext, readers in CHECKED.items():
            path = HERE / f"{name}.{ext}"
            for reader in readers:
                im = decode(path, ext, reader)
                target = out / f"{name}.{ext}.{reader}.ppm"
                w, h = im.size
                target.write_bytes(b"P6\n%d %d\n255\n" % (w, h) + im.tobytes())
                print(f"{target.relative_to(HERE)}: {w}x{h}")
    (out / "READERS.txt").write_text(versions() + "\n")
    foreign()


if __name__ == "__main__":
    main()
