//! A pseudo-terminal for a Modbus master (pysunspec2, mbpoll, a SCADA),
//! bridged to the ATmega2560's USART2 (`suntracker-emu --modbus-pty PATH`).
//!
//! `openpty(3)` makes the pair; the slave side is set raw (`cfmakeraw`: no
//! line discipline between the client and the image), linked at PATH and
//! closed here, so the master side reports a hang-up (`POLLHUP`) exactly
//! while no client holds the terminal open — the same arrangement as
//! `.ci/qemu_gps.py --modbus-pty`. [`ModbusPty::pass`] moves the client's
//! bytes into the USART's receive queue (simavr hands them to the image at
//! the baud rate it programmed, back to back: a request written at once
//! is one frame) and the image's bytes to the client.
//!
//! SIGTERM and SIGINT ([`install_stop_handler`]) end the run at the next
//! service of the bench, with its summary, instead of killing it.

use std::ffi::CStr;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};

use crate::models::modbus_master::UART;
use crate::sim::Sim;

static STOP: AtomicBool = AtomicBool::new(false);

extern "C" fn on_stop(_: libc::c_int) {
    STOP.store(true, Ordering::Relaxed);
}

/// Makes SIGTERM and SIGINT set the flag [`stop_requested`] reads.
pub fn install_stop_handler() {
    let handler = on_stop as extern "C" fn(libc::c_int) as libc::sighandler_t;
    // SAFETY: the handler only stores to an atomic (async-signal-safe).
    unsafe {
        libc::signal(libc::SIGTERM, handler);
        libc::signal(libc::SIGINT, handler);
    }
}

/// Whether SIGTERM or SIGINT arrived since [`install_stop_handler`].
pub fn stop_requested() -> bool {
    STOP.load(Ordering::Relaxed)
}

/// The master side of the pair and the link to its slave.
pub struct ModbusPty {
    master: libc::c_int,
    link: PathBuf,
}

fn os_err(what: &str) -> String {
    format!("{what}: {}", std::io::Error::last_os_error())
}

impl ModbusPty {
    /// Opens a pair, sets it raw and links `link` (replaced if it exists)
    /// to the slave's device.
    pub fn open(link: &Path) -> Result<ModbusPty, String> {
        let (mut master, mut slave) = (0, 0);
        // SAFETY: openpty writes the two descriptors; the name, termios and
        // window size pointers may be null.
        let r = unsafe {
            libc::openpty(
                &mut master,
                &mut slave,
                std::ptr::null_mut(),
                std::ptr::null(),
                std::ptr::null(),
            )
        };
        if r != 0 {
            return Err(os_err("openpty"));
        }
        // SAFETY: termios is plain data, filled by tcgetattr.
        let mut tio: libc::termios = unsafe { std::mem::zeroed() };
        let name = unsafe {
            libc::tcgetattr(slave, &mut tio);
            libc::cfmakeraw(&mut tio);
            libc::tcsetattr(slave, libc::TCSANOW, &tio);
            let p = libc::ttyname(slave);
            if p.is_null() {
                None
            } else {
                Some(CStr::from_ptr(p).to_string_lossy().into_owned())
            }
        };
        unsafe {
            libc::close(slave);
            let flags = libc::fcntl(master, libc::F_GETFL);
            libc::fcntl(master, libc::F_SETFL, flags | libc::O_NONBLOCK);
        }
        let name = name.ok_or_else(|| os_err("ttyname"))?;
        if std::fs::symlink_metadata(link).is_ok() {
            std::fs::remove_file(link).map_err(|e| format!("{}: {e}", link.display()))?;
        }
        std::os::unix::fs::symlink(&name, link).map_err(|e| format!("{}: {e}", link.display()))?;
        Ok(ModbusPty {
            master,
            link: link.to_path_buf(),
        })
    }

    /// Whether a client holds the terminal open (no hang-up on the master
    /// side).
    pub fn attached(&mut self) -> bool {
        let mut fd = libc::pollfd {
            fd: self.master,
            events: libc::POLLIN,
            revents: 0,
        };
        // SAFETY: one valid pollfd, no wait.
        let n = unsafe { libc::poll(&mut fd, 1, 0) };
        n >= 0 && fd.revents & libc::POLLHUP == 0
    }

    /// Moves the client's bytes to USART2's receive queue and the image's
    /// bytes to the client (dropped while no client is attached, as on a
    /// bus with no master).
    pub fn pass(&mut self, sim: &mut Sim) {
        let mut buf = [0u8; 512];
        loop {
            // SAFETY: reads into a buffer of its length.
            let n = unsafe { libc::read(self.master, buf.as_mut_ptr().cast(), buf.len()) };
            if n <= 0 {
                break;
            }
            // The line at the rate the registers say (`Sim::retime_uart`).
            sim.retime_uart(UART);
            sim.uart_send(UART, &buf[..n as usize]);
        }
        let out = sim.uart_take(UART);
        if !out.is_empty() && self.attached() {
            // A pty's buffer takes kilobytes; a reply is at most 256 bytes.
            // SAFETY: writes from a buffer of its length.
            unsafe { libc::write(self.master, out.as_ptr().cast(), out.len()) };
        }
    }
}

impl Drop for ModbusPty {
    fn drop(&mut self) {
        // SAFETY: the descriptor is ours.
        unsafe { libc::close(self.master) };
        if std::fs::symlink_metadata(&self.link).is_ok_and(|m| m.file_type().is_symlink()) {
            let _ = std::fs::remove_file(&self.link);
        }
    }
}
