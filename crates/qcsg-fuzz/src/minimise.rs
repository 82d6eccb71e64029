//! Delta debugging: the smallest input (within a time budget) that still fails the same way.
//!
//! [`minimise`] removes chunks of lines, then chunks of bytes, as in Zeller's ddmin: it splits
//! the input into `n` chunks and keeps the first removal after which the failure still
//! reproduces (then tries coarser chunks again), doubling `n` when no removal does, until single
//! lines (bytes) cannot be removed or the deadline passes. "Reproduces" is the caller's
//! predicate; the supervisor asks for the same stage, kind and signature.

use std::time::Instant;

/// The units a phase removes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Unit {
    Line,
    Byte,
}

/// The smallest input found before `deadline` for which `still_fails` holds, starting from
/// `bytes` (for which it is assumed to hold).
pub fn minimise(
    bytes: &[u8],
    still_fails: &mut dyn FnMut(&[u8]) -> bool,
    deadline: Instant,
) -> Vec<u8> {
    let mut current = bytes.to_vec();
    for unit in [Unit::Line, Unit::Byte] {
        current = reduce(&current, unit, still_fails, deadline);
    }
    current
}

/// `bytes` split into units (lines keep their line end).
fn split(bytes: &[u8], unit: Unit) -> Vec<&[u8]> {
    match unit {
        Unit::Line => bytes.split_inclusive(|&b| b == b'\n').collect(),
        Unit::Byte => bytes.chunks(1).collect(),
    }
}

/// One ddmin phase over `unit`s.
fn reduce(
    bytes: &[u8],
    unit: Unit,
    still_fails: &mut dyn FnMut(&[u8]) -> bool,
    deadline: Instant,
) -> Vec<u8> {
    let mut pieces: Vec<Vec<u8>> = split(bytes, unit).into_iter().map(<[u8]>::to_vec).collect();
    let mut n = 2usize;
    while pieces.len() >= 2 && Instant::now() < deadline {
        let chunk = pieces.len().div_ceil(n);
        let mut reduced = false;
        let mut start = 0;
        while start < pieces.len() && Instant::now() < deadline {
            let end = (start + chunk).min(pieces.len());
            let candidate: Vec<u8> = pieces[..start]
                .iter()
                .chain(&pieces[end..])
                .flatten()
                .copied()
                .collect();
            if still_fails(&candidate) {
                pieces.drain(start..end);
                n = (n - 1).max(2);
                reduced = true;
                break;
            }
            start = end;
        }
        if !reduced {
            if n >= pieces.len() {
                break;
            }
            n = (n * 2).min(pieces.len());
        }
    }
    // A single unit left may still go (an empty input that fails).
    if pieces.len() == 1 && Instant::now() < deadline && still_fails(b"") {
        pieces.clear();
    }
    pieces.concat()
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use super::*;

    fn later() -> Instant {
        Instant::now() + Duration::from_secs(60)
    }

    #[test]
    fn a_nesting_blow_up_shrinks_to_its_core() {
        let mut text = String::from("x = 1;\ncube(2);\n");
        text.push_str(&"union(){".repeat(30));
        text.push_str("\nsphere(1);\necho(3);\n");
        // Fails while at least 20 `union(){` are nested.
        let mut runs = 0;
        let mut fails = |b: &[u8]| {
            runs += 1;
            String::from_utf8_lossy(b).matches("union(){").count() >= 20
        };
        let out = minimise(text.as_bytes(), &mut fails, later());
        assert_eq!(String::from_utf8_lossy(&out), "union(){".repeat(20));
        assert!(runs < 2000, "{runs} runs");
    }

    #[test]
    fn lines_not_needed_are_removed() {
        let text = "a\nb\nPANIC\nc\nd\ne\n";
        let mut fails = |b: &[u8]| b.windows(5).any(|w| w == b"PANIC");
        assert_eq!(minimise(text.as_bytes(), &mut fails, later()), b"PANIC");
    }

    #[test]
    fn a_passed_deadline_returns_the_input() {
        let text = b"abc\ndef\n";
        let mut fails = |_: &[u8]| true;
        assert_eq!(minimise(text, &mut fails, Instant::now()), text.to_vec());
    }
}
