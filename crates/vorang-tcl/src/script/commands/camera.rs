//! Camera and transforms: `persp_camera`, `ortho_camera`, `vol_scale`, `vol_translate`,
//! `vol_rotate`, `look_at` (thesis A.1; conventions in docs/camera.md).

use super::{Call, CommandInfo};
use crate::script::Context;
use vorang::scene::{Camera, LookAt, TransformOp};

pub const PERSP_CAMERA: CommandInfo = CommandInfo {
    name: "persp_camera",
    usage: "fovy aspect near far",
    summary: "perspective camera: vertical field of view (degrees), width/height, clipping depths near < far (both > 0)",
    details: "Clipping is by planes of constant depth.",
    run: |s: &mut Context, c: &Call| {
        c.expect(4..=4)?;
        let [fovy, aspect, near, far] = c.numbers(0, ["fovy", "aspect", "near", "far"])?;
        let cam = Camera::Persp {
            fovy,
            aspect,
            near,
            far,
        };
        s.session.set_camera(cam)?;
        Ok(String::new())
    },
};

pub const ORTHO_CAMERA: CommandInfo = CommandInfo {
    name: "ortho_camera",
    usage: "left right bottom top front back",
    summary: "orthographic camera: the window in eye coordinates and the depth range",
    details: "Default (no camera command): the x/y extent of the grid's bounding box, no depth clipping. Later transforms do not change this default.",
    run: |s: &mut Context, c: &Call| {
        c.expect(6..=6)?;
        let [left, right, bottom, top, front, back] =
            c.numbers(0, ["left", "right", "bottom", "top", "front", "back"])?;
        let cam = Camera::Ortho {
            left,
            right,
            bottom,
            top,
            front,
            back,
        };
        s.session.set_camera(cam)?;
        Ok(String::new())
    },
};

pub const VIEW_ALL: CommandInfo = CommandInfo {
    name: "view_all",
    usage: "",
    summary: "frame the whole transformed volume: a camera of the current kind, same viewing direction, the volume inside the image with a 5 % margin",
    details: "Orthographic (also when no camera is set): the window is centred on the volume and widened to the image's aspect ratio; the depth range covers it. Perspective: field of view and aspect stay, the eye moves along the viewing direction and looks at the volume's centre; near and far enclose it. Uses the current volume, transforms and image size: call it after them.",
    run: |s: &mut Context, c: &Call| {
        c.expect(0..=0)?;
        s.session.view_all()?;
        Ok(String::new())
    },
};

pub const VOL_SCALE: CommandInfo = CommandInfo {
    name: "vol_scale",
    usage: "x y z",
    summary: "scale the volume about the origin (after the transforms so far)",
    details: "",
    run: |s: &mut Context, c: &Call| {
        c.expect(3..=3)?;
        let v = c.numbers(0, ["x", "y", "z"])?;
        s.session.transform(TransformOp::Scale(v))?;
        Ok(String::new())
    },
};

pub const VOL_TRANSLATE: CommandInfo = CommandInfo {
    name: "vol_translate",
    usage: "x y z",
    summary: "move the volume (after the transforms so far)",
    details: "",
    run: |s: &mut Context, c: &Call| {
        c.expect(3..=3)?;
        let v = c.numbers(0, ["x", "y", "z"])?;
        s.session.transform(TransformOp::Translate(v))?;
        Ok(String::new())
    },
};

pub const VOL_ROTATE: CommandInfo = CommandInfo {
    name: "vol_rotate",
    usage: "x y z degrees",
    summary: "rotate the volume about the axis (x, y, z) through its bounding-box centre at its current position (right-handed)",
    details: "",
    run: |s: &mut Context, c: &Call| {
        c.expect(4..=4)?;
        let [x, y, z, degrees] = c.numbers(0, ["x", "y", "z", "degrees"])?;
        s.session.transform(TransformOp::Rotate {
            axis: [x, y, z],
            degrees,
        })?;
        Ok(String::new())
    },
};

pub const LOOK_AT: CommandInfo = CommandInfo {
    name: "look_at",
    usage: "ex ey ez rx ry rz ux uy uz",
    summary: "eye position, reference point and up direction",
    details: "Default: 0 0 0  0 0 -1  0 1 0. Eye = reference keeps the eye and looks along −z; an up vector not orthogonal to the view is orthogonalised.",
    run: |s: &mut Context, c: &Call| {
        c.expect(9..=9)?;
        let v = c.numbers(0, ["ex", "ey", "ez", "rx", "ry", "rz", "ux", "uy", "uz"])?;
        s.session.set_look_at(LookAt {
            eye: [v[0], v[1], v[2]],
            reference: [v[3], v[4], v[5]],
            up: [v[6], v[7], v[8]],
        });
        Ok(String::new())
    },
};
