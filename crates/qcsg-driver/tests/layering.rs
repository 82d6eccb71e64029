//! The layering of ARCHITECTURE.md, checked against the workspace's real dependencies (from
//! `cargo metadata`): a crate that starts to depend on one it must not fails this test.

use std::collections::BTreeMap;
use std::process::Command;

/// The front end: what the geometry must never compile.
const FRONT_END: &[&str] = &[
    "qcsg-syntax",
    "qcsg-sema",
    "qcsg-eval",
    "qcsg-driver",
    "qcsg-ide",
    "qcsg-lsp",
];

/// For each library crate, the qcsg crates it may depend on (normal dependencies). The tools
/// at the top (`qcsg-cli`, `qcsg-bench`, `qcsg-fuzz`) may depend on anything.
fn allowed() -> BTreeMap<&'static str, Vec<&'static str>> {
    BTreeMap::from([
        ("qcsg-diag", vec![]),
        ("qcsg-quadric", vec![]),
        ("qcsg-mesh", vec![]),
        // Test helpers: a file loader over memory (the loader's trait), the language suite's
        // annotations (diagnostics, analyses), oracle meshes (the point-triangle distance) and
        // reference points on a DNF's surface (membership, line-quadric roots).
        (
            "qcsg-testkit",
            vec![
                "qcsg-diag",
                "qcsg-sema",
                "qcsg-mesh",
                "qcsg-csg",
                "qcsg-quadric",
            ],
        ),
        ("qcsg-syntax", vec!["qcsg-diag"]),
        ("qcsg-sema", vec!["qcsg-diag", "qcsg-syntax"]),
        ("qcsg-csg", vec!["qcsg-diag", "qcsg-quadric", "qcsg-mesh"]),
        (
            "qcsg-eval",
            vec![
                "qcsg-diag",
                "qcsg-syntax",
                "qcsg-sema",
                "qcsg-csg",
                "qcsg-quadric",
                // polygon's convex cells.
                "qcsg-mesh",
            ],
        ),
        (
            "qcsg-driver",
            vec!["qcsg-diag", "qcsg-sema", "qcsg-eval", "qcsg-csg"],
        ),
        ("qcsg-sample", vec!["qcsg-diag", "qcsg-csg", "qcsg-quadric"]),
        ("qcsg-render", vec!["qcsg-diag", "qcsg-csg", "qcsg-quadric"]),
        // Meshes checked against the sampler's points, by the mesh crate's distance query.
        (
            "qcsg-export",
            vec![
                "qcsg-diag",
                "qcsg-csg",
                "qcsg-quadric",
                "qcsg-sample",
                "qcsg-mesh",
            ],
        ),
        (
            "qcsg-splat",
            vec![
                "qcsg-diag",
                "qcsg-csg",
                "qcsg-quadric",
                "qcsg-sample",
                "qcsg-render",
            ],
        ),
        ("qcsg-ide", vec!["qcsg-diag", "qcsg-syntax", "qcsg-sema"]),
        (
            "qcsg-lsp",
            vec![
                "qcsg-diag",
                "qcsg-syntax",
                "qcsg-sema",
                "qcsg-eval",
                "qcsg-csg",
                "qcsg-quadric",
                "qcsg-driver",
                "qcsg-ide",
                // The preview panel's frames and picks.
                "qcsg-render",
            ],
        ),
    ])
}

const TOOLS: &[&str] = &["qcsg-cli", "qcsg-bench", "qcsg-fuzz"];

/// Each workspace crate with its normal qcsg dependencies.
fn workspace_dependencies() -> BTreeMap<String, Vec<String>> {
    let cargo = std::env::var("CARGO").unwrap_or_else(|_| "cargo".to_owned());
    let output = Command::new(cargo)
        .args([
            "metadata",
            "--format-version",
            "1",
            "--no-deps",
            "--offline",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("cargo metadata runs");
    assert!(
        output.status.success(),
        "{}",
        String::from_utf8_lossy(&output.stderr)
    );
    let metadata: serde_json::Value = serde_json::from_slice(&output.stdout).expect("JSON");
    let mut crates = BTreeMap::new();
    for package in metadata["packages"].as_array().expect("packages") {
        let name = package["name"].as_str().expect("name").to_owned();
        let dependencies = package["dependencies"]
            .as_array()
            .expect("dependencies")
            .iter()
            .filter(|d| d["kind"].is_null())
            .filter_map(|d| d["name"].as_str())
            .filter(|d| d.starts_with("qcsg-"))
            .map(str::to_owned)
            .collect();
        crates.insert(name, dependencies);
    }
    crates
}

#[test]
fn every_crate_depends_only_on_the_layers_below_it() {
    let allowed = allowed();
    let mut wrong = Vec::new();
    for (name, dependencies) in workspace_dependencies() {
        if TOOLS.contains(&name.as_str()) {
            continue;
        }
        let Some(may) = allowed.get(name.as_str()) else {
            wrong.push(format!(
                "{name} is new: give it its place in ARCHITECTURE.md and in this test"
            ));
            continue;
        };
        for dependency in dependencies {
            if !may.contains(&dependency.as_str()) {
                wrong.push(format!("{name} must not depend on {dependency}"));
            }
        }
    }
    assert!(wrong.is_empty(), "{}", wrong.join("\n"));
}

#[test]
fn the_geometry_never_compiles_the_front_end() {
    for (name, may) in allowed() {
        if [
            "qcsg-quadric",
            "qcsg-csg",
            "qcsg-sample",
            "qcsg-render",
            "qcsg-splat",
        ]
        .contains(&name)
        {
            assert!(
                may.iter().all(|d| !FRONT_END.contains(d)),
                "the rules let {name} compile the front end"
            );
        }
    }
}
