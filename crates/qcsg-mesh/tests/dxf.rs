//! The DXF reader on small drawings written here (each entity kind, blocks, layers, joining,
//! errors, far and tiny coordinates) and on OpenSCAD's bundled example drawings.

use glam::DVec2;
use qcsg_mesh::{Drawing, DrawingLimits, DrawingOptions, DrawingWarning, ReadError, read_dxf};

/// A DXF file with `entities` in its ENTITIES section and `blocks` in its BLOCKS section, each a
/// list of `(code, value)` pairs.
fn dxf(blocks: &[(i32, &str)], entities: &[(i32, &str)]) -> String {
    let mut text = String::new();
    let mut pair = |c: i32, v: &str| text.push_str(&format!("  {c}\n{v}\n"));
    pair(0, "SECTION");
    pair(2, "HEADER");
    pair(9, "$EXTMIN");
    pair(10, "0.0");
    pair(0, "ENDSEC");
    pair(0, "SECTION");
    pair(2, "BLOCKS");
    for &(c, v) in blocks {
        pair(c, v);
    }
    pair(0, "ENDSEC");
    pair(0, "SECTION");
    pair(2, "ENTITIES");
    for &(c, v) in entities {
        pair(c, v);
    }
    pair(0, "ENDSEC");
    pair(0, "EOF");
    text
}

fn line(layer: &str, a: [f64; 2], b: [f64; 2]) -> Vec<(i32, String)> {
    vec![
        (0, "LINE".into()),
        (8, layer.into()),
        (10, a[0].to_string()),
        (20, a[1].to_string()),
        (11, b[0].to_string()),
        (21, b[1].to_string()),
    ]
}

fn square(layer: &str, lo: f64, hi: f64) -> Vec<(i32, String)> {
    let c = [[lo, lo], [hi, lo], [hi, hi], [lo, hi]];
    (0..4)
        .flat_map(|i| line(layer, c[i], c[(i + 1) % 4]))
        .collect()
}

fn read(text: &str, options: &DrawingOptions) -> Result<Drawing, ReadError> {
    read_dxf(text.as_bytes(), options, &DrawingLimits::default())
}

fn pairs(v: &[(i32, String)]) -> Vec<(i32, &str)> {
    v.iter().map(|(c, s)| (*c, s.as_str())).collect()
}

fn all() -> DrawingOptions {
    DrawingOptions::default()
}

fn layer(name: &str) -> DrawingOptions {
    DrawingOptions {
        layer: Some(name.into()),
        ..DrawingOptions::default()
    }
}

/// The vertices of a path in order.
fn corners(d: &Drawing, path: usize) -> Vec<DVec2> {
    d.paths[path].edges.iter().map(|e| e.from).collect()
}

#[test]
fn lines_in_any_order_join_into_one_closed_path() {
    let mut entities = square("0", 0.0, 10.0);
    // Reverse one line and move another to the end: joining follows end points, not file order.
    entities[6..12].swap(1, 1);
    let mut lines: Vec<_> = entities.chunks(6).map(|c| c.to_vec()).collect();
    lines.swap(0, 3);
    let l = &mut lines[1];
    let (a, b) = (
        (l[2].1.clone(), l[3].1.clone()),
        (l[4].1.clone(), l[5].1.clone()),
    );
    (l[2].1, l[3].1, l[4].1, l[5].1) = (b.0, b.1, a.0, a.1);
    let entities: Vec<_> = lines.concat();
    let d = read(&dxf(&[], &pairs(&entities)), &all()).unwrap();
    assert_eq!(d.paths.len(), 1);
    assert!(d.paths[0].closed_in_file);
    assert_eq!(d.paths[0].edges.len(), 4);
    assert!(d.warnings.is_empty(), "{:?}", d.warnings);
    for w in d.paths[0].edges.windows(2) {
        assert_eq!(w[0].to, w[1].from);
    }
}

#[test]
fn end_points_within_the_grid_tolerance_join_exactly() {
    let mut e = line("0", [0.0, 0.0], [100.0, 0.0]);
    e.extend(line("0", [100.0002, 0.0003], [100.0, 100.0]));
    e.extend(line("0", [100.0, 100.0], [0.0, 0.0001]));
    let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
    assert_eq!(d.paths.len(), 1);
    assert!(d.paths[0].closed_in_file);
    // The second line starts exactly where the first ends.
    assert_eq!(corners(&d, 0)[1], DVec2::new(100.0, 0.0));
}

#[test]
fn an_open_chain_is_closed_with_a_warning() {
    let mut e = line("0", [0.0, 0.0], [10.0, 0.0]);
    e.extend(line("0", [10.0, 0.0], [10.0, 10.0]));
    let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
    assert_eq!(d.paths.len(), 1);
    assert!(!d.paths[0].closed_in_file);
    assert_eq!(d.paths[0].edges.len(), 3);
    assert!(matches!(d.warnings[..], [DrawingWarning::OpenPath { .. }]));
}

#[test]
fn lwpolyline_and_polyline_closed_by_their_flag() {
    let lw = [
        (0, "LWPOLYLINE"),
        (8, "0"),
        (90, "3"),
        (70, "1"),
        (10, "0"),
        (20, "0"),
        (10, "4"),
        (20, "0"),
        (42, "0.5"),
        (10, "0"),
        (20, "3"),
    ];
    let d = read(&dxf(&[], &lw), &all()).unwrap();
    assert_eq!(d.paths.len(), 1);
    assert!(d.paths[0].closed_in_file);
    // The bulge belongs to the vertex it follows, (4, 0): the edge from there to (0, 3) is an
    // arc, the others straight.
    let arcs: Vec<_> = d.paths[0]
        .edges
        .iter()
        .filter(|e| e.arc.is_some())
        .collect();
    assert_eq!(arcs.len(), 1);
    let ends = [arcs[0].from, arcs[0].to];
    assert!(ends.contains(&DVec2::new(4.0, 0.0)) && ends.contains(&DVec2::new(0.0, 3.0)));
    let mut open = lw.to_vec();
    open[3] = (70, "0");
    let d = read(&dxf(&[], &open), &all()).unwrap();
    assert!(!d.paths[0].closed_in_file);
    let poly = [
        (0, "POLYLINE"),
        (8, "0"),
        (66, "1"),
        (70, "1"),
        (0, "VERTEX"),
        (10, "0"),
        (20, "0"),
        (0, "VERTEX"),
        (10, "5"),
        (20, "0"),
        (0, "VERTEX"),
        (10, "5"),
        (20, "5"),
        (0, "SEQEND"),
    ];
    let d = read(&dxf(&[], &poly), &all()).unwrap();
    assert_eq!(d.paths.len(), 1);
    assert!(d.paths[0].closed_in_file);
    assert_eq!(d.paths[0].edges.len(), 3);
    assert!(d.warnings.is_empty(), "{:?}", d.warnings);
}

#[test]
fn circles_and_arcs_stay_exact() {
    let e = [
        (0, "CIRCLE"),
        (8, "0"),
        (10, "1"),
        (20, "2"),
        (40, "3"),
        // A quarter arc from (10, 0) to (0, 10) about the origin, closed by two lines.
        (0, "ARC"),
        (8, "0"),
        (10, "0"),
        (20, "0"),
        (40, "10"),
        (50, "0"),
        (51, "90"),
        (0, "LINE"),
        (8, "0"),
        (10, "0"),
        (20, "10"),
        (11, "0"),
        (21, "0"),
        (0, "LINE"),
        (8, "0"),
        (10, "0"),
        (20, "0"),
        (11, "10"),
        (21, "0"),
        // An ARC of a full turn is a circle; one of no sweep is nothing.
        (0, "ARC"),
        (10, "50"),
        (20, "0"),
        (40, "1"),
        (50, "30"),
        (51, "390"),
        (0, "ARC"),
        (10, "60"),
        (20, "0"),
        (40, "1"),
        (50, "30"),
        (51, "30"),
    ];
    let d = read(&dxf(&[], &e), &all()).unwrap();
    assert_eq!(d.circles.len(), 2);
    assert_eq!(d.circles[0].center, DVec2::new(1.0, 2.0));
    assert_eq!(d.circles[0].radius, 3.0);
    assert_eq!(d.paths.len(), 1);
    let path = &d.paths[0];
    assert!(path.closed_in_file);
    let arc_edge = path.edges.iter().find(|e| e.arc.is_some()).unwrap();
    let arc = arc_edge.arc.unwrap();
    assert_eq!((arc.center, arc.radius), (DVec2::ZERO, 10.0));
    // The arc's end points are exact at multiples of 90°.
    let ends = [arc_edge.from, arc_edge.to];
    assert!(ends.contains(&DVec2::new(10.0, 0.0)) && ends.contains(&DVec2::new(0.0, 10.0)));
    // Its midpoint is on the circle, away from the origin.
    let mid = arc.midpoint(arc_edge.from, arc_edge.to);
    assert!((mid - DVec2::splat(10.0 / 2f64.sqrt())).length() < 1e-12);
}

#[test]
fn layers_select_and_no_layer_reads_all() {
    let mut e = square("a", 0.0, 1.0);
    e.extend(square("b", 2.0, 3.0));
    let text = dxf(&[], &pairs(&e));
    assert_eq!(read(&text, &all()).unwrap().paths.len(), 2);
    assert_eq!(read(&text, &layer("")).unwrap().paths.len(), 2);
    let b = read(&text, &layer("b")).unwrap();
    assert_eq!(b.paths.len(), 1);
    assert_eq!(corners(&b, 0)[0], DVec2::new(2.0, 2.0));
    assert!(read(&text, &layer("c")).unwrap().paths.is_empty());
}

#[test]
fn origin_and_scale_apply_as_openscad_applies_them() {
    let e = square("0", 10.0, 12.0);
    let options = DrawingOptions {
        layer: None,
        origin: DVec2::new(10.0, 10.0),
        scale: 3.0,
    };
    let d = read(&dxf(&[], &pairs(&e)), &options).unwrap();
    let c = corners(&d, 0);
    assert_eq!(c[0], DVec2::ZERO);
    assert!(c.contains(&DVec2::new(6.0, 6.0)));
}

/// A block `name` holding the unit square's four lines.
fn square_block(name: &str) -> Vec<(i32, String)> {
    let mut b = vec![(0, "BLOCK".to_string()), (8, "0".into()), (2, name.into())];
    b.extend(square("0", 0.0, 1.0));
    b.push((0, "ENDBLK".into()));
    b
}

fn insert(block: &str, at: [f64; 2], scale: [f64; 2], rotation: f64) -> Vec<(i32, String)> {
    vec![
        (0, "INSERT".into()),
        (8, "0".into()),
        (2, block.into()),
        (10, at[0].to_string()),
        (20, at[1].to_string()),
        (41, scale[0].to_string()),
        (42, scale[1].to_string()),
        (50, rotation.to_string()),
    ]
}

#[test]
fn insert_maps_a_block_by_scale_rotation_and_point() {
    let blocks = square_block("sq");
    let e = insert("sq", [5.0, 5.0], [2.0, 3.0], 90.0);
    let d = read(&dxf(&pairs(&blocks), &pairs(&e)), &all()).unwrap();
    assert_eq!(d.paths.len(), 1);
    let c = corners(&d, 0);
    // (1, 1) → diag(2, 3) → (2, 3) → rotated 90° → (−3, 2) → + (5, 5).
    for expected in [[5.0, 5.0], [5.0, 7.0], [2.0, 7.0], [2.0, 5.0]] {
        assert!(c.contains(&DVec2::from_array(expected)), "{c:?}");
    }
    // The import scale applies to the inserted block too.
    let options = DrawingOptions {
        scale: 2.0,
        ..DrawingOptions::default()
    };
    let d = read(&dxf(&pairs(&blocks), &pairs(&e)), &options).unwrap();
    assert!(corners(&d, 0).contains(&DVec2::new(4.0, 14.0)));
}

#[test]
fn nested_blocks_expand_and_a_cycle_is_an_error() {
    let mut blocks = square_block("sq");
    blocks.extend([(0, "BLOCK".into()), (2, "two".into())]);
    blocks.extend(insert("sq", [0.0, 0.0], [1.0, 1.0], 0.0));
    blocks.extend(insert("sq", [5.0, 0.0], [1.0, 1.0], 0.0));
    blocks.push((0, "ENDBLK".into()));
    let e = insert("two", [0.0, 10.0], [1.0, 1.0], 0.0);
    let d = read(&dxf(&pairs(&blocks), &pairs(&e)), &all()).unwrap();
    assert_eq!(d.paths.len(), 2);

    let mut cyclic = vec![(0, "BLOCK".to_string()), (2, "a".into())];
    cyclic.extend(insert("b", [0.0, 0.0], [1.0, 1.0], 0.0));
    cyclic.extend([(0, "ENDBLK".into()), (0, "BLOCK".into()), (2, "b".into())]);
    cyclic.extend(insert("a", [0.0, 0.0], [1.0, 1.0], 0.0));
    cyclic.push((0, "ENDBLK".into()));
    let e = insert("a", [0.0, 0.0], [1.0, 1.0], 0.0);
    let error = read(&dxf(&pairs(&cyclic), &pairs(&e)), &all()).unwrap_err();
    assert!(error.message.contains("inside itself"), "{error}");
    assert!(error.location.starts_with("line "), "{error}");
}

#[test]
fn a_block_circle_scaled_unevenly_is_an_ellipse() {
    let blocks = [
        (0, "BLOCK"),
        (2, "c"),
        (0, "CIRCLE"),
        (10, "0"),
        (20, "0"),
        (40, "1"),
        (0, "ENDBLK"),
    ];
    let e = insert("c", [0.0, 0.0], [2.0, 1.0], 0.0);
    let d = read(&dxf(&blocks, &pairs(&e)), &all()).unwrap();
    assert!(d.circles.is_empty() && d.curves.is_empty());
    assert_eq!(d.ellipses.len(), 1);
    assert_eq!(
        d.ellipses[0].axes,
        [DVec2::new(2.0, 0.0), DVec2::new(0.0, 1.0)]
    );
    // A zero scale flattens it: kept aside, as no region.
    let e = insert("c", [0.0, 0.0], [0.0, 1.0], 0.0);
    let d = read(&dxf(&blocks, &pairs(&e)), &all()).unwrap();
    assert_eq!(d.curves.len(), 1);
    let e = insert("c", [1.0, 0.0], [-2.0, 2.0], 30.0);
    let d = read(&dxf(&blocks, &pairs(&e)), &all()).unwrap();
    assert_eq!(d.circles[0].radius, 2.0);
    assert_eq!(d.circles[0].center, DVec2::new(1.0, 0.0));
}

#[test]
fn unsupported_entities_are_skipped_with_a_warning() {
    let mut e = vec![
        (0, "SPLINE".to_string()),
        (8, "0".into()),
        (0, "SPLINE".into()),
        (8, "0".into()),
        (0, "TEXT".into()),
        (8, "other".into()),
    ];
    e.extend(square("0", 0.0, 1.0));
    let d = read(&dxf(&[], &pairs(&e)), &layer("0")).unwrap();
    assert_eq!(d.paths.len(), 1);
    assert_eq!(d.warnings.len(), 1);
    assert!(matches!(
        &d.warnings[0],
        DrawingWarning::Unsupported { entity, count: 2, .. } if entity == "SPLINE"
    ));
}

#[test]
fn malformed_files_are_errors_at_their_line() {
    let cases: [(&str, &str); 6] = [
        ("  0\nSECTION\nX\nENTITIES\n", "line 3"),
        (
            "  0\nSECTION\n  2\nENTITIES\n  0\nLINE\n 10\n1,5\n",
            "line 8",
        ),
        (
            "  0\nSECTION\n  2\nENTITIES\n  0\nLINE\n 10\n1\n 20\n1\n  0\nENDSEC\n",
            "line 5",
        ),
        (
            "  0\nSECTION\n  2\nENTITIES\n  0\nLWPOLYLINE\n 10\n1\n 10\n2\n 20\n1\n  0\nENDSEC\n",
            "line 5",
        ),
        (
            "  0\nSECTION\n  2\nENTITIES\n  0\nCIRCLE\n 40\nnan\n",
            "line 8",
        ),
        ("  0\nSECTION\n  2\nENTITIES\n  0\n", "line 5"),
    ];
    for (text, location) in cases {
        let error = read(text, &all()).unwrap_err();
        assert_eq!(error.format, "DXF");
        assert_eq!(error.location, location, "{text:?}: {error}");
    }
    let error = read_dxf(
        b"AutoCAD Binary DXF\r\n\x1a\0",
        &all(),
        &DrawingLimits::default(),
    )
    .unwrap_err();
    assert!(error.message.contains("binary"));
}

#[test]
fn limits_on_entities_and_points() {
    let e = square("0", 0.0, 1.0);
    let text = dxf(&[], &pairs(&e));
    let few = DrawingLimits {
        max_entities: 3,
        ..DrawingLimits::default()
    };
    let error = read_dxf(text.as_bytes(), &all(), &few).unwrap_err();
    assert!(error.message.contains("limit"), "{error}");
    let few = DrawingLimits {
        max_points: 7,
        ..DrawingLimits::default()
    };
    assert!(read_dxf(text.as_bytes(), &all(), &few).is_err());
    // INSERTs that multiply (each block inserting the previous twice) stop at the limit.
    let mut blocks = square_block("b0");
    for level in 1..40 {
        blocks.extend([(0, "BLOCK".to_string()), (2, format!("b{level}"))]);
        blocks.extend(insert(
            &format!("b{}", level - 1),
            [0.0, 0.0],
            [1.0, 1.0],
            0.0,
        ));
        blocks.extend(insert(
            &format!("b{}", level - 1),
            [1.0, 0.0],
            [1.0, 1.0],
            0.0,
        ));
        blocks.push((0, "ENDBLK".into()));
    }
    let e = insert("b39", [0.0, 0.0], [1.0, 1.0], 0.0);
    let error = read(&dxf(&pairs(&blocks), &pairs(&e)), &all()).unwrap_err();
    assert!(error.message.contains("INSERT"), "{error}");
}

#[test]
fn far_and_tiny_drawings_join() {
    // At 1e6 the grid still joins ends a ten-thousandth apart.
    let mut e = line("0", [1e6, 1e6], [1e6 + 1.0, 1e6]);
    e.extend(line("0", [1e6 + 1.0, 1e6 + 1e-4], [1e6, 1e6 + 1.0]));
    e.extend(line("0", [1e6, 1e6 + 1.0], [1e6, 1e6]));
    let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
    assert_eq!(d.paths.len(), 1);
    assert!(d.paths[0].closed_in_file);
    // A triangle a millionth across keeps its three corners.
    let mut e = line("0", [0.0, 0.0], [1e-6, 0.0]);
    e.extend(line("0", [1e-6, 0.0], [0.0, 1e-6]));
    e.extend(line("0", [0.0, 1e-6], [0.0, 0.0]));
    let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
    assert_eq!(d.paths.len(), 1);
    assert_eq!(d.paths[0].edges.len(), 3);
    assert!(corners(&d, 0).contains(&DVec2::new(1e-6, 0.0)));
}

fn example(name: &str, options: &DrawingOptions) -> Drawing {
    let path = format!("/usr/share/openscad/examples/Old/{name}.dxf");
    let bytes = std::fs::read(&path).unwrap_or_else(|e| panic!("{path}: {e}"));
    read_dxf(&bytes, options, &DrawingLimits::default()).unwrap_or_else(|e| panic!("{path}: {e}"))
}

#[test]
fn openscad_examples_read() {
    if !std::path::Path::new("/usr/share/openscad/examples/Old").exists() {
        eprintln!("OpenSCAD's examples are not installed; skipped");
        return;
    }
    for (name, layers) in [
        ("example007", &["cutout1", "cutout2"][..]),
        ("example008", &["G", "E", "B", "X"]),
        ("example013", &[""]),
    ] {
        for l in layers {
            let d = example(name, &layer(l));
            assert!(!d.paths.is_empty(), "{name} {l}");
            assert!(
                d.paths.iter().all(|p| p.closed_in_file),
                "{name} {l}: {:?}",
                d.warnings
            );
        }
    }
    // example013 is four INSERTs of blocks: one outline of 20 edges.
    assert_eq!(example("example013", &all()).paths[0].edges.len(), 20);
    // example008's B has its two holes.
    assert_eq!(example("example008", &layer("B")).paths.len(), 3);
    // example009: the body is one path of 8 arcs and five circles.
    let body = example("example009", &layer("body"));
    assert_eq!(body.circles.len(), 5);
    assert_eq!(body.paths.len(), 1);
    assert!(body.paths[0].edges.iter().all(|e| e.arc.is_some()));
    // Its dimensions and cross, as example009.scad reads them.
    let all_layers = example("example009", &all());
    assert_eq!(all_layers.dimension(Some("bodywidth")), Ok(Some(22.0)));
    assert_eq!(all_layers.dimension(Some("fanwidth")), Ok(Some(20.0)));
    assert_eq!(all_layers.dimension(Some("platewidth")), Ok(Some(2.0)));
    let fanrot = all_layers.dimension(Some("fanrot")).unwrap().unwrap();
    // OpenSCAD 2021.01 echoes 57.5288.
    assert!((fanrot - 57.5288).abs() < 1e-4, "{fanrot}");
    assert_eq!(all_layers.dimension(Some("none")), Ok(None));
    let cross = example("example009", &layer("fan_side_center"))
        .cross()
        .unwrap();
    assert!((cross - DVec2::new(0.0, -40.0)).length() < 1e-12);
}

#[test]
fn many_open_chains_and_a_busy_vertex_join_in_linear_time() {
    // 20,000 separate segments (each an open chain) and 20,000 segments from one vertex: a
    // search that restarted from the first edge, or scanned the busy vertex's edges at every
    // step, would take billions of steps.
    let mut e = Vec::new();
    for i in 0..20_000 {
        let x = i as f64 * 3.0;
        e.extend(line("0", [x, 0.0], [x + 1.0, 0.0]));
    }
    for i in 0..20_000 {
        let a = i as f64 * 1e-4;
        e.extend(line(
            "0",
            [0.0, 50.0],
            [100.0 * a.cos(), 50.0 + 100.0 * a.sin()],
        ));
    }
    let start = std::time::Instant::now();
    let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
    assert_eq!(d.paths.len(), 20_000 + 10_000);
    assert!(start.elapsed().as_secs() < 20, "{:?}", start.elapsed());
}

/// The pairs of an LWPOLYLINE through `points`, each `[x, y, bulge]`.
fn lwpolyline(points: &[[f64; 3]], closed: bool) -> Vec<(i32, String)> {
    let mut v = vec![
        (0, "LWPOLYLINE".to_string()),
        (8, "0".into()),
        (90, points.len().to_string()),
        (70, if closed { "1" } else { "0" }.into()),
    ];
    for p in points {
        v.push((10, p[0].to_string()));
        v.push((20, p[1].to_string()));
        if p[2] != 0.0 {
            v.push((42, p[2].to_string()));
        }
    }
    v
}

#[test]
fn bulges_make_arcs_with_a_warning() {
    // A half circle (bulge 1) below the edge from (0, 0) to (10, 0); a quarter turn clockwise
    // (bulge −tan 22.5°) from (10, 10) to (0, 10), about (5, 15).
    let t = 22.5f64.to_radians().tan();
    let e = lwpolyline(
        &[
            [0.0, 0.0, 1.0],
            [10.0, 0.0, 0.0],
            [10.0, 10.0, -t],
            [0.0, 10.0, 0.0],
        ],
        true,
    );
    let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
    assert_eq!(d.paths.len(), 1);
    let arcs: Vec<_> = d.paths[0]
        .edges
        .iter()
        .filter_map(|e| e.arc.map(|a| (e.from, e.to, a)))
        .collect();
    assert_eq!(arcs.len(), 2);
    let half = arcs
        .iter()
        .find(|(_, _, a)| (a.radius - 5.0).abs() < 1e-12)
        .unwrap();
    assert!((half.2.center - DVec2::new(5.0, 0.0)).length() < 1e-12);
    let mid = half.2.midpoint(half.0, half.1);
    assert!((mid - DVec2::new(5.0, -5.0)).length() < 1e-9, "{mid}");
    let quarter = arcs
        .iter()
        .find(|(_, _, a)| (a.radius - 50f64.sqrt()).abs() < 1e-9)
        .unwrap();
    assert!((quarter.2.center - DVec2::new(5.0, 15.0)).length() < 1e-9);
    let mid = quarter.2.midpoint(quarter.0, quarter.1);
    assert!(
        (mid - DVec2::new(5.0, 15.0 - 50f64.sqrt())).length() < 1e-9,
        "{mid}"
    );
    assert!(
        d.warnings
            .iter()
            .any(|w| matches!(w, DrawingWarning::Bulges { count: 2, .. })),
        "{:?}",
        d.warnings
    );
    // A POLYLINE's VERTEX bulges: two half circles make a full disc's outline.
    let mut e = vec![
        (0, "POLYLINE".to_string()),
        (8, "0".into()),
        (66, "1".into()),
        (70, "1".into()),
    ];
    for x in ["0", "10"] {
        e.extend([
            (0, "VERTEX".to_string()),
            (8, "0".into()),
            (10, x.into()),
            (20, "0".into()),
            (42, "1".into()),
        ]);
    }
    e.push((0, "SEQEND".into()));
    let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
    assert_eq!(d.paths[0].edges.len(), 2);
    assert!(d.paths[0].edges.iter().all(|e| e.arc.is_some()));
    // No bulge, no arc and no warning.
    let e = lwpolyline(&[[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], true);
    let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
    assert!(d.paths[0].edges.iter().all(|e| e.arc.is_none()) && d.warnings.is_empty());
}

fn ellipse(
    c: [f64; 2],
    axis: [f64; 2],
    ratio: f64,
    params: Option<[f64; 2]>,
) -> Vec<(i32, String)> {
    let mut v = vec![
        (0, "ELLIPSE".to_string()),
        (8, "0".into()),
        (10, c[0].to_string()),
        (20, c[1].to_string()),
        (11, axis[0].to_string()),
        (21, axis[1].to_string()),
        (40, ratio.to_string()),
    ];
    if let Some([s, e]) = params {
        v.push((41, s.to_string()));
        v.push((42, e.to_string()));
    }
    v
}

#[test]
fn ellipses_full_and_partial_stay_exact() {
    use std::f64::consts::{PI, TAU};
    // Full: no parameters (a whole turn by default), and 0 to 2π.
    for params in [None, Some([0.0, TAU])] {
        let e = ellipse([1.0, 2.0], [3.0, 4.0], 0.5, params);
        let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
        assert_eq!(d.ellipses.len(), 1, "{params:?}");
        assert_eq!(d.ellipses[0].center, DVec2::new(1.0, 2.0));
        assert_eq!(
            d.ellipses[0].axes,
            [DVec2::new(3.0, 4.0), DVec2::new(-2.0, 1.5)]
        );
    }
    // Half, from parameter 0 to π: an open path closed by its chord, with the arc's points on
    // the ellipse and above the major axis.
    let e = ellipse([0.0, 0.0], [8.0, 0.0], 0.5, Some([0.0, PI]));
    let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
    assert_eq!(d.paths.len(), 1);
    let edge = d.paths[0]
        .edges
        .iter()
        .find(|e| e.ellipse.is_some())
        .unwrap();
    let el = edge.ellipse.unwrap();
    let mid = el.midpoint(edge.from, edge.to);
    assert!((mid - DVec2::new(0.0, 4.0)).length() < 1e-9, "{mid}");
    assert!((el.param(DVec2::new(0.0, -4.0)) + PI / 2.0).abs() < 1e-12);
    assert!(
        d.warnings
            .iter()
            .any(|w| matches!(w, DrawingWarning::OpenPath { .. }))
    );
    // Origin and scale move and scale it as a whole, with a warning that OpenSCAD differs.
    let options = DrawingOptions {
        origin: DVec2::new(1.0, 1.0),
        scale: 2.0,
        ..all()
    };
    let e = ellipse([3.0, 4.0], [10.0, 0.0], 0.5, None);
    let d = read(&dxf(&[], &pairs(&e)), &options).unwrap();
    assert_eq!(d.ellipses[0].center, DVec2::new(4.0, 6.0));
    assert_eq!(
        d.ellipses[0].axes,
        [DVec2::new(20.0, 0.0), DVec2::new(0.0, 10.0)]
    );
    assert!(
        d.warnings
            .iter()
            .any(|w| matches!(w, DrawingWarning::EllipseOptions { .. }))
    );
    // No sweep draws nothing, as OpenSCAD.
    let e = ellipse([0.0, 0.0], [8.0, 0.0], 0.5, Some([1.0, 1.0]));
    let d = read(&dxf(&[], &pairs(&e)), &all()).unwrap();
    assert!(d.ellipses.is_empty() && d.paths.is_empty());
}

#[test]
fn malformed_ellipses_are_errors_at_their_line() {
    for (e, needle) in [
        (ellipse([0.0, 0.0], [1.0, 0.0], 0.0, None), "axis ratio 0"),
        (
            ellipse([0.0, 0.0], [1.0, 0.0], -0.5, None),
            "axis ratio -0.5",
        ),
        (ellipse([0.0, 0.0], [0.0, 0.0], 0.5, None), "major axis"),
        (
            vec![
                (0, "ELLIPSE".to_string()),
                (8, "0".into()),
                (10, "0".into()),
                (20, "0".into()),
                (40, "0.5".into()),
            ],
            "major axis",
        ),
    ] {
        let error = read(&dxf(&[], &pairs(&e)), &all()).unwrap_err();
        let text = error.to_string();
        assert!(text.contains(needle) && text.contains("line 21"), "{text}");
    }
}
