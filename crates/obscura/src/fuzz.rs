//! The budget of the project's randomized robustness tests ("fuzz smoke tests": mutated
//! files and random settings that must give a value or a typed error, never a panic).
//! Each runs until it has done `cases` cases or `seconds` have passed, whichever comes
//! first, so the whole smoke run stays under a minute in CI; a long run by hand raises
//! both: `OBSCURA_FUZZ_CASES=10000000 OBSCURA_FUZZ_SECONDS=600 cargo test --release fuzz`.

use std::time::{Duration, Instant};

/// Cases and wall-clock limit of one fuzz test.
#[derive(Clone, Copy, Debug)]
pub struct Budget {
    cases: usize,
    deadline: Instant,
}

impl Budget {
    /// `default_cases` and `default_seconds`, each overridden by `OBSCURA_FUZZ_CASES` /
    /// `OBSCURA_FUZZ_SECONDS` when set.
    pub fn from_env(default_cases: usize, default_seconds: u64) -> Self {
        let var = |name: &str| std::env::var(name).ok().and_then(|s| s.parse().ok());
        let seconds = var("OBSCURA_FUZZ_SECONDS").unwrap_or(default_seconds);
        Self {
            cases: var("OBSCURA_FUZZ_CASES").map_or(default_cases, |c| c as usize),
            deadline: Instant::now() + Duration::from_secs(seconds),
        }
    }

    /// Whether case number `done` (counting from 0) should run.
    pub fn more(&self, done: usize) -> bool {
        done < self.cases && Instant::now() < self.deadline
    }
}
