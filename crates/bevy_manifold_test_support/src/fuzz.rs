//! Structured fuzzing on stable Rust: valid seed inputs mutated the way
//! broken and hostile files differ from good ones (numbers pushed to
//! extremes, fields dropped or retyped, arrays emptied or multiplied, lines
//! cut, repeated or garbled, bytes flipped), each fed to a parser that must
//! return, never panic, and never take long. Deterministic: a case is its
//! seed, so a failure names what reproduces it.
//!
//! A bounded run is part of the tests; `FUZZ_CASES=N` sets the count per
//! format for a long run (the README's command), and each input that ever
//! failed is kept under the tests' `fuzz/` folder and replayed every run.

use crate::Rng;
use serde_json::Value;
use std::panic::AssertUnwindSafe;
use std::time::{Duration, Instant};

/// Numbers a hostile file uses: zero, signed zero, extremes, subnormals,
/// off-by-a-bit integers.
const EXTREMES: [f64; 14] = [
    0.0,
    -0.0,
    1.0,
    -1.0,
    1e308,
    -1e308,
    1e-310,
    4_294_967_296.0,
    -2_147_483_649.0,
    3.0e9,
    1e20,
    0.5,
    255.0,
    1e6,
];

/// One mutation of a JSON value, somewhere in it.
pub fn mutate_json(v: &mut Value, rng: &mut Rng) {
    // Walk to a random node: at each level stop with chance 1/3.
    let mut node = v;
    loop {
        let children = match node {
            Value::Array(a) => a.len(),
            Value::Object(o) => o.len(),
            _ => 0,
        };
        if children == 0 || rng.below(3) == 0 {
            break;
        }
        let k = rng.below(children);
        node = match node {
            Value::Array(a) => &mut a[k],
            Value::Object(o) => o.values_mut().nth(k).expect("in range"),
            _ => unreachable!("has children"),
        };
    }
    match rng.below(9) {
        0 => *node = Value::from(EXTREMES[rng.below(EXTREMES.len())]),
        1 => *node = Value::Null,
        2 => *node = Value::from("not a number"),
        3 => *node = Value::Array(Vec::new()),
        4 => {
            // Scale a number a little or a lot.
            if let Some(x) = node.as_f64() {
                let f = [1.0 + 1e-9, 1.5, -1.0, 1e3, 1e-3][rng.below(5)];
                *node = Value::from(x * f);
            }
        }
        5 => {
            // Drop an entry.
            match node {
                Value::Array(a) if !a.is_empty() => {
                    a.remove(rng.below(a.len()));
                }
                Value::Object(o) if !o.is_empty() => {
                    let key = o.keys().nth(rng.below(o.len())).cloned().expect("in range");
                    o.remove(&key);
                }
                _ => *node = Value::Bool(true),
            }
        }
        6 => {
            // Repeat an array's entries (many of them).
            if let Value::Array(a) = node
                && let Some(first) = a.first().cloned()
            {
                let n = [2, 10, 300][rng.below(3)];
                a.extend(std::iter::repeat_n(first, n));
            }
        }
        7 => {
            // An unknown field.
            if let Value::Object(o) = node {
                o.insert("unexpected".into(), Value::from(1));
            }
        }
        _ => *node = Value::from(-(rng.below(1000) as f64)),
    }
}

/// One mutation of a text, by lines and tokens.
pub fn mutate_text(text: &str, rng: &mut Rng) -> String {
    let mut lines: Vec<String> = text.lines().map(String::from).collect();
    if lines.is_empty() {
        return "x".into();
    }
    let k = rng.below(lines.len());
    match rng.below(7) {
        0 => {
            lines.remove(k);
        }
        1 => {
            let l = lines[k].clone();
            lines.insert(k, l);
        }
        2 => lines[k] = "garbage 1 2".into(),
        3 => {
            // One token of the line to an extreme or a word.
            let mut tokens: Vec<String> = lines[k].split_whitespace().map(String::from).collect();
            if !tokens.is_empty() {
                let t = rng.below(tokens.len());
                tokens[t] = match rng.below(4) {
                    0 => "NaN".into(),
                    1 => "inf".into(),
                    2 => format!("{}", EXTREMES[rng.below(EXTREMES.len())]),
                    _ => format!("{}", rng.next_f64() * 4.0 - 2.0),
                };
            }
            lines[k] = tokens.join(" ");
        }
        4 => lines.truncate(k),
        5 => {
            let n = lines.len();
            lines.swap(k, rng.below(n));
        }
        _ => {
            // A number nudged: the matrix stays almost an isometry.
            let mut tokens: Vec<String> = lines[k].split_whitespace().map(String::from).collect();
            if let Some(t) = tokens.iter_mut().find(|t| t.parse::<f64>().is_ok()) {
                let x: f64 = t.parse().unwrap_or(0.0);
                *t = format!("{}", x + [1e-12, 1e-6, 0.1][rng.below(3)]);
            }
            lines[k] = tokens.join(" ");
        }
    }
    lines.join("\n")
}

/// One mutation of bytes: flips, cut, repeats.
pub fn mutate_bytes(bytes: &mut Vec<u8>, rng: &mut Rng) {
    if bytes.is_empty() {
        bytes.push(0);
        return;
    }
    match rng.below(4) {
        0 => {
            let k = rng.below(bytes.len());
            bytes[k] ^= 1 << rng.below(8);
        }
        1 => {
            let k = rng.below(bytes.len());
            bytes.truncate(k);
        }
        2 => {
            // A little-endian u32 somewhere set to a huge count.
            let k = rng.below(bytes.len().saturating_sub(4).max(1));
            let v = [u32::MAX, 0x7fff_ffff, 0x1000_0000][rng.below(3)].to_le_bytes();
            for (i, b) in v.iter().enumerate() {
                if k + i < bytes.len() {
                    bytes[k + i] = *b;
                }
            }
        }
        _ => {
            let k = rng.below(bytes.len());
            let b = bytes[k];
            bytes.insert(k, b);
        }
    }
}

/// What a fuzz run saw.
#[derive(Debug, Default)]
pub struct FuzzReport {
    /// Inputs run.
    pub cases: usize,
    /// How many the target accepted (the rest it refused with an error).
    pub accepted: usize,
    /// The slowest input.
    pub slowest: Duration,
    /// Wall time in all.
    pub total: Duration,
}

/// How many cases per format: `FUZZ_CASES` when set, else `default`.
#[must_use]
pub fn cases(default: usize) -> usize {
    std::env::var("FUZZ_CASES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(default)
}

/// A fuzz target: how to mutate its inputs, how to run one, and how to
/// write one to a file when it fails.
pub struct Target<M, F, D> {
    /// The format's name, for messages and file names.
    pub format: &'static str,
    /// One mutation.
    pub mutate: M,
    /// Runs the input; true when it was accepted (false: refused with an
    /// error).
    pub run: F,
    /// The input as the bytes of a file.
    pub bytes: D,
}

/// Runs a target on `count` mutants of the seeds (1 to 4 mutations each,
/// case `i` from seed `base + i`). Panics, naming the case, when the target
/// panics or one input takes longer than `limit`; the failing input is
/// written to the temporary directory first (to keep it under the tests'
/// `fuzz/` folder as a regression).
pub fn run<T: Clone, M, F, D>(
    target: &Target<M, F, D>,
    seeds: &[T],
    count: usize,
    base: u64,
    limit: Duration,
) -> FuzzReport
where
    M: Fn(&mut T, &mut Rng),
    F: Fn(&T) -> bool,
    D: Fn(&T) -> Vec<u8>,
{
    let format = target.format;
    let start = Instant::now();
    let mut report = FuzzReport::default();
    for i in 0..count {
        let mut rng = Rng(base + i as u64);
        let mut input = seeds[rng.below(seeds.len())].clone();
        for _ in 0..=rng.below(4) {
            (target.mutate)(&mut input, &mut rng);
        }
        let t = Instant::now();
        let result = std::panic::catch_unwind(AssertUnwindSafe(|| (target.run)(&input)));
        let took = t.elapsed();
        let failed = match result {
            Ok(accepted) => {
                report.accepted += usize::from(accepted);
                (took > limit).then(|| format!("took {took:?}, more than {limit:?}"))
            }
            Err(_) => Some("panicked".to_string()),
        };
        if let Some(what) = failed {
            let seed = base + i as u64;
            let file = std::env::temp_dir().join(format!("fuzz-{}-{seed}", format.replace(' ', "-")));
            let _ = std::fs::write(&file, (target.bytes)(&input));
            panic!(
                "{format}: case {i} (seed {seed}) {what}; its input is in {}",
                file.display()
            );
        }
        report.slowest = report.slowest.max(took);
        report.cases += 1;
    }
    report.total = start.elapsed();
    eprintln!(
        "fuzz {format}: {} cases, {} accepted, slowest {:?}, {:?} in all, no panic, no hang",
        report.cases, report.accepted, report.slowest, report.total
    );
    report
}
