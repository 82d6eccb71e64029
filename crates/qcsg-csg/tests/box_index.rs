//! The box index answers as walking every box would: the boxes near a box, and those a
//! monotone predicate (a ray's slab test) holds for, on random boxes with empty, flat and
//! unbounded ones among them.

use proptest::prelude::*;
use proptest::test_runner::{Config, RngSeed};
use qcsg_csg::{Aabb, BoxIndex};
use qcsg_quadric::DVec3;

/// A box from a corner, a size and a kind: 0 empty, 1 unbounded below on one axis, 2 flat,
/// else plain.
fn make_box((corner, size, kind): ([f64; 3], [f64; 3], u8)) -> Aabb {
    let min = DVec3::from_array(corner);
    let max = min + DVec3::from_array(size);
    match kind {
        0 => Aabb::EMPTY,
        1 => Aabb::new(DVec3::new(f64::NEG_INFINITY, min.y, min.z), max),
        2 => Aabb::new(min, DVec3::new(max.x, max.y, min.z)),
        _ => Aabb::new(min, max),
    }
}

fn boxes() -> impl Strategy<Value = Vec<Aabb>> {
    let one = (
        prop::array::uniform3(-20.0f64..20.0),
        prop::array::uniform3(0.0f64..4.0),
        0u8..12,
    );
    prop::collection::vec(one.prop_map(make_box), 0..120)
}

/// Whether the ray from `origin` along `direction` crosses `b` (the slab test, which holds for
/// every box containing one it holds for).
fn crosses(origin: DVec3, direction: DVec3, b: &Aabb) -> bool {
    if b.is_empty() {
        return false;
    }
    let (mut t_in, mut t_out) = (0.0f64, f64::INFINITY);
    for axis in 0..3 {
        let (o, d) = (origin[axis], direction[axis]);
        let (a, c) = ((b.min[axis] - o) / d, (b.max[axis] - o) / d);
        let (near, far) = if a <= c { (a, c) } else { (c, a) };
        t_in = t_in.max(near);
        t_out = t_out.min(far);
    }
    t_in <= t_out
}

proptest! {
    #![proptest_config(Config {
        cases: 500,
        rng_seed: RngSeed::Fixed(0x0b0c_5e1d),
        failure_persistence: None,
        ..Config::default()
    })]

    #[test]
    fn near_finds_what_walking_finds(
        boxes in boxes(),
        query in (prop::array::uniform3(-25.0f64..25.0), prop::array::uniform3(0.0f64..6.0)),
        margin in 0.0f64..8.0,
    ) {
        let index = BoxIndex::new(boxes.clone());
        let min = DVec3::from_array(query.0);
        let bounds = Aabb::new(min, min + DVec3::from_array(query.1));
        let walked: Vec<u32> = (0..boxes.len() as u32)
            .filter(|&i| bounds.gap(&boxes[i as usize]) <= margin)
            .collect();
        prop_assert_eq!(index.near(&bounds, margin), walked);
        prop_assert_eq!(index.near(&bounds, f64::INFINITY).len(), boxes.len());
    }

    #[test]
    fn select_finds_what_walking_finds(
        boxes in boxes(),
        origin in prop::array::uniform3(-30.0f64..30.0),
        direction in prop::array::uniform3(-1.0f64..1.0),
    ) {
        let index = BoxIndex::new(boxes.clone());
        let (origin, direction) = (DVec3::from_array(origin), DVec3::from_array(direction));
        let mut selected = Vec::new();
        index.select(|b| crosses(origin, direction, b), &mut selected);
        selected.sort_unstable();
        let walked: Vec<u32> = (0..boxes.len() as u32)
            .filter(|&i| crosses(origin, direction, &boxes[i as usize]))
            .collect();
        prop_assert_eq!(selected, walked);
    }
}

#[test]
fn gap_is_euclidean() {
    let a = Aabb::new(DVec3::ZERO, DVec3::ONE);
    let b = Aabb::new(DVec3::new(4.0, 5.0, 0.5), DVec3::splat(6.0));
    assert_eq!(a.gap(&b), 5.0);
    assert_eq!(b.gap(&a), 5.0);
    assert_eq!(a.gap(&a), 0.0);
    assert_eq!(a.gap(&Aabb::EMPTY), f64::INFINITY);
    assert_eq!(a.gap(&Aabb::EVERYTHING), 0.0);
}
