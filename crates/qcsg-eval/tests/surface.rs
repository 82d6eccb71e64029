//! `surface(file)` of `.dat` tables and PNG images, against an exact reference: the height
//! function of OpenSCAD's mesh (four triangles around each cell's centre, whose height is the
//! mean of the corners), with the base at `min(0, lowest − 1)`. Row order, centring, `invert`,
//! 16-bit images, stiff heights and every failure at the `file` argument.

use std::path::{Path, PathBuf};

use glam::DVec3;
use qcsg_csg::{DnfOptions, build_dnf};
use qcsg_eval::EvalOptions;
use qcsg_eval::surface::{HeightMap, read_height_map};
use qcsg_testkit::Rng;

mod common;

use common::eval_in;

/// A fresh directory for one test.
fn scratch(name: &str) -> PathBuf {
    common::scratch("surface-tests", name)
}

/// The first error of evaluating `text` in `dir`: code, the text it points at, message.
fn first_error(dir: &Path, text: &str, options: &EvalOptions) -> (&'static str, String, String) {
    let e = eval_in(dir, text, options);
    let d = e
        .diagnostics
        .iter()
        .find(|d| d.is_error())
        .unwrap_or_else(|| panic!("{text}: no error in {:?}", e.diagnostics));
    (
        d.code,
        text[d.span.start as usize..d.span.end as usize].to_owned(),
        d.message.clone(),
    )
}

/// The height of OpenSCAD's surface mesh over `(x, y)` of the uncentred grid, if inside it.
fn reference_height(map: &HeightMap, x: f64, y: f64) -> Option<f64> {
    let (cols, rows) = ((map.columns - 1) as f64, (map.rows - 1) as f64);
    if !(0.0..=cols).contains(&x) || !(0.0..=rows).contains(&y) {
        return None;
    }
    let j = (x.floor() as usize).min(map.columns - 2);
    let i = (y.floor() as usize).min(map.rows - 2);
    let (u, v) = (x - j as f64, y - i as f64);
    let (a, b, c, d) = (
        map.at(i, j),
        map.at(i, j + 1),
        map.at(i + 1, j),
        map.at(i + 1, j + 1),
    );
    let m = (a + b + c + d) / 4.0;
    // The triangle of the cell the point is in, and its corners (with the centre (½, ½)).
    let (p, q) = if v <= u && v <= 1.0 - u {
        (((0.0, 0.0), a), ((1.0, 0.0), b))
    } else if u >= v && u >= 1.0 - v {
        (((1.0, 0.0), b), ((1.0, 1.0), d))
    } else if v >= u && v >= 1.0 - u {
        (((1.0, 1.0), d), ((0.0, 1.0), c))
    } else {
        (((0.0, 1.0), c), ((0.0, 0.0), a))
    };
    // Barycentric interpolation over (p, q, centre).
    let ((px, py), hp) = p;
    let ((qx, qy), hq) = q;
    let (cx, cy) = (0.5, 0.5);
    let det = (qy - cy) * (px - cx) + (cx - qx) * (py - cy);
    let l1 = ((qy - cy) * (u - cx) + (cx - qx) * (v - cy)) / det;
    let l2 = ((cy - py) * (u - cx) + (px - cx) * (v - cy)) / det;
    Some(l1 * hp + l2 * hq + (1.0 - l1 - l2) * m)
}

/// Compares the solid of `call` (in `dir`) with the reference over `map`, whose grid starts
/// at `origin`, at random points of its box; `gap` is how far from the surfaces points must be.
fn assert_matches(dir: &Path, call: &str, map: &HeightMap, origin: DVec3, gap: f64) {
    let e = eval_in(dir, call, &EvalOptions::default());
    assert!(
        !e.diagnostics.iter().any(|d| d.is_error()),
        "{call}: {:?}",
        e.diagnostics
    );
    let dnf = build_dnf(&e.dag, &DnfOptions::default()).expect("a bounded solid");
    let base = qcsg_eval::surface::base_height(map);
    let top = map.heights.iter().fold(f64::MIN, |m, &h| m.max(h));
    let lo = DVec3::new(-1.0, -1.0, base - (top - base) * 0.2 - 1.0);
    let hi = DVec3::new(
        map.columns as f64,
        map.rows as f64,
        top + (top - base) * 0.2 + 1.0,
    );
    let mut rng = Rng::new(0x5eed ^ map.heights.len() as u64);
    let (mut inside, mut outside) = (0, 0);
    for _ in 0..1500 {
        let p = rng.in_box(lo, hi);
        let expected = match reference_height(map, p.x, p.y) {
            None => {
                if p.x.abs().min(p.y.abs()) < gap
                    || (p.x - (map.columns - 1) as f64).abs() < gap
                    || (p.y - (map.rows - 1) as f64).abs() < gap
                {
                    continue;
                }
                false
            }
            Some(h) => {
                let near_side = p.x.min(p.y) < gap
                    || (p.x - (map.columns - 1) as f64).abs() < gap
                    || (p.y - (map.rows - 1) as f64).abs() < gap;
                if near_side || (p.z - h).abs() < gap || (p.z - base).abs() < gap {
                    continue;
                }
                p.z > base && p.z < h
            }
        };
        if expected {
            inside += 1;
        } else {
            outside += 1;
        }
        assert_eq!(e.dag.contains(p + origin), expected, "{call}: DAG at {p}");
        assert_eq!(dnf.contains(p + origin), expected, "{call}: DNF at {p}");
    }
    assert!(
        inside > 50 && outside > 50,
        "{inside} inside, {outside} out"
    );
}

/// A PNG of `rows` (top row first) of RGB pixels.
fn png_rgb(rows: &[Vec<[u8; 3]>]) -> Vec<u8> {
    let (w, h) = (rows[0].len() as u32, rows.len() as u32);
    let img = image::RgbImage::from_fn(w, h, |x, y| image::Rgb(rows[y as usize][x as usize]));
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    out.into_inner()
}

const DAT: &str =
    "# a height map\n\n 1 2 3.5 2\n\t0.5 -1 4 2 \r\n  # a comment between rows\n3 3 3 1e0\n";

#[test]
fn a_table_is_rows_of_heights_at_y_equal_to_the_row() {
    let map = read_height_map(DAT.as_bytes(), false, 100).unwrap();
    assert_eq!((map.rows, map.columns), (3, 4));
    assert_eq!(map.at(0, 2), 3.5);
    assert_eq!(map.at(1, 1), -1.0);
    assert_eq!(map.at(2, 3), 1.0);
    // invert is for images only.
    assert_eq!(read_height_map(DAT.as_bytes(), true, 100).unwrap(), map);
    assert_eq!(qcsg_eval::surface::base_height(&map), -2.0);
    // All heights above 1: the base stays at 0.
    let high = read_height_map(b"5 6\n7 8\n", false, 100).unwrap();
    assert_eq!(qcsg_eval::surface::base_height(&high), 0.0);

    let dir = scratch("dat");
    std::fs::write(dir.join("map.dat"), DAT).unwrap();
    assert_matches(&dir, "surface(\"map.dat\");", &map, DVec3::ZERO, 1e-6);
    assert_matches(
        &dir,
        "surface(file = \"map.dat\", center = true, convexity = 4);",
        &map,
        DVec3::new(-1.5, -1.0, 0.0),
        1e-6,
    );
    assert_matches(
        &dir,
        "translate([10, 20, 30]) surface(\"map.dat\", false);",
        &map,
        DVec3::new(10.0, 20.0, 30.0),
        1e-6,
    );
    let e = eval_in(
        &dir,
        "surface(\"map.dat\"); surface(\"map.dat\");",
        &EvalOptions::default(),
    );
    assert_eq!(e.imports, vec![dir.join("map.dat")]);
}

#[test]
fn an_image_is_its_luminance_top_row_at_the_largest_y() {
    let rows = vec![
        vec![[255, 0, 0], [0, 255, 0], [0, 0, 255]],
        vec![[10, 20, 30], [200, 100, 50], [0, 0, 0]],
    ];
    let bytes = png_rgb(&rows);
    let map = read_height_map(&bytes, false, 100).unwrap();
    assert_eq!((map.rows, map.columns), (2, 3));
    // OpenSCAD 2021.01's heights (read from its STL export of this image).
    assert_eq!(map.at(1, 0), 100.0 / 255.0 * (0.2126 * 255.0));
    assert!((map.at(1, 0) - 21.26).abs() < 1e-12);
    assert!((map.at(0, 1) - 46.1373).abs() < 1e-4);
    assert!((map.at(0, 0) - 7.29255).abs() < 1e-5);
    assert_eq!(map.at(0, 2), 0.0);
    // invert takes 1 − L on the 0–255 scale, as OpenSCAD 2021.01 does.
    let inverted = read_height_map(&bytes, true, 100).unwrap();
    assert!((inverted.at(1, 1) - -71.1278).abs() < 1e-4);
    assert!((qcsg_eval::surface::base_height(&inverted) - -72.1278).abs() < 1e-4);
    assert!((inverted.at(0, 2) - 0.392157).abs() < 1e-6);

    let dir = scratch("png");
    std::fs::write(dir.join("map.png"), &bytes).unwrap();
    assert_matches(&dir, "surface(\"map.png\");", &map, DVec3::ZERO, 1e-6);
    assert_matches(
        &dir,
        "surface(\"map.png\", invert = true, center = true);",
        &inverted,
        DVec3::new(-1.0, -0.5, 0.0),
        1e-6,
    );
    // The format is the content's: a PNG named .dat is an image, a table named .png a table.
    std::fs::write(dir.join("image.dat"), &bytes).unwrap();
    std::fs::write(dir.join("table.png"), DAT).unwrap();
    assert_matches(&dir, "surface(\"image.dat\");", &map, DVec3::ZERO, 1e-6);
    let table = read_height_map(DAT.as_bytes(), false, 100).unwrap();
    assert_matches(&dir, "surface(\"table.png\");", &table, DVec3::ZERO, 1e-6);
}

#[test]
fn sixteen_bit_and_grey_images_count_by_the_high_byte() {
    let img = image::ImageBuffer::<image::Luma<u16>, _>::from_fn(2, 2, |x, y| {
        image::Luma([[0x12ff_u16, 0x8080][x as usize] + 0x100 * y as u16])
    });
    let mut out = std::io::Cursor::new(Vec::new());
    img.write_to(&mut out, image::ImageFormat::Png).unwrap();
    let map = read_height_map(&out.into_inner(), false, 100).unwrap();
    let lum = |v: f64| 100.0 / 255.0 * (0.2126 * v + 0.7152 * v + 0.0722 * v);
    // Row 0 of the image (y = 0 in the image) is the top: map row 1.
    assert_eq!(map.at(1, 0), lum(f64::from(0x12)));
    assert_eq!(map.at(1, 1), lum(f64::from(0x80)));
    assert_eq!(map.at(0, 0), lum(f64::from(0x13)));
}

#[test]
fn stiff_heights() {
    let dir = scratch("stiff");
    for (name, scale, offset, gap) in [
        ("big.dat", 1e6, 0.0, 1e-1),
        ("far.dat", 1.0, 1e6, 1e-3),
        ("tiny.dat", 1e-6, 0.0, 1e-9),
    ] {
        let heights = [
            [0.0, 3.0, 1.0, 2.0],
            [2.0, -1.0, 5.0, 0.5],
            [1.0, 1.0, 4.0, 2.5],
        ];
        let text: String = heights
            .iter()
            .map(|row| {
                let cells: Vec<String> = row
                    .iter()
                    .map(|h| format!("{}", h * scale + offset))
                    .collect();
                cells.join(" ") + "\n"
            })
            .collect();
        std::fs::write(dir.join(name), &text).unwrap();
        let map = read_height_map(text.as_bytes(), false, 100).unwrap();
        assert_matches(
            &dir,
            &format!("surface(\"{name}\");"),
            &map,
            DVec3::ZERO,
            gap,
        );
    }
}

#[test]
fn failures_are_errors_at_the_file_argument() {
    let dir = scratch("failures");
    std::fs::write(dir.join("bad.dat"), "1 2 3\n4 x 6\n").unwrap();
    std::fs::write(dir.join("nan.dat"), "1 2\nnan 4\n").unwrap();
    std::fs::write(dir.join("ragged.dat"), "1 2 3\n4 5\n").unwrap();
    std::fs::write(dir.join("empty.dat"), "# nothing\n\n").unwrap();
    std::fs::write(dir.join("row.dat"), "1 2 3 4\n").unwrap();
    std::fs::write(dir.join("binary.dat"), [0xff_u8, 0xfe, 0x00, 0x31]).unwrap();
    let mut broken = b"\x89PNG\r\n\x1a\n".to_vec();
    broken.extend_from_slice(b"not really an image");
    std::fs::write(dir.join("broken.png"), &broken).unwrap();
    std::fs::write(dir.join("big.dat"), "1 2 3\n4 5 6\n7 8 9\n").unwrap();
    std::fs::create_dir_all(dir.join("folder")).unwrap();
    std::fs::write(dir.join("huge.dat"), "1e300 1e300\n1e300 1e300\n").unwrap();
    let options = EvalOptions::default();
    for (call, code, arg, says) in [
        (
            "surface(\"missing.dat\");",
            "E0566",
            "\"missing.dat\"",
            "no such file",
        ),
        ("surface(\"folder\");", "E0566", "\"folder\"", "folder"),
        (
            "surface(\"bad.dat\");",
            "E0567",
            "\"bad.dat\"",
            "line 2: `x`",
        ),
        (
            "surface(file = \"nan.dat\");",
            "E0567",
            "\"nan.dat\"",
            "`nan`",
        ),
        (
            "surface(\"ragged.dat\");",
            "E0567",
            "\"ragged.dat\"",
            "line 2: a row of 2",
        ),
        (
            "surface(\"empty.dat\");",
            "E0567",
            "\"empty.dat\"",
            "no numbers",
        ),
        (
            "surface(\"row.dat\");",
            "E0567",
            "\"row.dat\"",
            "at least 2 rows",
        ),
        (
            "surface(\"binary.dat\");",
            "E0567",
            "\"binary.dat\"",
            "UTF-8",
        ),
        ("surface(\"broken.png\");", "E0567", "\"broken.png\"", "PNG"),
        ("surface();", "E0552", "surface();", "file"),
        (
            "function f(x) = x; surface(file = f(3));",
            "E0552",
            "f(3)",
            "number",
        ),
        // Heights so large that the base (one below) is no lower: no solid.
        ("surface(\"huge.dat\");", "E0565", "\"huge.dat\"", ""),
    ] {
        let (c, at, message) = first_error(&dir, call, &options);
        assert_eq!((c, at.as_str()), (code, arg), "{call}: {message}");
        assert!(message.contains(says), "{call}: {message}");
    }
    // The grid's points count against --max-vector-len; the file's bytes against
    // --max-import-bytes.
    let small = EvalOptions {
        max_vector_len: 8,
        ..EvalOptions::default()
    };
    let (c, at, message) = first_error(&dir, "surface(\"big.dat\");", &small);
    assert_eq!((c, at.as_str()), ("E0558", "\"big.dat\""), "{message}");
    let png = png_rgb(&vec![vec![[1, 2, 3]; 3]; 3]);
    std::fs::write(dir.join("big.png"), png).unwrap();
    let (c, _, message) = first_error(&dir, "surface(\"big.png\");", &small);
    assert_eq!(c, "E0558", "{message}");
    let tight = EvalOptions {
        max_import_bytes: 10,
        ..EvalOptions::default()
    };
    let (c, at, _) = first_error(&dir, "surface(\"big.dat\");", &tight);
    assert_eq!((c, at.as_str()), ("E0568", "\"big.dat\""));
}
