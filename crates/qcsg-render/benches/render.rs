//! Render time of the CPU ray tracer for scenes of about 3 and 30 quadrics.

fn main() {}
