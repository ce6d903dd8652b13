//! The operating system's part of a cyclic thread: the monotonic clock, sleeping to an
//! absolute deadline, SCHED_FIFO, locked memory and the timer slack; and a program file read
//! into pages taken ahead. Linux only; elsewhere every request reports "not supported",
//! sleeping falls back to `std::thread::sleep` and a file is read as it comes.

use std::fmt;

/// What the IPO thread asked for and got.
#[derive(Clone, Debug)]
pub struct RtReport {
    /// SCHED_FIFO with this priority, or why not.
    pub fifo: Result<i32, String>,
    /// mlockall(MCL_CURRENT | MCL_FUTURE), or why not.
    pub mlock: Result<(), String>,
    /// Timer slack set to this many ns, or why not.
    pub slack: Result<u64, String>,
    /// /dev/cpu_dma_latency held at 0 µs (no deep idle states while the kernel runs, as
    /// cyclictest does), or why not.
    pub dma_latency: Result<(), String>,
}

impl fmt::Display for RtReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match &self.fifo {
            Ok(p) => write!(f, "SCHED_FIFO priority {p}")?,
            Err(e) => write!(f, "SCHED_FIFO refused ({e}), running SCHED_OTHER")?,
        }
        match &self.mlock {
            Ok(()) => write!(f, ", memory locked")?,
            Err(e) => write!(f, ", memory not locked ({e})")?,
        }
        match &self.slack {
            Ok(ns) => write!(f, ", timer slack {ns} ns")?,
            Err(e) => write!(f, ", timer slack unchanged ({e})")?,
        }
        match &self.dma_latency {
            Ok(()) => write!(f, ", cpu_dma_latency 0 µs"),
            Err(e) => write!(f, ", cpu_dma_latency not held ({e})"),
        }
    }
}

/// Nanoseconds on the monotonic clock.
#[cfg(target_os = "linux")]
pub fn now_ns() -> u64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: ts is a valid out-pointer; CLOCK_MONOTONIC always exists on Linux.
    unsafe { libc::clock_gettime(libc::CLOCK_MONOTONIC, &mut ts) };
    ts.tv_sec as u64 * 1_000_000_000 + ts.tv_nsec as u64
}

/// Sleeps until the monotonic clock reads `deadline_ns` (absolute: no drift from the time
/// the cycle's work took).
#[cfg(target_os = "linux")]
pub fn sleep_until(deadline_ns: u64) {
    let ts = libc::timespec {
        tv_sec: (deadline_ns / 1_000_000_000) as libc::time_t,
        tv_nsec: (deadline_ns % 1_000_000_000) as libc::c_long,
    };
    loop {
        // SAFETY: ts is valid; the remaining-time pointer may be null with TIMER_ABSTIME.
        let r = unsafe {
            libc::clock_nanosleep(
                libc::CLOCK_MONOTONIC,
                libc::TIMER_ABSTIME,
                &ts,
                std::ptr::null_mut(),
            )
        };
        if r != libc::EINTR {
            return;
        }
    }
}

/// Asks for what a cyclic thread needs; call it in that thread. Each request may be refused
/// (no CAP_SYS_NICE, an RLIMIT_MEMLOCK too small): the report says what was got. Keep the
/// returned file open while the thread runs (closing it gives up the latency request).
#[cfg(target_os = "linux")]
pub fn setup_cyclic_thread(priority: i32, slack_ns: u64) -> (RtReport, Option<std::fs::File>) {
    let errno = || std::io::Error::last_os_error().to_string();
    // SAFETY: plain system calls on the calling thread with valid arguments.
    let fifo = unsafe {
        let param = libc::sched_param {
            sched_priority: priority,
        };
        let r = libc::pthread_setschedparam(libc::pthread_self(), libc::SCHED_FIFO, &param);
        if r == 0 {
            Ok(priority)
        } else {
            Err(std::io::Error::from_raw_os_error(r).to_string())
        }
    };
    let mlock = unsafe {
        if libc::mlockall(libc::MCL_CURRENT | libc::MCL_FUTURE) == 0 {
            Ok(())
        } else {
            Err(errno())
        }
    };
    let slack = unsafe {
        if libc::prctl(libc::PR_SET_TIMERSLACK, slack_ns as libc::c_ulong, 0, 0, 0) == 0 {
            Ok(slack_ns.max(1))
        } else {
            Err(errno())
        }
    };
    let dma = std::fs::OpenOptions::new()
        .write(true)
        .open("/dev/cpu_dma_latency")
        .and_then(|mut f| {
            use std::io::Write;
            f.write_all(&0i32.to_ne_bytes())?;
            Ok(f)
        });
    let (dma_latency, file) = match dma {
        Ok(f) => (Ok(()), Some(f)),
        Err(e) => (Err(e.to_string()), None),
    };
    (
        RtReport {
            fifo,
            mlock,
            slack,
            dma_latency,
        },
        file,
    )
}

#[cfg(not(target_os = "linux"))]
pub fn now_ns() -> u64 {
    use std::sync::OnceLock;
    static START: OnceLock<std::time::Instant> = OnceLock::new();
    START
        .get_or_init(std::time::Instant::now)
        .elapsed()
        .as_nanos() as u64
}

#[cfg(not(target_os = "linux"))]
pub fn sleep_until(deadline_ns: u64) {
    let now = now_ns();
    if deadline_ns > now {
        std::thread::sleep(std::time::Duration::from_nanos(deadline_ns - now));
    }
}

#[cfg(not(target_os = "linux"))]
pub fn setup_cyclic_thread(_priority: i32, _slack_ns: u64) -> (RtReport, Option<std::fs::File>) {
    let no = || Err("not supported on this OS".to_string());
    (
        RtReport {
            fifo: no(),
            mlock: no(),
            slack: no(),
            dma_latency: no(),
        },
        None,
    )
}

/// The rest of `file` (opened, `len` bytes by its metadata), read into memory whose pages are
/// taken in one request before the read (`MADV_POPULATE_WRITE`), so that the copy meets no
/// page fault: a 6.5 MB program is read in 3.0 ms instead of 3.6 (docs/benchmarks.md). Where
/// the request is refused (an older kernel, another OS) the read takes its pages as it goes.
pub fn read_file(mut file: &std::fs::File, len: u64) -> std::io::Result<Vec<u8>> {
    let mut bytes = Vec::new();
    let too_large = |_| std::io::Error::new(std::io::ErrorKind::OutOfMemory, "file too large");
    bytes
        .try_reserve_exact(usize::try_from(len).unwrap_or(usize::MAX))
        .map_err(too_large)?;
    take_pages(bytes.spare_capacity_mut());
    std::io::Read::read_to_end(&mut file, &mut bytes)?;
    Ok(bytes)
}

/// Takes the whole pages of `room` ahead of writing them (nothing written, nothing read).
#[cfg(target_os = "linux")]
fn take_pages(room: &mut [std::mem::MaybeUninit<u8>]) {
    // SAFETY: sysconf reads no memory of ours.
    let page = usize::try_from(unsafe { libc::sysconf(libc::_SC_PAGESIZE) }).unwrap_or(0);
    if room.len() < 16 * page.max(1) {
        return;
    }
    let start = room.as_mut_ptr() as usize;
    let (first, end) = (
        start.next_multiple_of(page),
        (start + room.len()) / page * page,
    );
    // SAFETY: [first, end) lies within `room`, memory this process owns and may write;
    // MADV_POPULATE_WRITE only faults its pages in (their contents stay what they are).
    unsafe {
        libc::madvise(
            first as *mut libc::c_void,
            end - first,
            libc::MADV_POPULATE_WRITE,
        );
    }
}

#[cfg(not(target_os = "linux"))]
fn take_pages(_room: &mut [std::mem::MaybeUninit<u8>]) {}

/// Asks the process `pid` to end (SIGTERM): a child of this process, not yet reaped, so the
/// pid is still its own.
#[cfg(unix)]
pub fn terminate(pid: u32) {
    // SAFETY: kill(2) takes any pid and signal number; it touches no memory of ours.
    unsafe {
        libc::kill(pid as libc::pid_t, libc::SIGTERM);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_file_reads_back_whole_small_or_large() {
        let dir = std::env::temp_dir().join(format!("softnc-os-read-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        for n in [0usize, 1, 4095, 4096, 70_000, 1 << 20, (1 << 20) + 17] {
            let text: Vec<u8> = (0..n).map(|i| b'0' + (i % 10) as u8).collect();
            let path = dir.join(format!("{n}.nc"));
            std::fs::write(&path, &text).unwrap();
            let file = std::fs::File::open(&path).unwrap();
            let len = file.metadata().unwrap().len();
            assert_eq!(read_file(&file, len).unwrap(), text);
            // A file that grew since its length was taken is read whole all the same.
            assert_eq!(
                read_file(&std::fs::File::open(&path).unwrap(), 0).unwrap(),
                text
            );
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn sleeping_to_a_deadline_wakes_after_it() {
        let t0 = now_ns();
        for k in 1..=5 {
            let deadline = t0 + k * 1_000_000;
            sleep_until(deadline);
            assert!(now_ns() >= deadline);
        }
    }
}
