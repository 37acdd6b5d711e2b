//! A test harness for test files with tests that need something the
//! machine may not have (a GPU adapter, the shared Curved Spaces files):
//! libtest-mimic, so the output and the summary line are libtest's.
//! Without it each such test is listed as *ignored*, never as passed;
//! under CI (`CI` set) its absence is no excuse, so those tests run and
//! fail. The other tests in the file run everywhere.
//!
//! A test file sets `harness = false` in its crate's `Cargo.toml` and ends
//! with:
//!
//! ```text
//! bevy_manifold_test_support::test_main! {
//!     cpu: [the_bvh_finds_the_nearest_hit],
//!     gpu: [gpu_and_cpu_agree_in_every_space],
//! }
//! ```
//!
//! or, for another requirement, `test_main_requiring!` with
//! `requiring(what, availability): [...]`.

use libtest_mimic::{Arguments, Trial};

/// Runs `always` tests everywhere and `needing` tests when `available` is
/// `Ok` (naming what was found) or under CI (where its `Err` is a
/// failure); the process exit code is libtest's. `what` names the
/// requirement in the lines printed.
#[must_use]
pub fn run_requiring(
    always: &[(&'static str, fn())],
    needing: &[(&'static str, fn())],
    what: &str,
    available: Result<String, String>,
) -> std::process::ExitCode {
    let args = Arguments::from_args();
    let ci = std::env::var_os("CI").is_some();
    if !needing.is_empty() {
        match &available {
            Ok(found) => eprintln!("{what}: {found}"),
            Err(e) if ci => eprintln!("no {what} under CI, so the tests that need it fail: {e}"),
            Err(e) => eprintln!("no {what} ({e}): the tests that need it are ignored"),
        }
    }
    let skip = available.is_err() && !ci;
    let trial = |(name, test): &(&'static str, fn()), ignored: bool| {
        let test = *test;
        Trial::test(*name, move || {
            test();
            Ok(())
        })
        .with_ignored_flag(ignored)
    };
    let trials = always
        .iter()
        .map(|t| trial(t, false))
        .chain(needing.iter().map(|t| trial(t, skip)))
        .collect();
    let conclusion = libtest_mimic::run(&args, trials);
    end_process(conclusion.has_failed())
}

/// Ends the test process with libtest's status once the results are
/// printed. On Unix it leaves through `_exit`, skipping the C library's
/// exit handlers: Mesa's lavapipe tears its threads and LLVM state down
/// there, and with several devices made and dropped in one process that
/// teardown now and then corrupted the heap after every test had passed
/// ("double free or corruption", SIGABRT: a green run reported as a
/// failure). Nothing a test needs runs after this point.
fn end_process(failed: bool) -> std::process::ExitCode {
    use std::io::Write;
    let status = if failed { 101 } else { 0 };
    let _ = std::io::stdout().flush();
    let _ = std::io::stderr().flush();
    #[cfg(unix)]
    // SAFETY: `_exit` ends the process at once; every output stream this
    // harness wrote was flushed above.
    unsafe {
        libc::_exit(status)
    }
    #[cfg(not(unix))]
    std::process::ExitCode::from(status as u8)
}

/// Runs `cpu` tests always and `gpu` tests when a GPU adapter is there
/// (or under CI, where its absence is a failure).
#[cfg(feature = "gpu")]
#[must_use]
pub fn run(cpu: &[(&'static str, fn())], gpu: &[(&'static str, fn())]) -> std::process::ExitCode {
    let adapter = if gpu.is_empty() {
        Ok(String::new())
    } else {
        bevy_manifold_gpu::probe_adapter().map_err(|e| e.to_string())
    };
    run_requiring(cpu, gpu, "GPU adapter", adapter)
}

/// The `main` of a test file with GPU tests: `cpu: [...]` run always,
/// `gpu: [...]` only with an adapter (see the module docs).
#[cfg(feature = "gpu")]
#[macro_export]
macro_rules! test_main {
    (cpu: [$($cpu:path),* $(,)?], gpu: [$($gpu:path),* $(,)?] $(,)?) => {
        fn main() -> std::process::ExitCode {
            $crate::harness::run(
                &[$((stringify!($cpu), $cpu as fn())),*],
                &[$((stringify!($gpu), $gpu as fn())),*],
            )
        }
    };
}

/// The `main` of a test file with tests that need something else:
/// `requiring(what, availability): [...]` run when `availability` (a
/// `Result<String, String>`) is `Ok`, or under CI.
#[macro_export]
macro_rules! test_main_requiring {
    (cpu: [$($cpu:path),* $(,)?], requiring($what:expr, $available:expr): [$($needing:path),* $(,)?] $(,)?) => {
        fn main() -> std::process::ExitCode {
            $crate::harness::run_requiring(
                &[$((stringify!($cpu), $cpu as fn())),*],
                &[$((stringify!($needing), $needing as fn())),*],
                $what,
                $available,
            )
        }
    };
}
