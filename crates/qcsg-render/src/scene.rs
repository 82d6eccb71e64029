//! What a preview shows: the solid, plus the `#` highlighted and `%` background parts that
//! OpenSCAD previews draw translucent over it.

use qcsg_csg::{Aabb, Dag, Dnf, DnfOptions, DnfQuadric, Layers, Term, build_layers};
use qcsg_diag::Diagnostic;

use crate::raytrace::{TermIndex, term_index};

/// One solid to ray trace: its DNF and what its rays look at (the padded term boxes it is
/// clipped to, indexed).
#[derive(Clone, Debug)]
pub struct Layer {
    dnf: Dnf,
    index: TermIndex,
}

impl Layer {
    /// A layer of one solid.
    pub fn new(dnf: Dnf) -> Self {
        let index = term_index(&dnf);
        Self { dnf, index }
    }

    /// The union of several solids as one layer (their DNFs concatenated).
    pub fn union(parts: Vec<Dnf>) -> Option<Self> {
        let mut parts = parts.into_iter();
        let mut dnf = parts.next()?;
        for part in parts {
            let offset = dnf.quadrics.len() as u32;
            dnf.quadrics
                .extend(part.quadrics.into_iter().map(|q: DnfQuadric| q));
            dnf.terms
                .extend(part.terms.into_iter().map(|term: Term| Term {
                    literals: term.literals.iter().map(|&l| l + offset).collect(),
                    bounds: term.bounds,
                }));
            dnf.bounds = dnf.bounds.union(&part.bounds);
        }
        // Parts may share surfaces with each other: decide them over the whole table.
        dnf.surfaces = qcsg_csg::dnf::surfaces_of(&dnf);
        Some(Self::new(dnf))
    }

    /// The solid.
    pub fn dnf(&self) -> &Dnf {
        &self.dnf
    }

    /// What its rays look at: the padded term boxes and, for terms of many literals, where
    /// each literal fails, indexed.
    pub fn index(&self) -> &TermIndex {
        &self.index
    }

    /// The union of the term boxes.
    pub fn bounds(&self) -> Aabb {
        self.dnf.bounds
    }
}

/// A scene to render.
#[derive(Clone, Debug)]
pub struct Scene {
    /// The solid, drawn opaque.
    pub solid: Option<Layer>,
    /// The highlighted parts (`#`), drawn translucent pink, also where they were subtracted.
    pub highlights: Option<Layer>,
    /// The background parts (`%`), drawn translucent grey; not part of the solid.
    pub backgrounds: Option<Layer>,
}

impl Scene {
    /// A scene of one solid and no translucent parts.
    pub fn new(solid: Dnf) -> Self {
        Self {
            solid: Some(Layer::new(solid)),
            highlights: None,
            backgrounds: None,
        }
    }

    /// The scene of a DAG's layers: its solid, highlighted parts and background parts.
    pub fn from_layers(layers: Layers) -> Self {
        Self {
            solid: layers.solid.map(Layer::new),
            highlights: Layer::union(layers.highlights),
            backgrounds: Layer::union(layers.backgrounds),
        }
    }

    /// The scene of a DAG (see [`build_layers`]).
    pub fn from_dag(dag: &mut Dag, options: &DnfOptions) -> Result<Self, Vec<Diagnostic>> {
        build_layers(dag, options).map(Self::from_layers)
    }

    /// The box holding everything drawn (empty for an empty scene).
    pub fn bounds(&self) -> Aabb {
        [&self.solid, &self.highlights, &self.backgrounds]
            .into_iter()
            .flatten()
            .fold(Aabb::EMPTY, |acc, layer| acc.union(&layer.bounds()))
    }

    /// Number of quadrics over all layers.
    pub fn quadric_count(&self) -> usize {
        [&self.solid, &self.highlights, &self.backgrounds]
            .into_iter()
            .flatten()
            .map(|layer| layer.dnf.quadrics.len())
            .sum()
    }
}
