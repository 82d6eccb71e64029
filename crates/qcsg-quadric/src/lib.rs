//! Exact, numerically stable f64 quadric math (paper 000 §3).
