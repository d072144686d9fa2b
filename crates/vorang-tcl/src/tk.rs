//! Tk for the `online` window and the viewer, loaded into the interpreter on first
//! use with `package require Tk`: scripts that never show a window need neither a display nor
//! the Tk library, and Tk is found the way Tcl finds any package (its `pkgIndex.tcl`), so
//! building VoRANG does not need Tk at all.
//!
//! Pixels go into a photo image through Tk's C call `Tk_PhotoPutBlock`, not through Tcl
//! strings: a 512² frame as `#rrggbb` words would cost more than many renders. The two C
//! functions are looked up in the very library Tcl loaded (`info loaded` names it), so they
//! belong to the Tk that runs the window.

use std::ffi::{CString, c_char, c_int, c_void};

use crate::tcl::Interp;

/// `Tk_PhotoImageBlock` (tk.h, stable since Tk 8.3).
#[repr(C)]
struct PhotoImageBlock {
    pixel_ptr: *const u8,
    width: c_int,
    height: c_int,
    pitch: c_int,
    pixel_size: c_int,
    offset: [c_int; 4],
}

type FindPhoto = unsafe extern "C" fn(*mut c_void, *const c_char) -> *mut c_void;
type PutBlock = unsafe extern "C" fn(
    *mut c_void,
    *mut c_void,
    *const PhotoImageBlock,
    c_int,
    c_int,
    c_int,
    c_int,
    c_int,
) -> c_int;

/// `TK_PHOTO_COMPOSITE_SET`: replace the pixels, do not blend them over the old ones.
const COMPOSITE_SET: c_int = 1;

#[cfg(unix)]
unsafe extern "C" {
    fn dlopen(file: *const c_char, mode: c_int) -> *mut c_void;
    fn dlsym(handle: *mut c_void, name: *const c_char) -> *mut c_void;
}

/// `RTLD_NOW | RTLD_NOLOAD`: a handle to a library already loaded, never a second copy.
#[cfg(target_os = "linux")]
const DL_ALREADY_LOADED: c_int = 0x2 | 0x4;
#[cfg(all(unix, not(target_os = "linux")))]
const DL_ALREADY_LOADED: c_int = 0x2 | 0x10;

/// Tk, loaded into one interpreter (two function pointers: cheap to copy).
#[derive(Clone, Copy)]
pub struct Tk {
    find_photo: FindPhoto,
    put_block: PutBlock,
}

impl std::fmt::Debug for Tk {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str("Tk")
    }
}

impl Tk {
    /// `package require Tk` in `interp` and the photo calls of the library it loaded. Tk's own
    /// main window `.` is withdrawn: VoRANG's windows are toplevels of their own, which a user
    /// may close and a later render opens again. Fails (with Tk's message, e.g. "couldn't
    /// connect to display") where there is no display.
    pub fn load(interp: &Interp) -> Result<Tk, String> {
        interp
            .eval("package require Tk 8.6")
            .map_err(|e| e.message)?;
        interp.eval("wm withdraw .").map_err(|e| e.message)?;
        let loaded = interp.eval("info loaded").map_err(|e| e.message)?;
        let path = interp
            .split_list(&loaded)?
            .iter()
            .filter_map(|entry| interp.split_list(entry).ok())
            .find(|pair| pair.get(1).is_some_and(|p| p == "Tk"))
            .and_then(|pair| pair.first().cloned())
            .unwrap_or_default();
        Self::symbols(&path)
    }

    #[cfg(unix)]
    fn symbols(path: &str) -> Result<Tk, String> {
        let file = CString::new(path).map_err(|e| e.to_string())?;
        // SAFETY: dlopen with RTLD_NOLOAD only returns a handle to a library already in the
        // process (Tk, loaded by `package require` above); an empty path (Tk linked statically)
        // means the program itself. The handle is never closed: Tk stays loaded.
        let handle = unsafe {
            dlopen(
                if path.is_empty() {
                    std::ptr::null()
                } else {
                    file.as_ptr()
                },
                DL_ALREADY_LOADED,
            )
        };
        if handle.is_null() {
            return Err(format!(
                "Tk is loaded but its library '{path}' is not found"
            ));
        }
        let symbol = |name: &str| {
            let c = CString::new(name).unwrap_or_default();
            // SAFETY: `handle` is a live library handle; `c` is NUL-terminated.
            let p = unsafe { dlsym(handle, c.as_ptr()) };
            if p.is_null() {
                Err(format!("the Tk library '{path}' has no {name}"))
            } else {
                Ok(p)
            }
        };
        let (find, put) = (symbol("Tk_FindPhoto")?, symbol("Tk_PhotoPutBlock")?);
        // SAFETY: both symbols are Tk's public C functions with exactly these signatures
        // (tkDecls.h, Tk 8.5 and later, where Tk_PhotoPutBlock takes the interpreter first).
        Ok(unsafe {
            Tk {
                find_photo: std::mem::transmute::<*mut c_void, FindPhoto>(find),
                put_block: std::mem::transmute::<*mut c_void, PutBlock>(put),
            }
        })
    }

    #[cfg(not(unix))]
    fn symbols(_path: &str) -> Result<Tk, String> {
        Err("the VoRANG window is only available on Unix-like systems".into())
    }

    /// Puts `rgba` (8-bit RGBA, `width × height`, row by row) into photo image `photo` at
    /// `(x, y)`, replacing what was there; the photo grows if needed. Must be called on the
    /// interpreter's thread, with the interpreter Tk was loaded into.
    pub fn put(
        &self,
        interp: &Interp,
        photo: &str,
        (x, y): (usize, usize),
        (width, height): (usize, usize),
        rgba: &[u8],
    ) -> Result<(), String> {
        if rgba.len() != width * height * 4 {
            return Err(format!(
                "{} bytes for a {width}×{height} RGBA block",
                rgba.len()
            ));
        }
        if width == 0 || height == 0 {
            return Ok(());
        }
        let name = CString::new(photo).map_err(|e| e.to_string())?;
        let int = |v: usize| c_int::try_from(v).map_err(|_| format!("{v} is too large for Tk"));
        let block = PhotoImageBlock {
            pixel_ptr: rgba.as_ptr(),
            width: int(width)?,
            height: int(height)?,
            pitch: int(width * 4)?,
            pixel_size: 4,
            offset: [0, 1, 2, 3],
        };
        // SAFETY: the interpreter is live and on this thread (the caller's contract); `name`
        // is NUL-terminated. Tk returns null for an unknown photo.
        let handle = unsafe { (self.find_photo)(interp.as_ptr(), name.as_ptr()) };
        if handle.is_null() {
            return Err(format!("no photo image '{photo}'"));
        }
        // SAFETY: `handle` is a live photo of this interpreter; `block` describes `rgba`,
        // which holds exactly width·height·4 bytes (checked above) and outlives the call (Tk
        // copies the pixels).
        let code = unsafe {
            (self.put_block)(
                interp.as_ptr(),
                handle,
                &block,
                int(x)?,
                int(y)?,
                block.width,
                block.height,
                COMPOSITE_SET,
            )
        };
        if code == 0 {
            Ok(())
        } else {
            // Tk fails here only when it cannot allocate the photo's memory.
            Err(format!(
                "Tk could not store a {width}×{height} block in '{photo}' (out of memory)"
            ))
        }
    }
}
