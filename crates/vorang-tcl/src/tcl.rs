//! A minimal safe wrapper over the Tcl 8.6 C API (docs/architecture.md): an interpreter that owns its
//! registered commands, evaluation of strings and files, results, variables and list splitting.
//!
//! Only the dozen calls VoRANG needs are declared. Every `unsafe` block states why it is sound;
//! the common invariants are that `Interp::raw` is a live interpreter created by
//! `Tcl_CreateInterp` and deleted only in `Drop`, and that Tcl is only used from the thread that
//! created the interpreter (`Interp` is neither `Send` nor `Sync`).

use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::marker::PhantomData;
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::path::Path;
use std::sync::Once;

#[repr(C)]
struct TclInterp {
    _private: [u8; 0],
}

#[repr(C)]
struct TclObj {
    _private: [u8; 0],
}

type ObjCmdProc =
    unsafe extern "C" fn(*mut c_void, *mut TclInterp, c_int, *const *mut TclObj) -> c_int;
type CmdDeleteProc = unsafe extern "C" fn(*mut c_void);

const TCL_OK: c_int = 0;
const TCL_ERROR: c_int = 1;
const TCL_GLOBAL_ONLY: c_int = 1;
const TCL_EVAL_GLOBAL: c_int = 0x020000;

unsafe extern "C" {
    fn Tcl_FindExecutable(argv0: *const c_char);
    fn Tcl_CreateInterp() -> *mut TclInterp;
    fn Tcl_DeleteInterp(interp: *mut TclInterp);
    fn Tcl_Init(interp: *mut TclInterp) -> c_int;
    fn Tcl_CreateObjCommand(
        interp: *mut TclInterp,
        name: *const c_char,
        proc_: ObjCmdProc,
        client_data: *mut c_void,
        delete: Option<CmdDeleteProc>,
    ) -> *mut c_void;
    fn Tcl_EvalEx(interp: *mut TclInterp, script: *const c_char, len: c_int, flags: c_int)
    -> c_int;
    fn Tcl_EvalFile(interp: *mut TclInterp, path: *const c_char) -> c_int;
    fn Tcl_GetStringResult(interp: *mut TclInterp) -> *const c_char;
    fn Tcl_SetObjResult(interp: *mut TclInterp, obj: *mut TclObj);
    fn Tcl_NewStringObj(bytes: *const c_char, len: c_int) -> *mut TclObj;
    fn Tcl_GetStringFromObj(obj: *mut TclObj, len: *mut c_int) -> *const c_char;
    fn Tcl_GetVar2(
        interp: *mut TclInterp,
        name1: *const c_char,
        name2: *const c_char,
        flags: c_int,
    ) -> *const c_char;
    fn Tcl_SetVar2(
        interp: *mut TclInterp,
        name1: *const c_char,
        name2: *const c_char,
        value: *const c_char,
        flags: c_int,
    ) -> *const c_char;
    fn Tcl_ListObjGetElements(
        interp: *mut TclInterp,
        list: *mut TclObj,
        objc: *mut c_int,
        objv: *mut *mut *mut TclObj,
    ) -> c_int;
    fn Tcl_CommandComplete(cmd: *const c_char) -> c_int;
    fn Tcl_GetErrorLine(interp: *mut TclInterp) -> c_int;
}

/// A command handler: receives the interpreter (for nested evaluation and list parsing) and the
/// words of the call (`words[0]` is the command name); returns the result or an error message.
pub type Handler = Box<dyn FnMut(&Interp, &[String]) -> Result<String, String>>;

/// A Tcl interpreter.
pub struct Interp {
    raw: *mut TclInterp,
    /// Keeps the handlers alive as long as Tcl may call them. Each handler is boxed once more
    /// so that its address — handed to Tcl as client data — stays put when the Vec grows.
    #[allow(clippy::vec_box)]
    handlers: Vec<Box<Handler>>,
    /// Tcl is single-threaded per interpreter: not `Send`, not `Sync`.
    _not_send: PhantomData<*mut ()>,
}

/// The outcome of an evaluation that failed: the message and Tcl's stack trace.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TclError {
    pub message: String,
    /// The `errorInfo` trace.
    pub info: String,
    /// `Tcl_GetErrorLine`: the line of the failing command within the evaluated script.
    pub line: usize,
}

fn cstring(s: &str) -> CString {
    // Tcl strings cannot hold NUL bytes in this interface; drop any.
    CString::new(s.replace('\0', "")).unwrap_or_default()
}

/// Copies a C string Tcl owns into Rust.
///
/// # Safety
/// `p` must be null or point to a NUL-terminated string that stays valid during the call.
unsafe fn owned(p: *const c_char) -> String {
    if p.is_null() {
        String::new()
    } else {
        // SAFETY: non-null and NUL-terminated by the caller's guarantee.
        unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
    }
}

/// The string value of a Tcl object.
///
/// # Safety
/// `obj` must point to a live Tcl object.
unsafe fn obj_string(obj: *mut TclObj) -> String {
    let mut len: c_int = 0;
    // SAFETY: `obj` is live; Tcl returns its string rep (valid while the object lives) and its
    // length in bytes.
    let p = unsafe { Tcl_GetStringFromObj(obj, &mut len) };
    if p.is_null() || len <= 0 {
        return String::new();
    }
    // SAFETY: Tcl guarantees `len` readable bytes at `p`.
    let bytes = unsafe { std::slice::from_raw_parts(p as *const u8, len as usize) };
    String::from_utf8_lossy(bytes).into_owned()
}

/// The trampoline Tcl calls for every registered command.
///
/// # Safety
/// `client_data` is the `Box<Handler>` registered with this command, alive until the
/// interpreter is deleted; `objv` holds `objc` live objects for the duration of the call.
unsafe extern "C" fn trampoline(
    client_data: *mut c_void,
    interp: *mut TclInterp,
    objc: c_int,
    objv: *const *mut TclObj,
) -> c_int {
    // SAFETY: see the function's contract.
    let handler = unsafe { &mut *(client_data as *mut Handler) };
    let words: Vec<String> = (0..objc.max(0) as usize)
        // SAFETY: objv has objc valid entries.
        .map(|i| unsafe { obj_string(*objv.add(i)) })
        .collect();
    // A borrowed view of the interpreter for the handler; it must not delete it.
    let view = std::mem::ManuallyDrop::new(Interp {
        raw: interp,
        handlers: Vec::new(),
        _not_send: PhantomData,
    });
    // Never unwind into C: a panic becomes a Tcl error.
    let result = catch_unwind(AssertUnwindSafe(|| handler(&view, &words))).unwrap_or_else(|_| {
        Err(format!(
            "internal error in {}: please report this",
            words.first().map_or("", |w| w.as_str())
        ))
    });
    let (code, text) = match result {
        Ok(s) => (TCL_OK, s),
        Err(s) => (TCL_ERROR, s),
    };
    let c = cstring(&text);
    // SAFETY: `interp` is live during the call; Tcl copies the bytes into a new object whose
    // ownership passes to the interpreter result.
    unsafe { Tcl_SetObjResult(interp, Tcl_NewStringObj(c.as_ptr(), -1)) };
    code
}

static INIT: Once = Once::new();

impl Interp {
    /// A new interpreter with the standard Tcl commands (and Tcl's script library, if installed).
    pub fn new() -> Interp {
        INIT.call_once(|| {
            // SAFETY: called once per process before any interpreter exists; a null argv0 is
            // allowed and only affects `info nameofexecutable`.
            unsafe { Tcl_FindExecutable(std::ptr::null()) };
        });
        // SAFETY: Tcl is initialised; the returned interpreter is owned by the new `Interp`.
        let raw = unsafe { Tcl_CreateInterp() };
        // SAFETY: `raw` is live. Failure only means Tcl's script library (init.tcl) was not
        // found; the built-in commands still work, so the result is ignored.
        unsafe { Tcl_Init(raw) };
        Interp {
            raw,
            handlers: Vec::new(),
            _not_send: PhantomData,
        }
    }

    /// Registers (or replaces) command `name`.
    pub fn register(&mut self, name: &str, handler: Handler) {
        let mut boxed: Box<Handler> = Box::new(handler);
        let data = &mut *boxed as *mut Handler as *mut c_void;
        self.handlers.push(boxed);
        let c = cstring(name);
        // SAFETY: `raw` is live; `data` points into a Box kept in `self.handlers` until the
        // interpreter is deleted in `Drop` (a later registration of the same name only adds a
        // new Box, the old one stays valid).
        unsafe { Tcl_CreateObjCommand(self.raw, c.as_ptr(), trampoline, data, None) };
    }

    fn error(&self) -> TclError {
        TclError {
            // SAFETY: `raw` is live; the result string is valid until the next Tcl call.
            message: unsafe { owned(Tcl_GetStringResult(self.raw)) },
            info: self.get_var("errorInfo").unwrap_or_default(),
            // SAFETY: `raw` is live.
            line: unsafe { Tcl_GetErrorLine(self.raw) }.max(0) as usize,
        }
    }

    fn finish(&self, code: c_int) -> Result<String, TclError> {
        if code == TCL_OK {
            // SAFETY: `raw` is live; the result string is copied at once.
            Ok(unsafe { owned(Tcl_GetStringResult(self.raw)) })
        } else {
            Err(self.error())
        }
    }

    /// Evaluates a script at global level.
    pub fn eval(&self, script: &str) -> Result<String, TclError> {
        let c = cstring(script);
        // SAFETY: `raw` is live; the script is NUL-terminated (length −1).
        let code = unsafe { Tcl_EvalEx(self.raw, c.as_ptr(), -1, TCL_EVAL_GLOBAL) };
        self.finish(code)
    }

    /// Evaluates a file, as `source` does (`info script` is the file while it runs).
    pub fn eval_file(&self, path: &Path) -> Result<String, TclError> {
        let c = cstring(&path.to_string_lossy());
        // SAFETY: `raw` is live; the path is NUL-terminated.
        let code = unsafe { Tcl_EvalFile(self.raw, c.as_ptr()) };
        self.finish(code)
    }

    /// A global variable (or array element `name(key)` via `name2`).
    pub fn get_var(&self, name: &str) -> Option<String> {
        let c = cstring(name);
        // SAFETY: `raw` is live; a null `name2` means a scalar or `name(key)` syntax.
        let p = unsafe { Tcl_GetVar2(self.raw, c.as_ptr(), std::ptr::null(), TCL_GLOBAL_ONLY) };
        // SAFETY: Tcl returns null or a valid string owned by the variable.
        (!p.is_null()).then(|| unsafe { owned(p) })
    }

    pub fn set_var(&self, name: &str, value: &str) {
        let (n, v) = (cstring(name), cstring(value));
        // SAFETY: `raw` is live; both strings are NUL-terminated and copied by Tcl.
        unsafe {
            Tcl_SetVar2(
                self.raw,
                n.as_ptr(),
                std::ptr::null(),
                v.as_ptr(),
                TCL_GLOBAL_ONLY,
            )
        };
    }

    /// Splits a Tcl list (with Tcl's own quoting rules).
    pub fn split_list(&self, list: &str) -> Result<Vec<String>, String> {
        let c = cstring(list);
        // SAFETY: `raw` is live. The new object has reference count 0; it is handed to
        // Tcl_SetObjResult below, which takes ownership and frees it later, so it does not leak.
        unsafe {
            let obj = Tcl_NewStringObj(c.as_ptr(), -1);
            let mut n: c_int = 0;
            let mut items: *mut *mut TclObj = std::ptr::null_mut();
            let code = Tcl_ListObjGetElements(self.raw, obj, &mut n, &mut items);
            let out = if code == TCL_OK {
                Ok((0..n.max(0) as usize)
                    .map(|i| obj_string(*items.add(i)))
                    .collect())
            } else {
                Err(owned(Tcl_GetStringResult(self.raw)))
            };
            Tcl_SetObjResult(self.raw, obj);
            out
        }
    }

    /// The `Tcl_Interp*` for C calls into libraries Tcl loaded (Tk's photo images,
    /// [`super::tk`]); valid while `self` lives, and only on this thread.
    pub(crate) fn as_ptr(&self) -> *mut c_void {
        self.raw as *mut c_void
    }

    /// True if `script` is a complete command (balanced braces and quotes): for the prompt.
    pub fn complete(script: &str) -> bool {
        let c = cstring(script);
        // SAFETY: pure function on a NUL-terminated string.
        unsafe { Tcl_CommandComplete(c.as_ptr()) != 0 }
    }
}

impl Default for Interp {
    fn default() -> Self {
        Interp::new()
    }
}

impl Drop for Interp {
    fn drop(&mut self) {
        // Views handed to handlers are wrapped in ManuallyDrop (see `trampoline`), so every
        // Interp that is dropped owns its interpreter.
        // SAFETY: `raw` was created by Tcl_CreateInterp in `new` and is deleted exactly once,
        // before the handlers it refers to are dropped with `self.handlers`.
        unsafe { Tcl_DeleteInterp(self.raw) };
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn evaluates_tcl_with_float_math_and_lists() {
        let i = Interp::new();
        assert_eq!(
            i.eval("expr {sin(0.5)*2.0}").unwrap(),
            format!("{}", (0.5f64).sin() * 2.0)
        );
        assert_eq!(i.eval("expr {7/2.0}").unwrap(), "3.5");
        assert_eq!(
            i.split_list("a {b c} \"d e\"").unwrap(),
            vec!["a", "b c", "d e"]
        );
        assert!(i.split_list("a {b").is_err());
        assert!(Interp::complete("set a 1"));
        assert!(!Interp::complete("for {set i 0} {$i < 3} {"));
    }

    #[test]
    fn commands_get_words_and_return_results_or_errors() {
        let mut i = Interp::new();
        let mut calls = 0;
        i.register(
            "twice",
            Box::new(move |_, w| {
                calls += 1;
                match w.get(1).and_then(|v| v.parse::<f64>().ok()) {
                    Some(v) => Ok(format!("{}", 2.0 * v)),
                    None => Err(format!(
                        "wrong # args: should be \"twice x\" (call {calls})"
                    )),
                }
            }),
        );
        assert_eq!(i.eval("twice [expr {1.5+1}]").unwrap(), "5");
        let e = i.eval("set a 1\n\ntwice").unwrap_err();
        assert!(e.message.contains("wrong # args"), "{e:?}");
        assert_eq!(e.line, 3);
        assert!(e.info.contains("twice"));
        i.register("boom", Box::new(|_, _| panic!("bad")));
        assert!(
            i.eval("boom")
                .unwrap_err()
                .message
                .contains("internal error")
        );
    }
}
