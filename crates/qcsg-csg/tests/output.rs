//! JSON and text output: the formats of docs/cli.md, sharing, determinism.

mod common;

use common::{cube, sphere, src};
use qcsg_csg::{
    Dag, DnfOptions, build_dnf, byte_locator, dag_to_json, dag_to_text, dnf_to_json, dnf_to_text,
    line_locator, names_from_list,
};
use qcsg_diag::SourceMap;
use qcsg_quadric::DVec3;
use serde_json::Value;

/// A module instantiated three times with the same arguments, each copy translated, coloured
/// once, minus a sphere; plus a background part.
fn scene() -> Dag {
    let mut dag = Dag::new();
    let mut parts = Vec::new();
    for i in 0..3 {
        // What an evaluator does for each instantiation: rebuild the same nodes.
        let c = cube(&mut dag, DVec3::ONE, 4);
        parts.push(
            dag.translated(c.into(), DVec3::new(2.0 * i as f64, 0.0, 0.0))
                .unwrap(),
        );
    }
    let row = dag.union(parts, src(20));
    let red = dag
        .color(row.into(), [1.0, 0.0, 0.0, 1.0], src(30))
        .unwrap();
    let s = sphere(&mut dag, 0.3, 40);
    let s = dag.translated(s.into(), DVec3::new(0.5, 0.5, 1.0)).unwrap();
    let d = dag.difference([red.into(), s], src(50));
    dag.set_root(d.into());
    let bg = sphere(&mut dag, 5.0, 60);
    dag.add_background(bg.into());
    dag
}

#[test]
fn dag_json_shares_nodes_and_writes_row_major_transforms() {
    let dag = scene();
    let names = vec!["main.qcsg".to_string()];
    let json: Value = serde_json::from_str(&dag_to_json(&dag, &names_from_list(&names))).unwrap();
    let nodes = json["nodes"].as_array().unwrap();
    let leaves = nodes.iter().filter(|n| n["kind"] == "leaf").count();
    assert_eq!(
        leaves,
        3 + 1 + 1,
        "three slabs shared by all copies, two spheres"
    );
    let union = nodes.iter().find(|n| n["kind"] == "union").unwrap();
    let children = union["children"].as_array().unwrap();
    assert_eq!(children.len(), 3);
    assert!(children.iter().all(|c| c["node"] == children[0]["node"]));
    assert_eq!(
        children[1]["transform"][3], 2.0,
        "row-major: translation in the last column"
    );
    assert!(children[0]["transform"].is_null(), "identity is null");
    assert_eq!(json["backgrounds"].as_array().unwrap().len(), 1);
    assert_eq!(nodes[0]["source"]["file"], "main.qcsg");
    assert_eq!(nodes[0]["source"]["byte_range"], serde_json::json!([4, 5]));
}

#[test]
fn dnf_json_has_the_documented_shape() {
    let dag = scene();
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    let names = vec!["main.qcsg".to_string()];
    let text = dnf_to_json(&dnf, &names_from_list(&names));
    let json: Value = serde_json::from_str(&text).unwrap();
    let keys: Vec<&str> = json
        .as_object()
        .unwrap()
        .keys()
        .map(String::as_str)
        .collect();
    for key in ["bounds", "quadrics", "terms", "stats"] {
        assert!(keys.contains(&key), "{key} missing");
    }
    let quadrics = json["quadrics"].as_array().unwrap();
    for (i, q) in quadrics.iter().enumerate() {
        assert_eq!(q["id"], i);
        assert_eq!(q["origin"].as_array().unwrap().len(), 3);
        assert_eq!(q["coefficients"].as_array().unwrap().len(), 10);
        assert!(q["kind"].is_string());
        assert_eq!(q["source"]["file"], "main.qcsg");
        assert_eq!(q["source"]["byte_range"].as_array().unwrap().len(), 2);
    }
    // The cube slabs are red, the subtracted sphere has no colour.
    assert!(
        quadrics
            .iter()
            .any(|q| q["color"] == serde_json::json!([1.0, 0.0, 0.0, 1.0]))
    );
    assert!(quadrics.iter().any(|q| q["color"].is_null()));
    let terms = json["terms"].as_array().unwrap();
    assert_eq!(terms.len(), 3, "{text}");
    for t in terms {
        for id in t.as_array().unwrap() {
            assert!((id.as_u64().unwrap() as usize) < quadrics.len());
        }
    }
    let min_x = json["bounds"]["min"][0].as_f64().unwrap();
    let max_x = json["bounds"]["max"][0].as_f64().unwrap();
    assert!((-1e-9..=0.0).contains(&min_x) && (5.0..5.0 + 1e-9).contains(&max_x));
    assert!(json["stats"]["passes"].as_array().unwrap().len() >= 6);
}

#[test]
fn output_is_deterministic() {
    let names = vec!["main.qcsg".to_string()];
    let a = dnf_to_json(
        &build_dnf(&scene(), &DnfOptions::default()).unwrap(),
        &names_from_list(&names),
    );
    let b = dnf_to_json(
        &build_dnf(&scene(), &DnfOptions::default()).unwrap(),
        &names_from_list(&names),
    );
    assert_eq!(a, b);
    let a = dag_to_json(&scene(), &names_from_list(&names));
    let b = dag_to_json(&scene(), &names_from_list(&names));
    assert_eq!(a, b);
}

#[test]
fn text_forms_are_readable() {
    let dag = scene();
    let mut map = SourceMap::new();
    map.add("main.qcsg", "cube\n(1);\n".repeat(20));
    let locate = line_locator(&map);
    let dag_text = dag_to_text(&dag, &locate);
    assert!(dag_text.contains("root = n"), "{dag_text}");
    assert!(dag_text.contains("main.qcsg:1:5"), "{dag_text}");
    assert!(dag_text.contains("background = n"));
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    let text = dnf_to_text(&dnf, &locate);
    assert_eq!(
        text.lines()
            .filter(|l| {
                let l = l.trim_start();
                l.starts_with('t') && l[1..].starts_with(|c: char| c.is_ascii_digit())
            })
            .count(),
        3,
        "{text}"
    );
    assert!(text.contains("sphere") && text.contains("slab"), "{text}");
    let names = vec!["main.qcsg".to_string()];
    let bytes = dnf_to_text(&dnf, &byte_locator(&names));
    assert!(bytes.contains("main.qcsg@4..5"), "{bytes}");
}

#[test]
fn faces_shared_by_differently_coloured_parts_keep_their_colours() {
    let mut dag = Dag::new();
    let a = cube(&mut dag, DVec3::ONE, 0);
    let b = cube(&mut dag, DVec3::ONE, 0);
    let red = dag.color(a.into(), [1.0, 0.0, 0.0, 1.0], src(1)).unwrap();
    let blue = dag.color(b.into(), [0.0, 0.0, 1.0, 1.0], src(2)).unwrap();
    let blue = dag
        .translated(blue.into(), DVec3::new(2.0, 0.0, 0.0))
        .unwrap();
    let u = dag.union([red.into(), blue], src(3));
    dag.set_root(u.into());
    let dnf = build_dnf(&dag, &DnfOptions::default()).unwrap();
    for term in &dnf.terms {
        let colours: Vec<_> = term
            .literals
            .iter()
            .map(|&i| dnf.quadrics[i as usize].color)
            .collect();
        assert!(colours.iter().all(|c| *c == colours[0]), "{colours:?}");
    }
    assert_eq!(dnf.quadrics.len(), 6);
}
