//! The stable fuzz runner: the body of a cargo-fuzz target run over its seed inputs and then
//! over a deterministic, seeded stream of mutants of them, for a fixed number of iterations
//! (never a wall-clock budget), so `cargo test` exercises every fuzz target on the stable
//! toolchain and a failure reproduces exactly.
//!
//! Each mutant is a seed with one to four mutations stacked: a bit flip, a byte set to a
//! random or to a boundary value, random bytes inserted, a range deleted or duplicated, a
//! four-byte little-endian boundary integer written, the input truncated, a splice with
//! another seed (this one's head, the other's tail), a chunk of another seed inserted, or one
//! of the campaign's dictionary tokens inserted.
//!
//! When the body panics, the failing input is written to the temporary folder and its path
//! printed with the iteration, then the panic goes on (the test fails).
//!
//! ```
//! use test_support::fuzz::Campaign;
//! let mut longest = 0;
//! let report = Campaign::new("doc", vec![b"abc".to_vec()])
//!     .iterations(100)
//!     .run(|data| longest = longest.max(data.len()));
//! assert_eq!((report.seeds, report.mutants), (1, 100));
//! assert!(longest > 3);
//! ```

use std::panic::{AssertUnwindSafe, catch_unwind, resume_unwind};

/// Byte values at the edges of common encodings and at MOOS syntax characters.
const BYTES: &[u8] = &[
    0x00, 0x01, 0x7f, 0x80, 0xff, b'\n', b'\r', b'\t', b' ', b'=', b',', b':', b'{', b'}', b'(',
    b')', b'$', b'%', b'#', b'/', b'"', b'\\',
];

/// Little-endian 32-bit values at the edges of lengths and counts.
const INTS: &[i32] = &[0, 1, -1, 8, 9, 255, 256, 1 << 16, i32::MAX, i32::MIN];

/// A bounded, deterministic fuzz campaign: seeds, an optional dictionary, a number of
/// mutants and the random seed they come from.
#[derive(Debug, Clone)]
pub struct Campaign {
    name: String,
    seeds: Vec<Vec<u8>>,
    tokens: Vec<Vec<u8>>,
    iterations: usize,
    rng_seed: u64,
    max_len: usize,
}

/// What a finished campaign ran.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Report {
    /// Seed inputs run as they are.
    pub seeds: usize,
    /// Mutants run.
    pub mutants: usize,
    /// Mutants that differed from the seed they were made from.
    pub changed: usize,
}

impl Campaign {
    /// A campaign named `name` (used in failure reports) over `seeds`, with 1000 mutants from
    /// the random seed 0x5eed by default. With no seeds, mutants grow from the empty input.
    pub fn new(name: &str, seeds: Vec<Vec<u8>>) -> Self {
        Campaign {
            name: name.to_string(),
            seeds,
            tokens: Vec::new(),
            iterations: 1000,
            rng_seed: 0x5eed,
            max_len: 1 << 16,
        }
    }

    /// Tokens the mutator may insert (keywords of the input's syntax).
    pub fn tokens(mut self, tokens: &[&str]) -> Self {
        self.tokens = tokens.iter().map(|t| t.as_bytes().to_vec()).collect();
        self
    }

    /// How many mutants to run after the seeds.
    pub fn iterations(mut self, n: usize) -> Self {
        self.iterations = n;
        self
    }

    /// The random seed of the mutant stream (the same seed gives the same mutants).
    pub fn rng_seed(mut self, seed: u64) -> Self {
        self.rng_seed = seed;
        self
    }

    /// The longest mutant (longer ones are cut), 64 KiB by default.
    pub fn max_len(mut self, n: usize) -> Self {
        self.max_len = n.max(1);
        self
    }

    /// Runs `body` on every seed, then on each mutant in turn.
    pub fn run(self, mut body: impl FnMut(&[u8])) -> Report {
        for (i, s) in self.seeds.iter().enumerate() {
            self.guarded(&mut body, s, &format!("seed {i}"));
        }
        let mut rng = fastrand::Rng::with_seed(self.rng_seed);
        let mut input = Vec::new();
        let mut changed = 0;
        for i in 0..self.iterations {
            let from = if self.seeds.is_empty() {
                None
            } else {
                Some(rng.usize(..self.seeds.len()))
            };
            input.clear();
            if let Some(k) = from {
                input.extend_from_slice(&self.seeds[k]);
            }
            for _ in 0..rng.usize(1..=4) {
                self.mutate(&mut rng, &mut input);
            }
            input.truncate(self.max_len);
            changed += usize::from(from.is_none_or(|k| self.seeds[k] != input));
            self.guarded(&mut body, &input, &format!("mutant {i}"));
        }
        Report {
            seeds: self.seeds.len(),
            mutants: self.iterations,
            changed,
        }
    }

    fn guarded(&self, body: &mut impl FnMut(&[u8]), input: &[u8], what: &str) {
        if let Err(panic) = catch_unwind(AssertUnwindSafe(|| body(input))) {
            let path = std::env::temp_dir().join(format!(
                "coug-fuzz-{}-{}.crash",
                self.name,
                std::process::id()
            ));
            let saved = match std::fs::write(&path, input) {
                Ok(()) => format!("saved to {}", path.display()),
                Err(e) => format!("not saved ({e})"),
            };
            eprintln!(
                "fuzz {}: {what} (random seed {:#x}) panicked; the {}-byte input is {saved}",
                self.name,
                self.rng_seed,
                input.len()
            );
            resume_unwind(panic);
        }
    }

    /// Applies one random mutation to `data`.
    fn mutate(&self, rng: &mut fastrand::Rng, data: &mut Vec<u8>) {
        let other = |rng: &mut fastrand::Rng| -> &[u8] {
            if self.seeds.is_empty() {
                &[]
            } else {
                &self.seeds[rng.usize(..self.seeds.len())]
            }
        };
        let len = data.len();
        match rng.u8(..11) {
            0 if len > 0 => {
                let i = rng.usize(..len);
                data[i] ^= 1 << rng.u8(..8);
            }
            1 if len > 0 => {
                let i = rng.usize(..len);
                data[i] = rng.u8(..);
            }
            2 if len > 0 => {
                let i = rng.usize(..len);
                data[i] = BYTES[rng.usize(..BYTES.len())];
            }
            3 if len > 0 => {
                let at = rng.usize(..len);
                let n = rng.usize(1..=(len - at).min(64));
                data.drain(at..at + n);
            }
            4 if len > 0 => {
                let at = rng.usize(..len);
                let n = rng.usize(1..=(len - at).min(64));
                let chunk = data[at..at + n].to_vec();
                let to = rng.usize(..=len);
                data.splice(to..to, chunk);
            }
            5 if len >= 4 => {
                let at = rng.usize(..=len - 4);
                let v = INTS[rng.usize(..INTS.len())];
                data[at..at + 4].copy_from_slice(&v.to_le_bytes());
            }
            6 if len > 0 => data.truncate(rng.usize(..len)),
            7 => {
                let o = other(rng);
                let head = rng.usize(..=len);
                let tail = rng.usize(..=o.len());
                data.truncate(head);
                data.extend_from_slice(&o[tail..]);
            }
            8 => {
                let o = other(rng);
                if !o.is_empty() {
                    let at = rng.usize(..o.len());
                    let n = rng.usize(1..=(o.len() - at).min(256));
                    let to = rng.usize(..=len);
                    data.splice(to..to, o[at..at + n].iter().copied());
                }
            }
            9 if !self.tokens.is_empty() => {
                let t = &self.tokens[rng.usize(..self.tokens.len())];
                let to = rng.usize(..=len);
                data.splice(to..to, t.iter().copied());
            }
            _ => {
                let to = rng.usize(..=len);
                let n = rng.usize(1..=8);
                data.splice(to..to, std::iter::repeat_with(|| rng.u8(..)).take(n));
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn inputs(c: Campaign) -> Vec<Vec<u8>> {
        let mut v = Vec::new();
        c.run(|d| v.push(d.to_vec()));
        v
    }

    #[test]
    fn the_same_random_seed_gives_the_same_mutants_and_another_differs() {
        let seeds = vec![b"ProcessConfig = a\n{\n x = 1\n}\n".to_vec(), vec![0u8; 40]];
        let c = Campaign::new("t", seeds).tokens(&["$(", "#include"]);
        let a = inputs(c.clone().iterations(300));
        assert_eq!(a.len(), 302);
        assert_eq!(a, inputs(c.clone().iterations(300)));
        assert_ne!(a, inputs(c.iterations(300).rng_seed(7)));
    }

    #[test]
    fn mutants_change_the_seeds_and_respect_the_length_cap() {
        let seeds = vec![vec![b'a'; 100]];
        let mut lens = Vec::new();
        let r = Campaign::new("t", seeds.clone())
            .max_len(120)
            .iterations(500)
            .run(|d| lens.push(d.len()));
        assert_eq!((r.seeds, r.mutants), (1, 500));
        assert!(r.changed > 450, "{r:?}");
        assert!(lens.iter().all(|&n| n <= 120));
        assert!(lens.iter().any(|&n| n < 100) && lens.iter().any(|&n| n > 100));
    }

    #[test]
    fn tokens_are_inserted() {
        let all = inputs(
            Campaign::new("t", vec![b"abc".to_vec()])
                .tokens(&["#ifdef"])
                .iterations(200),
        );
        assert!(all.iter().any(|d| d.windows(6).any(|w| w == b"#ifdef")));
    }

    #[test]
    fn a_panicking_body_fails_the_campaign() {
        let r = catch_unwind(|| {
            Campaign::new("panics", vec![b"x".to_vec()])
                .iterations(50)
                .run(|d| assert!(d.len() < 3, "too long"));
        });
        assert!(r.is_err());
        let saved =
            std::env::temp_dir().join(format!("coug-fuzz-panics-{}.crash", std::process::id()));
        assert!(std::fs::read(&saved).unwrap().len() >= 3);
        std::fs::remove_file(saved).unwrap();
    }
}
