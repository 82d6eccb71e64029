//! JSON output of the DAG (`--emit dag --format json`) and the DNF (`--emit dnf --format
//! json`), in the formats of `docs/cli.md`.
//!
//! Output is deterministic: structs serialise their fields in declaration order, lists follow
//! the arena's and the DNF's own order, and no hash map is iterated. Non-finite numbers (an
//! unbounded side of a box) are written as `null`. File names are resolved by the caller.

use qcsg_diag::FileId;
use serde::Serialize;

use crate::bounds::BoundsJson;
use crate::dag::{Dag, Edge, NodeKind, Source};
use crate::dnf::Dnf;
use crate::stats::DnfStats;

/// A source as it appears in JSON: `{"file": name, "byte_range": [start, end]}`.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct SourceJson {
    /// The file's name, as the caller resolved it.
    pub file: String,
    /// The byte range `[start, end)`.
    pub byte_range: [u32; 2],
}

impl SourceJson {
    /// The JSON form of `source`, naming its file with `file_name`.
    pub fn new(source: Source, file_name: &dyn Fn(FileId) -> String) -> Self {
        Self {
            file: file_name(source.file),
            byte_range: [source.span.start, source.span.end],
        }
    }
}

/// A resolver of file names from a list indexed by `FileId` (`"<unknown>"` past its end).
pub fn names_from_list(names: &[String]) -> impl Fn(FileId) -> String + '_ {
    move |file: FileId| {
        names
            .get(file.0 as usize)
            .cloned()
            .unwrap_or_else(|| "<unknown>".to_string())
    }
}

#[derive(Serialize)]
struct DnfJson<'a> {
    bounds: BoundsJson,
    #[serde(skip_serializing_if = "Option::is_none")]
    region: Option<BoundsJson>,
    quadrics: Vec<QuadricJson>,
    terms: Vec<&'a [u32]>,
    stats: &'a DnfStats,
}

#[derive(Serialize)]
struct QuadricJson {
    id: u32,
    origin: [f64; 3],
    coefficients: [f64; 10],
    kind: &'static str,
    source: SourceJson,
    color: Option<[f64; 4]>,
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    highlight: bool,
    sheets: Vec<SheetJson>,
}

/// One sheet of a quadric's surface: sheets with equal `surface` are one surface
/// ([`crate::coincident`]); `orientation` is `1` or `-1`.
#[derive(Serialize)]
struct SheetJson {
    surface: u32,
    orientation: i8,
}

/// The DNF as pretty-printed JSON: `{"bounds", "quadrics", "terms", "stats"}` (and `"region"`
/// when it was restricted to one). Each quadric lists its `sheets` (one plane for a
/// half-space, two for a slab, one curved sheet otherwise), each with the id of the surface it
/// is and its orientation there.
pub fn dnf_to_json(dnf: &Dnf, file_name: &dyn Fn(FileId) -> String) -> String {
    let json = DnfJson {
        bounds: dnf.bounds.to_arrays(),
        region: dnf.region.map(|r| r.to_arrays()),
        quadrics: dnf
            .quadrics
            .iter()
            .enumerate()
            .map(|(id, q)| QuadricJson {
                id: id as u32,
                origin: q.quadric.origin().to_array().map(positive_zero),
                coefficients: q.quadric.coefficients().map(positive_zero),
                kind: q.quadric.kind().name(),
                source: SourceJson::new(q.source, file_name),
                color: q.color,
                highlight: q.highlight,
                sheets: dnf
                    .surfaces
                    .of(id as u32)
                    .unwrap_or_default()
                    .iter()
                    .map(|s| SheetJson {
                        surface: s.surface,
                        orientation: s.orientation,
                    })
                    .collect(),
            })
            .collect(),
        terms: dnf.terms.iter().map(|t| t.literals.as_slice()).collect(),
        stats: &dnf.stats,
    };
    to_pretty(&json)
}

#[derive(Serialize)]
struct DagJson {
    root: Option<EdgeJson>,
    backgrounds: Vec<EdgeJson>,
    nodes: Vec<NodeJson>,
}

#[derive(Serialize)]
struct EdgeJson {
    node: u32,
    /// Row-major 4×4; `null` for the identity.
    transform: Option<[f64; 16]>,
}

#[derive(Serialize)]
struct NodeJson {
    id: u32,
    kind: &'static str,
    children: Vec<EdgeJson>,
    source: SourceJson,
    #[serde(skip_serializing_if = "Option::is_none")]
    bounds: Option<BoundsJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    quadric: Option<LeafJson>,
    #[serde(skip_serializing_if = "Option::is_none")]
    color: Option<[f64; 4]>,
}

#[derive(Serialize)]
struct LeafJson {
    origin: [f64; 3],
    coefficients: [f64; 10],
    kind: &'static str,
}

/// The DAG as pretty-printed JSON: `{"root", "backgrounds", "nodes"}`. Nodes reachable from
/// the root and the background parts appear once each, children before parents; every edge is
/// `{"node": id, "transform": [16 numbers, row-major] | null}` (`null`: identity).
pub fn dag_to_json(dag: &Dag, file_name: &dyn Fn(FileId) -> String) -> String {
    let edge_json = |edge: &Edge| EdgeJson {
        node: edge.child.0,
        transform: (edge.transform != crate::dag::TransformId::IDENTITY)
            .then(|| row_major(&dag.matrix(edge.transform))),
    };
    let reachable = reachable_nodes(dag);
    let nodes = dag
        .nodes()
        .iter()
        .enumerate()
        .filter(|(id, _)| reachable[*id])
        .map(|(id, node)| {
            let (quadric, color) = match &node.kind {
                NodeKind::Leaf(q) => (
                    Some(LeafJson {
                        origin: q.origin().to_array().map(positive_zero),
                        coefficients: q.coefficients().map(positive_zero),
                        kind: q.kind().name(),
                    }),
                    None,
                ),
                NodeKind::Color(rgba, _) => (None, Some(*rgba)),
                _ => (None, None),
            };
            NodeJson {
                id: id as u32,
                kind: node.kind.name(),
                children: node.kind.children().iter().map(edge_json).collect(),
                source: SourceJson::new(node.source, file_name),
                bounds: node.bounds.map(|b| b.to_arrays()),
                quadric,
                color,
            }
        })
        .collect();
    let json = DagJson {
        root: dag.root().as_ref().map(edge_json),
        backgrounds: dag.backgrounds().iter().map(edge_json).collect(),
        nodes,
    };
    to_pretty(&json)
}

/// Which nodes the root and the background parts reach.
pub(crate) fn reachable_nodes(dag: &Dag) -> Vec<bool> {
    let mut reached = vec![false; dag.len()];
    let mut stack: Vec<u32> = dag
        .root()
        .iter()
        .chain(dag.backgrounds())
        .map(|e| e.child.0)
        .collect();
    while let Some(id) = stack.pop() {
        let Some(slot) = reached.get_mut(id as usize) else {
            continue;
        };
        if *slot {
            continue;
        }
        *slot = true;
        if let Some(node) = dag.node(crate::dag::NodeId(id)) {
            stack.extend(node.kind.children().iter().map(|e| e.child.0));
        }
    }
    reached
}

/// A matrix as 16 numbers, row by row.
pub fn row_major(m: &qcsg_quadric::DMat4) -> [f64; 16] {
    m.transpose().to_cols_array().map(positive_zero)
}

/// `-0.0` as `0.0` (negation makes negative zeros; they mean nothing to readers).
pub(crate) fn positive_zero(v: f64) -> f64 {
    v + 0.0
}

fn to_pretty(value: &impl Serialize) -> String {
    // Serialising plain structs of numbers and strings cannot fail.
    serde_json::to_string_pretty(value).unwrap_or_default()
}
