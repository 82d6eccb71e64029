//! `hull()` of balls of different radii with cubes, checked against an independent hull: the
//! support function of the balls and corners sampled in many directions (`support`), with the
//! sampling error bounded, beside the membership certificates of `hull_balls.rs`.

mod common;
mod support;

use glam::{DMat4, DVec3};
use qcsg_testkit::Rng;
use support::Convex;

#[test]
fn random_balls_and_cubes_match_the_sampled_hull() {
    let mut rng = Rng::new(390);
    let (mut inside, mut outside) = (0, 0);
    for case in 0..6 {
        let mut text = String::from("hull() {");
        let mut set = Convex::default();
        for _ in 0..2 + case % 4 {
            let c = rng.in_box(DVec3::splat(-4.0), DVec3::splat(4.0));
            let r = rng.range(0.2, 2.0);
            text += &format!(
                " translate([{:e}, {:e}, {:e}]) sphere({:e});",
                c.x, c.y, c.z, r
            );
            set.balls.push((c, r));
        }
        if case % 2 == 1 {
            let at = rng.in_box(DVec3::splat(-4.0), DVec3::splat(4.0));
            let size = rng.range(0.5, 2.0);
            text += &format!(
                " translate([{:e}, {:e}, {:e}]) cube({:e});",
                at.x, at.y, at.z, size
            );
            for k in 0..8 {
                let corner = DVec3::new(
                    f64::from(k & 1),
                    f64::from((k >> 1) & 1),
                    f64::from((k >> 2) & 1),
                );
                set.discs.push((at + size * corner, 0.0));
            }
        }
        text += " }";
        let (i, o) = support::compare(&text, &[set], DMat4::IDENTITY, &mut rng);
        inside += i;
        outside += o;
    }
    assert!(
        inside > 120 && outside > 120,
        "{inside} inside, {outside} outside"
    );
}
