//! What a point of a sweep costs: the CPU time of the thread that computed each batch.
//!
//! Wall time is what a user waits, but as a *cost* it is unreliable on a shared machine:
//! a batch whose thread is descheduled for another process is charged the other
//! process's time, and the longer a batch runs the likelier that is, so on a busy
//! machine large points look several times dearer per sample than small ones. The
//! CPU time of the computing thread (POSIX `clock_gettime(CLOCK_THREAD_CPUTIME_ID)`)
//! counts only the cycles the batch used. Where the thread clock is unavailable (not
//! a Unix), wall time stands in.

use std::time::Instant;

/// A stopwatch of the current thread's CPU time.
pub struct CpuTimer {
    cpu: Option<f64>,
    wall: Instant,
}

impl CpuTimer {
    /// Start timing the current thread.
    pub fn start() -> CpuTimer {
        CpuTimer {
            cpu: thread_cpu_seconds(),
            wall: Instant::now(),
        }
    }

    /// Seconds of CPU time this thread used since [`CpuTimer::start`] (wall seconds
    /// where the thread clock is unavailable). Call it on the thread that started it.
    pub fn seconds(&self) -> f64 {
        match (self.cpu, thread_cpu_seconds()) {
            (Some(a), Some(b)) if b >= a => b - a,
            _ => self.wall.elapsed().as_secs_f64(),
        }
    }
}

/// CPU seconds used by the current thread so far.
#[cfg(unix)]
pub fn thread_cpu_seconds() -> Option<f64> {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the call only writes into it.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_THREAD_CPUTIME_ID, &mut ts) };
    (rc == 0).then_some(ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9)
}

/// CPU seconds used by the current thread so far (unavailable here).
#[cfg(not(unix))]
pub fn thread_cpu_seconds() -> Option<f64> {
    None
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sleeping_costs_no_cpu_and_work_does() {
        let t = CpuTimer::start();
        std::thread::sleep(std::time::Duration::from_millis(30));
        let slept = t.seconds();
        let t = CpuTimer::start();
        let mut x = 0u64;
        let w = Instant::now();
        while w.elapsed().as_millis() < 30 {
            x = x.wrapping_mul(6364136223846793005).wrapping_add(1);
        }
        std::hint::black_box(x);
        let worked = t.seconds();
        if cfg!(unix) {
            assert!(slept < 0.01, "a sleeping thread used {slept} s of CPU");
            assert!(worked > 0.0 && worked < 1.0, "{worked}");
            assert!(worked > slept);
        }
    }
}
