//! Benchmark of DNF construction (filled in with the DNF).

fn main() {}
