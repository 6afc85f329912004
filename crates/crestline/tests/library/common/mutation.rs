//! Mutation fuzzing helpers shared by the reader fuzz tests: a seeded random
//! generator, generic byte mutations of a file and the checks of an error message.
//!
//! A module of the library's tests' `common`, and included by path from the image
//! fuzz test of the command-line tool, so that both mutate files the same way.

// Each user takes what it needs: the mesh test checks messages with
// `message_problem`, the tool's test its own way (path or file name).
#![allow(dead_code)]

use std::path::Path;

// ---------------------------------------------------------------------------
// Random numbers

/// SplitMix64: a tiny, good-enough generator, reproducible from its seed.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// A number in `0..n` (`n` > 0).
    pub fn below(&mut self, n: usize) -> usize {
        (self.next() % n as u64) as usize
    }

    pub fn pick<'a, T>(&mut self, items: &'a [T]) -> &'a T {
        &items[self.below(items.len())]
    }
}

// ---------------------------------------------------------------------------
// Byte mutations

pub const INTERESTING_BYTES: &[u8] = &[
    0, 0xff, b'-', b'9', b'e', b'\n', b' ', b'.', b'#', b'/', 0x7f, 0x80, 0x07, 0x1b,
];
/// Numbers to write over a number of a text file: zero, negative, at the limits of
/// the integer types, beyond every one of them, and not finite.
pub const HUGE_NUMBERS: &[&str] = &[
    "0",
    "-1",
    "2147483648",
    "4294967295",
    "4294967296",
    "1000000000000000",
    "4611686018427387904",
    "18446744073709551615",
    "99999999999999999999999",
    "1e308",
    "nan",
];
/// 32-bit words to write over four bytes of a binary file.
pub const INTERESTING_WORDS: &[u32] = &[
    0,
    1,
    2,
    3,
    0x7f,
    0xff,
    0x100,
    0xffff,
    0x7fff_ffff,
    0x8000_0000,
    0xffff_ffff,
    0x4000_0000,
    0x7f80_0000, // +inf as f32
    0x7fc0_0000, // NaN as f32
];

/// The mutations, each applied to a file's bytes.
#[derive(Clone, Copy, Debug)]
pub enum Mutation {
    BitFlip,
    InterestingByte,
    Truncate,
    DuplicateChunk,
    DeleteChunk,
    SwapNumbers,
    SwapWords,
    HugeNumber,
    HugeWord,
}

pub const MUTATIONS: &[Mutation] = &[
    Mutation::BitFlip,
    Mutation::InterestingByte,
    Mutation::Truncate,
    Mutation::DuplicateChunk,
    Mutation::DeleteChunk,
    Mutation::SwapNumbers,
    Mutation::SwapWords,
    Mutation::HugeNumber,
    Mutation::HugeWord,
];

impl Mutation {
    pub fn apply(self, bytes: &mut Vec<u8>, rng: &mut Rng) {
        if bytes.is_empty() {
            return;
        }
        let at = rng.below(bytes.len());
        match self {
            Mutation::BitFlip => bytes[at] ^= 1 << rng.below(8),
            Mutation::InterestingByte => bytes[at] = *rng.pick(INTERESTING_BYTES),
            Mutation::Truncate => bytes.truncate(at),
            Mutation::DuplicateChunk => {
                let chunk = bytes[at..chunk_end(bytes, at, rng)].to_vec();
                let to = rng.below(bytes.len() + 1);
                bytes.splice(to..to, chunk);
            }
            Mutation::DeleteChunk => {
                let end = chunk_end(bytes, at, rng);
                bytes.drain(at..end);
            }
            Mutation::SwapNumbers => swap_numbers(bytes, rng),
            Mutation::SwapWords => swap_words(bytes, rng),
            Mutation::HugeNumber => huge_number(bytes, rng),
            Mutation::HugeWord => huge_word(bytes, rng),
        }
    }
}

/// The end of a chunk of up to 64 bytes starting at `start`.
fn chunk_end(bytes: &[u8], start: usize, rng: &mut Rng) -> usize {
    (start + 1 + rng.below(64)).min(bytes.len())
}

/// The byte ranges of the runs of ASCII digits.
pub fn digit_runs(bytes: &[u8]) -> Vec<(usize, usize)> {
    let mut runs = Vec::new();
    let mut start = None;
    for (i, b) in bytes.iter().chain([&b' ']).enumerate() {
        match (b.is_ascii_digit(), start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                runs.push((s, i));
                start = None;
            }
            _ => {}
        }
    }
    runs
}

/// A digit run, often one of the first (where the counts of a header are).
pub fn pick_run(runs: &[(usize, usize)], rng: &mut Rng) -> (usize, usize) {
    let early = runs.len().min(6);
    if rng.below(2) == 0 {
        runs[rng.below(early)]
    } else {
        *rng.pick(runs)
    }
}

fn swap_numbers(bytes: &mut Vec<u8>, rng: &mut Rng) {
    let runs = digit_runs(bytes);
    if runs.len() < 2 {
        return;
    }
    let (a, b) = (pick_run(&runs, rng), *rng.pick(&runs));
    let (first, second) = if a.0 <= b.0 { (a, b) } else { (b, a) };
    if first == second {
        return;
    }
    let mut out = bytes[..first.0].to_vec();
    out.extend(&bytes[second.0..second.1]);
    out.extend(&bytes[first.1..second.0]);
    out.extend(&bytes[first.0..first.1]);
    out.extend(&bytes[second.1..]);
    *bytes = out;
}

fn swap_words(bytes: &mut [u8], rng: &mut Rng) {
    if bytes.len() < 8 {
        return;
    }
    let (a, b) = (rng.below(bytes.len() - 3), rng.below(bytes.len() - 3));
    let (wa, wb) = (bytes[a..a + 4].to_vec(), bytes[b..b + 4].to_vec());
    bytes[a..a + 4].copy_from_slice(&wb);
    bytes[b..b + 4].copy_from_slice(&wa);
}

fn huge_number(bytes: &mut Vec<u8>, rng: &mut Rng) {
    let runs = digit_runs(bytes);
    if runs.is_empty() {
        return;
    }
    let (start, end) = pick_run(&runs, rng);
    bytes.splice(start..end, rng.pick(HUGE_NUMBERS).bytes());
}

fn huge_word(bytes: &mut [u8], rng: &mut Rng) {
    if bytes.len() < 4 {
        return;
    }
    let at = rng.below(bytes.len() - 3);
    let word = *rng.pick(INTERESTING_WORDS);
    let raw = if rng.below(2) == 0 {
        word.to_le_bytes()
    } else {
        word.to_be_bytes()
    };
    bytes[at..at + 4].copy_from_slice(&raw);
}

/// A mutant of `seed`: one to three mutations; returns their names.
pub fn mutate(seed: &[u8], rng: &mut Rng) -> (Vec<u8>, Vec<Mutation>) {
    let mut bytes = seed.to_vec();
    let applied: Vec<Mutation> = (0..1 + rng.below(3))
        .map(|_| *rng.pick(MUTATIONS))
        .collect();
    for mutation in &applied {
        mutation.apply(&mut bytes, rng);
    }
    (bytes, applied)
}

// ---------------------------------------------------------------------------
// Error messages

/// Text that only Rust's debug formatting would put in a message: a struct or
/// an `Option` printed with `{:?}`, an I/O error's debug form, or a string's
/// debug escape of a control character (the library writes `\x1b`).
pub const DEBUG_TEXT: &[&str] = &["{ ", "kind:", "Some(", "Os {", "\\u{", "PropertyDef"];

/// What is wrong with an error message about the input `path`, if anything: it
/// must name the file, stay on one line (no control characters) and hold no
/// debug text outside the input it quotes.
pub fn message_problem(message: &str, path: &Path) -> Option<String> {
    if !message.contains(&path.display().to_string()) {
        return Some("does not name the file".to_string());
    }
    text_problem(message)
}

/// What is wrong with the text of a message, if anything: a control character
/// (it must stay on one line) or debug text outside the input it quotes.
pub fn text_problem(message: &str) -> Option<String> {
    if message.chars().any(char::is_control) {
        return Some("contains a control character".to_string());
    }
    debug_text(message).map(|text| format!("contains debug text '{text}'"))
}

/// The first of [`DEBUG_TEXT`] in `message` outside the input it quotes.
pub fn debug_text(message: &str) -> Option<&'static str> {
    let unquoted = without_quoted_input(message);
    DEBUG_TEXT
        .iter()
        .find(|text| unquoted.contains(*text))
        .copied()
}

/// `message` without the input text it quotes between single quotes (which may
/// hold anything a mutant contains).
pub fn without_quoted_input(message: &str) -> String {
    message
        .split('\'')
        .step_by(2)
        .collect::<Vec<_>>()
        .join("''")
}

/// The number in the environment variable `name`, if it is set to one (as
/// `CRESTLINE_FUZZ_MUTANTS` and `CRESTLINE_FUZZ_SEED`).
pub fn env_number(name: &str) -> Option<u64> {
    std::env::var(name).ok().and_then(|v| v.trim().parse().ok())
}
