//! Step timings of a cut, for tuning: with `KATACHI_CUT_TRACE` set in the environment, each
//! cut prints how long its steps took to stderr. Off, a mark costs one load of a flag read
//! once per process.

use std::sync::OnceLock;
use std::time::Instant;

fn enabled() -> bool {
    static ON: OnceLock<bool> = OnceLock::new();
    *ON.get_or_init(|| std::env::var_os("KATACHI_CUT_TRACE").is_some())
}

/// Timings of consecutive steps.
pub(crate) struct Trace {
    on: bool,
    start: Instant,
    last: Instant,
    steps: Vec<(&'static str, f64)>,
}

impl Trace {
    pub fn start() -> Self {
        let now = Instant::now();
        Trace {
            on: enabled(),
            start: now,
            last: now,
            steps: Vec::new(),
        }
    }

    /// Ends step `name` (it began at the previous mark).
    #[inline]
    pub fn mark(&mut self, name: &'static str) {
        if self.on {
            let now = Instant::now();
            self.steps.push((name, (now - self.last).as_secs_f64()));
            self.last = now;
        }
    }
}

impl Drop for Trace {
    fn drop(&mut self) {
        if self.on {
            let mut s = String::from("katachi cut:");
            for (name, t) in &self.steps {
                s += &format!(" {name} {:.3}", t * 1e3);
            }
            s += &format!(
                " | total {:.3} ms",
                self.start.elapsed().as_secs_f64() * 1e3
            );
            eprintln!("{s}");
        }
    }
}
