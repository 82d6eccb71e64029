//! The `qcsg` command line (CLI.md).

fn main() {}
