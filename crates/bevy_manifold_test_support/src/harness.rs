//! A test harness for files with GPU tests (libtest-mimic, so the output
//! and the summary line are libtest's): without a GPU adapter each GPU
//! test is listed as *ignored*, never as passed; under CI (`CI` set) a
//! missing adapter is no excuse, so the GPU tests run and fail. CPU tests
//! in the same file run everywhere.
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

use libtest_mimic::{Arguments, Trial};

/// Runs `cpu` tests always and `gpu` tests when a GPU adapter is there
/// (or under CI, where its absence is a failure); the process exit code is
/// libtest's.
#[must_use]
pub fn run(cpu: &[(&'static str, fn())], gpu: &[(&'static str, fn())]) -> std::process::ExitCode {
    let args = Arguments::from_args();
    let adapter = if gpu.is_empty() {
        Ok(String::new())
    } else {
        bevy_manifold_gpu::probe_adapter().map_err(|e| e.to_string())
    };
    let ci = std::env::var_os("CI").is_some();
    match (&adapter, gpu.is_empty()) {
        (_, true) => {}
        (Ok(name), false) => eprintln!("GPU adapter: {name}"),
        (Err(e), false) if ci => eprintln!("no GPU adapter under CI, so the GPU tests fail: {e}"),
        (Err(e), false) => eprintln!("no GPU adapter ({e}): the GPU tests are ignored"),
    }
    let skip_gpu = adapter.is_err() && !ci;
    let trial = |(name, test): &(&'static str, fn()), ignored: bool| {
        let test = *test;
        Trial::test(*name, move || {
            test();
            Ok(())
        })
        .with_ignored_flag(ignored)
    };
    let trials = cpu
        .iter()
        .map(|t| trial(t, false))
        .chain(gpu.iter().map(|t| trial(t, skip_gpu)))
        .collect();
    libtest_mimic::run(&args, trials).exit_code()
}

/// The `main` of a test file with GPU tests: `cpu: [...]` run always,
/// `gpu: [...]` only with an adapter (see the module docs).
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
