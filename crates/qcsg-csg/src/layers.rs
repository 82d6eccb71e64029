//! What a preview draws, as DNFs: the solid, the `#` highlighted parts (drawn where they are,
//! also where they were subtracted) and the `%` background parts (not part of the solid).

use qcsg_diag::Diagnostic;

use crate::{Dag, Dnf, DnfOptions, build_dnf, build_dnf_of};

/// How many DAG edges the search for highlighted parts may follow before it gives up on them
/// (they are a preview aid: a scene too large to search is still drawn, without them).
const HIGHLIGHT_VISIT_LIMIT: usize = 1_000_000;

/// The DNFs of a scene's layers.
#[derive(Clone, Debug, Default)]
pub struct Layers {
    /// The solid; `None` for a scene without a root (only background parts, or nothing).
    pub solid: Option<Dnf>,
    /// Each highlighted part.
    pub highlights: Vec<Dnf>,
    /// Each background part.
    pub backgrounds: Vec<Dnf>,
}

/// Builds the layers of a DAG. Any layer's DNF error (unbounded, term limit) is an error of
/// the whole: a preview would stop on it.
pub fn build_layers(dag: &mut Dag, options: &DnfOptions) -> Result<Layers, Vec<Diagnostic>> {
    let solid = match dag.root() {
        Some(_) => Some(build_dnf(dag, options)?),
        None => None,
    };
    let highlights = dag
        .highlighted_parts(HIGHLIGHT_VISIT_LIMIT)
        .unwrap_or_default()
        .into_iter()
        .map(|edge| build_dnf_of(dag, edge, options))
        .collect::<Result<Vec<_>, _>>()?;
    let backgrounds = dag
        .backgrounds()
        .iter()
        .map(|&edge| build_dnf_of(dag, edge, options))
        .collect::<Result<Vec<_>, _>>()?;
    Ok(Layers {
        solid,
        highlights,
        backgrounds,
    })
}
