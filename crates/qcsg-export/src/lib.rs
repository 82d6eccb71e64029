//! Watertight triangle meshes of a solid in DNF, within a stated distance `T` of its exact
//! surface both ways, and the files they are written to (`docs/export.md`).
//!
//! The method is construction plus check:
//! 1. every literal of every term is meshed on its own within `T/4` of its quadric
//!    ([`literal`]: planes exactly, ellipsoids, cylinders and cones as inscribed polyhedra with a
//!    closed-form deviation bound, the other kinds as a level set), clipped to the term's box;
//! 2. the terms are intersections of their literals' meshes and the solid is the union of the
//!    terms, computed by Manifold's exact booleans, which return a 2-manifold, oriented mesh;
//!    where two surfaces meet, their meshes' intersection is a chain of mesh edges, so a
//!    drilled hole's rim is a sharp edge of the mesh; plane faces that a term shares with
//!    another (cells of one polygon or imported mesh) are grown a little first, so that the
//!    union merges touching pieces instead of keeping a wall between them ([`growth`]);
//! 3. the result is measured against the exact surface both ways ([`deviation`]): from the
//!    sampler's points, which come within `T/2` of every surface point, to the mesh, and from
//!    points spread over every triangle to the nearest of those points (an upper bound on the
//!    distance to the surface). Where the bound exceeds `T` (a sliver the booleans lost between
//!    nearly tangent surfaces, a level set too coarse), the literals are meshed again at half
//!    the tolerance, a few times, before the export gives up with the measured distance.
//!
//! Coordinates are meshed relative to the scene box's centre and moved back when the mesh is
//! read out, in f64 throughout; the file formats decide what precision is written
//! ([`formats`]).

mod collinear;
pub mod deviation;
pub mod formats;
mod growth;
mod literal;
pub mod topology;

use manifold_rust::csg_tree::CsgNode;
use manifold_rust::manifold::Manifold;
use manifold_rust::types::{Error as ManifoldError, OpType};
use qcsg_csg::{Aabb, Dnf};
use qcsg_quadric::DVec3;
use rayon::prelude::*;

pub use deviation::{Deviation, measure_deviation, measure_deviation_of_solid};
pub use literal::{level_set_surfaces, meshed_as_level_set};
pub use topology::{Topology, topology};

/// The default limit on the triangles of the mesh (and of one literal's mesh).
pub const DEFAULT_MAX_TRIANGLES: u64 = 20_000_000;

/// The default tolerance as a fraction of the scene box's diagonal.
pub const DEFAULT_TOLERANCE_FRACTION: f64 = 1e-3;

/// How often the literals are meshed again, each time at half the tolerance, when the check
/// finds the mesh too far from the surface.
pub const REFINEMENTS: u32 = 3;

/// How to export.
#[derive(Clone, Debug)]
pub struct ExportOptions {
    /// The largest distance allowed between the mesh and the exact surface, both ways.
    pub tolerance: f64,
    /// The most triangles the mesh (and one literal's mesh) may have.
    pub max_triangles: u64,
    /// Measure the deviation and refine where it fails; off, the mesh relies on the
    /// construction's bounds alone.
    pub verify: bool,
    /// Limits of the sampler that the check uses.
    pub sample_limits: qcsg_sample::SampleLimits,
}

impl ExportOptions {
    /// Options with the given tolerance and default limits, checked.
    pub fn new(tolerance: f64) -> Self {
        Self {
            tolerance,
            max_triangles: DEFAULT_MAX_TRIANGLES,
            verify: true,
            sample_limits: qcsg_sample::SampleLimits::default(),
        }
    }
}

/// An indexed triangle mesh in world coordinates, triangles counter-clockwise seen from outside.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TriangleMesh {
    /// Vertex positions.
    pub vertices: Vec<DVec3>,
    /// Triangles as three vertex indices.
    pub triangles: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// The triangle's corners.
    pub fn corners(&self, t: &[u32; 3]) -> [DVec3; 3] {
        t.map(|i| self.vertices[i as usize])
    }

    /// Every triangle's corners, in order: the mesh as a triangle soup.
    pub fn triangle_soup(&self) -> Vec<[DVec3; 3]> {
        self.triangles.iter().map(|t| self.corners(t)).collect()
    }
}

/// An exported mesh and what it took.
#[derive(Clone, Debug)]
pub struct Export {
    /// The mesh.
    pub mesh: TriangleMesh,
    /// The tolerance each literal was meshed to, in the pass that was kept.
    pub literal_tolerance: f64,
    /// The measured two-way deviation, when checked.
    pub deviation: Option<Deviation>,
    /// How many passes were made (1 when the first mesh passed the check).
    pub passes: u32,
}

/// What stops an export.
#[derive(Clone, Debug, PartialEq)]
pub enum ExportError {
    /// The tolerance is not a positive finite length.
    InvalidTolerance(f64),
    /// Some terms are unbounded: there is no finite mesh of them.
    Unbounded {
        /// How many terms.
        terms: usize,
    },
    /// A literal's mesh, or the whole mesh, would have more triangles than allowed.
    TooManyTriangles {
        /// The quadric (index into [`Dnf::quadrics`]) whose mesh needed them, `u32::MAX` for the
        /// whole mesh.
        quadric: u32,
        /// About how many it would need.
        needed: u64,
        /// The limit.
        limit: u64,
    },
    /// Manifold reported an error on a boolean.
    Boolean(String),
    /// The check's sampler crossed one of its limits.
    Sampling(qcsg_sample::SampleError),
    /// The mesh keeps walls inside the solid after every refinement: faces where two pieces of
    /// the solid touch, which the mesh booleans did not merge.
    InteriorWalls {
        /// How many triangles were found inside.
        triangles: usize,
        /// The measured deviation.
        measured: Deviation,
    },
    /// The mesh is still farther than the tolerance from the surface after every refinement.
    ToleranceNotMet {
        /// The measured deviation of the last pass.
        measured: Deviation,
        /// The tolerance asked for.
        tolerance: f64,
    },
}

impl std::fmt::Display for ExportError {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::InvalidTolerance(t) => {
                write!(f, "the tolerance must be positive and finite, got {t}")
            }
            Self::Unbounded { terms } => write!(
                f,
                "{terms} terms of the solid are unbounded, so no finite mesh holds them; bound the \
                 solid (e.g. intersect it with a cube)"
            ),
            Self::TooManyTriangles { needed, limit, .. } => write!(
                f,
                "the mesh would need about {needed} triangles, more than the limit of {limit}: \
                 raise the tolerance or `--max-triangles`"
            ),
            Self::Boolean(message) => write!(f, "a mesh boolean failed: {message}"),
            Self::Sampling(error) => write!(f, "checking the mesh: {error}"),
            Self::InteriorWalls {
                triangles,
                measured,
            } => write!(
                f,
                "the mesh has {triangles} triangles inside the solid, {} from its surface, after \
                 {REFINEMENTS} refinements: walls \
                 where pieces of the solid touch, which the mesh booleans left in (a known limit \
                 where cells touch on a curved face, e.g. of a rotational extrusion; see \
                 docs/export.md)",
                measured.mesh_to_surface
            ),
            Self::ToleranceNotMet {
                measured,
                tolerance,
            } => write!(
                f,
                "the mesh is {} from the surface (surface to mesh {}, mesh to surface {}) after \
                 {REFINEMENTS} refinements, more than the tolerance {tolerance}",
                measured.hausdorff(),
                measured.surface_to_mesh,
                measured.mesh_to_surface
            ),
        }
    }
}

impl std::error::Error for ExportError {}

/// What the export reports while it works.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Progress {
    /// A pass starts over this many terms.
    Pass {
        /// Terms to mesh.
        terms: u64,
    },
    /// One term is meshed.
    TermDone,
    /// The mesh is being checked.
    Checking,
}

/// Meshes the solid within `options.tolerance` of its surface.
pub fn export(
    dnf: &Dnf,
    options: &ExportOptions,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<Export, ExportError> {
    let tolerance = options.tolerance;
    if !(tolerance.is_finite() && tolerance > 0.0) {
        return Err(ExportError::InvalidTolerance(tolerance));
    }
    let unbounded = dnf.terms.iter().filter(|t| !t.bounds.is_bounded()).count();
    if unbounded > 0 {
        return Err(ExportError::Unbounded { terms: unbounded });
    }
    if dnf.terms.is_empty() {
        return Ok(Export {
            mesh: TriangleMesh::default(),
            literal_tolerance: tolerance / 4.0,
            deviation: None,
            passes: 0,
        });
    }
    let mut literal_tolerance = tolerance / 4.0;
    let mut passes = 0;
    // The sampler's points, computed once for every pass.
    let mut samples = None;
    loop {
        passes += 1;
        progress(Progress::Pass {
            terms: dnf.terms.len() as u64,
        });
        let mesh = mesh_dnf(dnf, literal_tolerance, options.max_triangles, progress)?;
        if !options.verify {
            return Ok(Export {
                mesh,
                literal_tolerance,
                deviation: None,
                passes,
            });
        }
        progress(Progress::Checking);
        if samples.is_none() {
            samples = Some(
                deviation::surface_points(
                    dnf,
                    tolerance / 2.0,
                    options.sample_limits,
                    tolerance * 1e-4,
                )
                .map_err(ExportError::Sampling)?,
            );
        }
        let (points, off_surface) = samples
            .as_ref()
            .map(|(p, d)| (p.as_slice(), *d))
            .unwrap_or_default();
        let mut measured = measure_deviation_of_solid(
            dnf,
            &mesh,
            points,
            tolerance / 2.0,
            tolerance,
            tolerance / 8.0,
        );
        measured.points_off_surface = off_surface;
        if measured.hausdorff() <= tolerance {
            return Ok(Export {
                mesh,
                literal_tolerance,
                deviation: Some(measured),
                passes,
            });
        }
        if passes > REFINEMENTS && measured.interior_triangles > 0 {
            return Err(ExportError::InteriorWalls {
                triangles: measured.interior_triangles,
                measured,
            });
        }
        if passes > REFINEMENTS {
            return Err(ExportError::ToleranceNotMet {
                measured,
                tolerance,
            });
        }
        literal_tolerance /= 2.0;
    }
}

/// One pass: every term meshed at `literal_tolerance`, then their union.
fn mesh_dnf(
    dnf: &Dnf,
    literal_tolerance: f64,
    max_triangles: u64,
    progress: &(dyn Fn(Progress) + Sync),
) -> Result<TriangleMesh, ExportError> {
    let origin = dnf.bounds.centre();
    let scene = Aabb::new(dnf.bounds.min - origin, dnf.bounds.max - origin);
    let planes = sheet_planes(dnf, origin);
    let shared = growth::SharedFaces::new(dnf);
    let terms: Vec<Manifold> = dnf
        .terms
        .par_iter()
        .map(|term| {
            let context = TermContext {
                origin,
                scene,
                planes: &planes,
                shared: &shared,
                tolerance: literal_tolerance,
                max_triangles,
            };
            let result = mesh_term(dnf, term, &context);
            progress(Progress::TermDone);
            result
        })
        .collect::<Result<_, _>>()?;
    let mut solid = union_all(terms);
    check_status(&solid)?;
    // Far from the world origin, an edge shorter than a few ulps of the world coordinates
    // collapses when the mesh is moved back, leaving triangles of zero area: such edges are
    // collapsed here, where Manifold keeps the mesh manifold while it does so.
    let world_ulp = f64::EPSILON * (dnf.bounds.min.abs().max(dnf.bounds.max.abs())).max_element();
    // Where a grown face's neighbour covers only part of it, the rest stands out by the growth:
    // a step whose edges (the growth long, or longer where it meets a face at a shallow angle)
    // are collapsed here too, so that it leaves no slivers.
    let steps = if shared.any() {
        growth::STEP_COLLAPSE * growth::GROWTH * scene.half_diagonal()
    } else {
        0.0
    };
    let collapse = (64.0 * world_ulp).max(steps);
    if collapse > solid.get_epsilon() {
        let mut imp = solid.into_impl();
        imp.epsilon = collapse;
        imp.tolerance = imp.tolerance.max(collapse);
        manifold_rust::edge_op::remove_degenerates(&mut imp, 0);
        imp.sort_geometry();
        imp.invalidate_self_intersects();
        solid = Manifold::from_impl(imp);
        check_status(&solid)?;
    }
    if solid.num_tri() as u64 > max_triangles {
        return Err(ExportError::TooManyTriangles {
            quadric: u32::MAX,
            needed: solid.num_tri() as u64,
            limit: max_triangles,
        });
    }
    let gl = solid.get_mesh_glp::<f64, u32>(-1);
    let stride = gl.num_prop as usize;
    let vertices = gl
        .vert_properties
        .chunks_exact(stride)
        .map(|v| DVec3::new(v[0], v[1], v[2]) + origin)
        .collect();
    let triangles = gl
        .tri_verts
        .chunks_exact(3)
        .map(|t| [t[0], t[1], t[2]])
        .collect();
    let mut mesh = TriangleMesh {
        vertices,
        triangles,
    };
    collinear::remove_collinear(&mut mesh);
    Ok(mesh)
}

/// The union of the terms. `Manifold::batch_boolean` folds its list one by one, so the
/// growing result is copied and searched again for every term: quadratic in the terms. The CSG
/// tree's n-ary union composes the terms whose boxes are disjoint without any boolean and
/// unites the rest smallest first, as Manifold's own batch union does.
fn union_all(terms: Vec<Manifold>) -> Manifold {
    let leaves: Vec<CsgNode> = terms
        .into_iter()
        .filter(|m| !m.is_empty())
        .map(|m| CsgNode::leaf(m.into_impl()))
        .collect();
    if leaves.is_empty() {
        Manifold::empty()
    } else {
        Manifold::from_impl(CsgNode::op_n(OpType::Add, leaves).evaluate())
    }
}

/// What every term of a pass shares.
struct TermContext<'a> {
    origin: DVec3,
    scene: Aabb,
    planes: &'a [(Vec<(DVec3, f64)>, bool)],
    shared: &'a growth::SharedFaces,
    tolerance: f64,
    max_triangles: u64,
}

/// For each quadric whose sheets are planes, the half-space behind each sheet as
/// `(normal, offset)` (`normal·p ≥ offset`, relative to `origin`), from its surface's
/// representative, and whether the solid is behind every sheet.
fn sheet_planes(dnf: &Dnf, origin: DVec3) -> Vec<(Vec<(DVec3, f64)>, bool)> {
    (0..dnf.quadrics.len() as u32)
        .map(|i| {
            let Some(sheets) = dnf.surfaces.of(i) else {
                return (Vec::new(), true);
            };
            let mut planes = Vec::new();
            let mut one_sided = true;
            for sheet in sheets {
                let Some(surface) = dnf.surfaces.surface(sheet.surface) else {
                    return (Vec::new(), true);
                };
                if !surface.planar {
                    return (Vec::new(), true);
                }
                let rep = &surface.quadric;
                let g = rep.gradient(rep.origin());
                let n = g.length();
                if !(n > 0.0 && n.is_finite()) {
                    return (Vec::new(), true);
                }
                // The representative's solid is `ĝ·(p − p₀) ≤ 0`: behind it, `−ĝ·p ≥ −ĝ·p₀`.
                let normal = -g / n;
                let offset = normal.dot(rep.centre() - origin);
                planes.push(if sheet.orientation >= 0 {
                    (normal, offset)
                } else {
                    (-normal, -offset)
                });
                one_sided &= sheet.one_sided;
            }
            (planes, one_sided)
        })
        .collect()
}

fn check_status(m: &Manifold) -> Result<(), ExportError> {
    match m.status() {
        ManifoldError::NoError => Ok(()),
        other => Err(ExportError::Boolean(format!("{other:?}"))),
    }
}

/// One term: its box, cut by each literal in turn (planes first: they are exact and cheap and
/// shrink what the curved literals' booleans see).
fn mesh_term(
    dnf: &Dnf,
    term: &qcsg_csg::Term,
    context: &TermContext,
) -> Result<Manifold, ExportError> {
    let origin = context.origin;
    // The box only bounds the term: widened a little, the literals' own surfaces make every
    // face, so a face that the box's rounding would have put 10⁻¹⁴ inside a neighbour's face
    // (a mirrored part flush with another) is the literal's plane, merged by the union.
    let margin = 1e-9 * context.scene.half_diagonal();
    let bounds = Aabb::new(
        term.bounds.min - origin - DVec3::splat(margin),
        term.bounds.max - origin + DVec3::splat(margin),
    );
    let size = bounds.max - bounds.min;
    if size.min_element().is_nan() || size.min_element() <= 0.0 {
        return Ok(Manifold::empty());
    }
    let mut solid = Manifold::cube(
        manifold_rust::linalg::Vec3::new(size.x, size.y, size.z),
        false,
    )
    .translate(manifold_rust::linalg::Vec3::new(
        bounds.min.x,
        bounds.min.y,
        bounds.min.z,
    ));
    let mut literals = term.literals.clone();
    literals.sort_by_key(|&l| {
        let kind = dnf.quadrics[l as usize].quadric.kind();
        (kind != qcsg_quadric::QuadricKind::Plane, l)
    });
    // Subtracted one by one, n holes would each be cut from a mesh that already holds the
    // others: quadratic in the holes. They are united first (disjoint ones merely composed)
    // and subtracted once, after the other literals have shrunk the solid.
    let mut holes = Vec::new();
    let faces = context.shared.of_term(dnf, term);
    let growth = growth::GROWTH * context.scene.half_diagonal();
    for l in literals {
        let mut sheets = context.planes[l as usize].0.clone();
        for ((_, offset), grown) in sheets.iter_mut().zip(faces.grown(l)) {
            if grown {
                *offset -= growth;
            }
        }
        let job = literal::LiteralJob {
            quadric: &dnf.quadrics[l as usize].quadric,
            index: l,
            bounds,
            scene: context.scene,
            sheets,
            one_sided: context.planes[l as usize].1,
            origin,
            tolerance: context.tolerance,
            max_triangles: context.max_triangles,
        };
        if let Some(hole) = literal::hole(&job)? {
            holes.push(hole);
            continue;
        }
        solid = literal::apply(&solid, &job)?;
        check_status(&solid)?;
        if solid.is_empty() {
            break;
        }
    }
    if !solid.is_empty() && !holes.is_empty() {
        let cut = union_all(holes);
        check_status(&cut)?;
        solid = solid.difference(&cut);
        check_status(&solid)?;
    }
    Ok(without_flat_parts(
        solid,
        1e-12 * context.scene.half_diagonal(),
    ))
}

/// The solid without its parts of no thickness: a term cut by two planes that the compiler
/// identified as one surface, facing each other (a cube's top face and a pocket's flush top),
/// is a flat shell of zero volume, which the union would keep as a lid over the pocket. A part
/// counts as flat when its volume over its area, about half its mean thickness, is below
/// `thickness`, far below any wall the compiler keeps (10⁻¹² of the scene against walls of
/// 10⁻⁹).
fn without_flat_parts(solid: Manifold, thickness: f64) -> Manifold {
    if solid.is_empty() {
        return solid;
    }
    let flat = |m: &Manifold| m.volume() <= thickness * m.surface_area();
    if !flat(&solid) && solid.num_tri() > 0 {
        let parts = solid.decompose();
        if parts.len() <= 1 {
            return solid;
        }
        if !parts.iter().any(flat) {
            return solid;
        }
        let kept: Vec<Manifold> = parts.into_iter().filter(|m| !flat(m)).collect();
        return Manifold::compose(&kept);
    }
    Manifold::empty()
}
