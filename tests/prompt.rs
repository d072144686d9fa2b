//! The interactive prompt in a pseudo-terminal: tab completes command names
//! and file names, and a mistyped command names the nearest one.
#![cfg(unix)]

use std::io::{Read, Write};
use std::os::fd::{FromRawFd, OwnedFd};
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// A pseudo-terminal pair: (master, slave).
fn openpty() -> (std::fs::File, OwnedFd) {
    let (mut master, mut slave) = (0, 0);
    // SAFETY: openpty writes two new descriptors, which we own from here on.
    let rc = unsafe {
        libc::openpty(
            &mut master,
            &mut slave,
            std::ptr::null_mut(),
            std::ptr::null(),
            std::ptr::null(),
        )
    };
    assert_eq!(rc, 0, "openpty failed");
    // SAFETY: both descriptors are fresh and owned by nobody else.
    unsafe {
        (
            std::fs::File::from_raw_fd(master),
            OwnedFd::from_raw_fd(slave),
        )
    }
}

/// The program under test, ended if the test fails half-way.
struct Child(std::process::Child);

impl Drop for Child {
    fn drop(&mut self) {
        if self.0.try_wait().ok().flatten().is_none() {
            let _ = self.0.kill();
            let _ = self.0.wait();
        }
    }
}

/// Reads what the terminal shows until `want` appears (or 10 s pass).
fn read_until(master: &mut std::fs::File, seen: &mut String, want: &str) -> bool {
    let start = Instant::now();
    let mut buf = [0u8; 4096];
    while !seen.contains(want) {
        if start.elapsed() > Duration::from_secs(10) {
            return false;
        }
        // SAFETY: polling one descriptor we own.
        let mut pfd = libc::pollfd {
            fd: std::os::fd::AsRawFd::as_raw_fd(master),
            events: libc::POLLIN,
            revents: 0,
        };
        if unsafe { libc::poll(&mut pfd, 1, 100) } <= 0 {
            continue;
        }
        match master.read(&mut buf) {
            Ok(0) | Err(_) => return seen.contains(want),
            Ok(n) => seen.push_str(&String::from_utf8_lossy(&buf[..n])),
        }
    }
    true
}

/// Waits for `want`, then for the next fresh prompt after it (a prompt drawn after a line
/// break: redrawing the line being edited repeats the prompt without one).
fn then_prompt(master: &mut std::fs::File, seen: &mut String, want: &str) {
    assert!(read_until(master, seen, want), "{seen}");
    let at = seen.find(want).unwrap() + want.len();
    seen.drain(..at);
    assert!(read_until(master, seen, "\n"), "{seen}");
    let at = seen.find('\n').unwrap() + 1;
    seen.drain(..at);
    assert!(read_until(master, seen, "vorang> "), "{seen}");
    seen.clear();
}

#[test]
fn the_prompt_completes_and_suggests() {
    let (mut master, slave) = openpty();
    let child = Command::new(env!("CARGO_BIN_EXE_vorang"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(Stdio::from(slave.try_clone().unwrap()))
        .stdout(Stdio::from(slave.try_clone().unwrap()))
        .stderr(Stdio::from(slave))
        .spawn()
        .unwrap();
    let mut child = Child(child);
    let mut seen = String::new();
    assert!(read_until(&mut master, &mut seen, "vorang> "), "{seen}");
    // A command name, then a file name.
    master.write_all(b"colorm\t").unwrap();
    assert!(read_until(&mut master, &mut seen, "colormap"), "{seen}");
    master.write_all(b" examples/gauss/rain\t").unwrap();
    assert!(
        read_until(&mut master, &mut seen, "examples/gauss/rainbow.cmap"),
        "{seen}"
    );
    // Each line is typed at a fresh prompt: the editor drops what was typed ahead.
    master.write_all(b"\r").unwrap();
    then_prompt(&mut master, &mut seen, "rainbow.cmap");
    master.write_all(b"rendr_btf\r").unwrap();
    then_prompt(&mut master, &mut seen, "did you mean \"render_btf\"?");
    master.write_all(b"help legend\r").unwrap();
    then_prompt(&mut master, &mut seen, "legend on|off");
    master.write_all(b"exit\r").unwrap();
    let start = Instant::now();
    loop {
        if let Some(status) = child.0.try_wait().unwrap() {
            assert!(status.success());
            break;
        }
        if start.elapsed() > Duration::from_secs(10) {
            let _ = child.0.kill();
            panic!("the prompt did not exit: {seen}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

#[test]
fn ctrl_c_cancels_a_render_and_keeps_the_session() {
    use std::os::unix::process::CommandExt;
    let (mut master, slave) = openpty();
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_vorang"));
    cmd.current_dir(env!("CARGO_MANIFEST_DIR"))
        .stdin(Stdio::from(slave.try_clone().unwrap()))
        .stdout(Stdio::from(slave.try_clone().unwrap()))
        .stderr(Stdio::from(slave));
    // The terminal becomes the child's controlling terminal, so that Ctrl-C typed on it sends
    // SIGINT to the child.
    // SAFETY: only async-signal-safe calls between fork and exec.
    unsafe {
        cmd.pre_exec(|| {
            libc::setsid();
            libc::ioctl(0, libc::TIOCSCTTY as _, 0);
            Ok(())
        });
    }
    let mut child = Child(cmd.spawn().unwrap());
    let mut seen = String::new();
    assert!(read_until(&mut master, &mut seen, "vorang> "), "{seen}");
    let dir = tempfile::tempdir().unwrap();
    let line = format!(
        "output {{{}}}; volume examples/propEA/propEA.hmesh; imagesize 3000 3000; method exact linear 0.02 1; set kept 42; render_btf\r",
        dir.path().join("slow.png").display()
    );
    master.write_all(line.as_bytes()).unwrap();
    // The progress bar shows once the render has run for a second.
    assert!(read_until(&mut master, &mut seen, "rendering ["), "{seen}");
    seen.clear();
    master.write_all(b"\x03").unwrap();
    then_prompt(&mut master, &mut seen, "the render was cancelled");
    // The session goes on, with its state.
    master.write_all(b"puts \"kept $kept\"\r").unwrap();
    then_prompt(&mut master, &mut seen, "kept 42");
    assert!(std::fs::read_dir(dir.path()).unwrap().next().is_none());
    master.write_all(b"exit\r").unwrap();
    let start = Instant::now();
    while child.0.try_wait().unwrap().is_none() {
        if start.elapsed() > Duration::from_secs(10) {
            let _ = child.0.kill();
            panic!("the prompt did not exit: {seen}");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}
