//! One literal `{q ≤ 0}` of a term applied to the term's mesh: the solid is cut by the literal's
//! own closed mesh, built within a tolerance `t` of the quadric's surface.
//!
//! Every kind gets the cheapest exact-or-bounded construction:
//! - planes (and pairs of planes) are exact: the mesh is trimmed by the plane itself;
//! - ellipsoids, elliptic cylinders and cones are inscribed polyhedra (a latitude-longitude
//!   sphere, a prism, one pyramid per nappe that reaches the box) mapped by the quadric's
//!   principal frame, with every vertex on the surface and the deviation of every triangle's
//!   interior bounded in closed form (see [`sphere_deviation`]);
//! - the remaining kinds (paraboloids, hyperboloids, hyperbolic and parabolic cylinders) are
//!   meshed as a level set of the first-order distance `−q / ‖∇q‖` on a grid whose spacing comes
//!   from the smallest radius of curvature of the quadric; their deviation is what the final
//!   check of the whole mesh measures.
//!
//! A literal whose solid is the inside of the tessellated solid intersects the term with it, its
//! complement subtracts it. Coordinates are relative to the scene's centre (`origin`), so that
//! Manifold's tolerances, which are relative to the coordinates' size, stay small.

use manifold_rust::linalg::Vec3;
use manifold_rust::manifold::Manifold;
use manifold_rust::sdf::level_set;
use manifold_rust::types::{Box as MBox, MeshGLP};
use qcsg_csg::Aabb;
use qcsg_quadric::{DVec3, PrincipalFrame, Quadric, QuadricKind, Tolerances, classify_frame};

use crate::ExportError;

/// What a literal needs to be meshed: the quadric, the term's box (relative to `origin`), the
/// tolerance and the triangle budget of one literal.
pub(crate) struct LiteralJob<'a> {
    /// The world quadric; the literal is `quadric ≤ 0`.
    pub quadric: &'a Quadric,
    /// Its index in the DNF, for diagnostics.
    pub index: u32,
    /// The term's box, relative to `origin`.
    pub bounds: Aabb,
    /// The scene's box, relative to `origin`: curved meshes take their resolution from it, so
    /// that one surface in several terms is meshed alike there.
    pub scene: Aabb,
    /// The planes of the quadric's sheets as the compiler identified them: each the half-space
    /// `normal·p ≥ offset` behind the sheet, computed from the surface's one representative, so
    /// that coincident faces of different terms are the same plane to the bit. Empty for
    /// curved quadrics.
    pub sheets: Vec<(DVec3, f64)>,
    /// Whether the solid lies behind every sheet (a half-space, a slab) rather than behind any
    /// (a slab's complement).
    pub one_sided: bool,
    /// The scene's centre: mesh coordinates are world coordinates minus it.
    pub origin: DVec3,
    /// The largest distance allowed between the literal's mesh and its surface.
    pub tolerance: f64,
    /// The most triangles one literal's mesh may have.
    pub max_triangles: u64,
}

fn v3(p: DVec3) -> Vec3 {
    Vec3::new(p.x, p.y, p.z)
}

/// Whether [`apply`] meshes a quadric of this kind as a level set: the kinds with no
/// closed-form inscribed polyhedron, which cost far more triangles and time than the others.
pub fn meshed_as_level_set(kind: QuadricKind) -> bool {
    use QuadricKind as K;
    matches!(
        kind,
        K::HyperbolicCylinder
            | K::ParabolicCylinder
            | K::HyperboloidOneSheet
            | K::HyperboloidTwoSheets
            | K::EllipticParaboloid
            | K::HyperbolicParaboloid
    )
}

/// How many of the solid's quadrics [`apply`] meshes as level sets.
pub fn level_set_surfaces(dnf: &qcsg_csg::Dnf) -> usize {
    dnf.quadrics
        .iter()
        .filter(|q| meshed_as_level_set(q.quadric.kind()))
        .count()
}

/// Applies the literal to `solid` (the term so far).
pub(crate) fn apply(solid: &Manifold, job: &LiteralJob) -> Result<Manifold, ExportError> {
    let q = job.quadric;
    let frame = PrincipalFrame::new(q, &Tolerances::default());
    let kind = classify_frame(&frame, &Tolerances::default());
    let centre = frame.centre - job.origin;
    let inside_at = |p: DVec3| q.value(p + job.origin) < 0.0;
    use QuadricKind as K;
    Ok(match kind {
        K::Empty => Manifold::empty(),
        K::AllSpace => solid.clone(),
        // Solids of no volume (a point, a line, a doubled plane) or all space but them.
        K::Point | K::Line | K::CoincidentPlanes => {
            let off = centre + frame.axes[0] + frame.axes[1] + frame.axes[2];
            if inside_at(off) {
                solid.clone()
            } else {
                Manifold::empty()
            }
        }
        K::Plane | K::ParallelPlanes if !job.sheets.is_empty() => {
            if job.one_sided {
                job.sheets.iter().fold(solid.clone(), |m, &(n, offset)| {
                    m.trim_by_plane(v3(n), offset)
                })
            } else {
                job.sheets
                    .iter()
                    .map(|&(n, offset)| solid.trim_by_plane(v3(n), offset))
                    .reduce(|a, b| a.union(&b))
                    .unwrap_or_else(Manifold::empty)
            }
        }
        K::Plane => {
            let c = job.bounds.centre();
            let g = q.gradient(c + job.origin);
            let v = q.value(c + job.origin);
            let n = g.length();
            if !(n > 0.0 && n.is_finite()) {
                return Ok(if v <= 0.0 {
                    solid.clone()
                } else {
                    Manifold::empty()
                });
            }
            // g·(p − c) + v ≤ 0  ⇔  (−ĝ)·p ≥ (v − g·c) / |g|.
            solid.trim_by_plane(v3(-g / n), (v - g.dot(c)) / n)
        }
        K::ParallelPlanes => {
            let k = (0..3).find(|&k| frame.eigenvalues[k] != 0.0).unwrap_or(0);
            let u = frame.axes[k];
            let w = (frame.constant / frame.eigenvalues[k]).abs().sqrt();
            let c = centre.dot(u);
            if inside_at(centre) {
                solid
                    .trim_by_plane(v3(u), c - w)
                    .trim_by_plane(v3(-u), -(c + w))
            } else {
                solid
                    .trim_by_plane(v3(u), c + w)
                    .union(&solid.trim_by_plane(v3(-u), -(c - w)))
            }
        }
        K::IntersectingPlanes => {
            let a = (0..3).find(|&k| frame.eigenvalues[k] > 0.0).unwrap_or(0);
            let b = (0..3).find(|&k| frame.eigenvalues[k] < 0.0).unwrap_or(1);
            let (ua, ub) = (frame.axes[a], frame.axes[b]);
            let (sa, sb) = (frame.eigenvalues[a].sqrt(), (-frame.eigenvalues[b]).sqrt());
            // q = f1·f2 with f1 = n1·(p − c), f2 = n2·(p − c): q ≤ 0 where they differ in sign.
            let n1 = (sa * ua - sb * ub).normalize();
            let n2 = (sa * ua + sb * ub).normalize();
            let (o1, o2) = (n1.dot(centre), n2.dot(centre));
            let first = solid.trim_by_plane(v3(-n1), -o1).trim_by_plane(v3(n2), o2);
            let second = solid.trim_by_plane(v3(n1), o1).trim_by_plane(v3(-n2), -o2);
            first.union(&second)
        }
        K::Sphere | K::Spheroid | K::Ellipsoid => {
            let mesh = ellipsoid(&frame, centre, job)?;
            combine(solid, &mesh, inside_at(centre))
        }
        K::EllipticCylinder => {
            let mesh = cylinder(&frame, centre, job)?;
            combine(solid, &mesh, inside_at(centre))
        }
        K::Cone => cone(solid, &frame, centre, job, &inside_at)?,
        K::HyperbolicCylinder
        | K::ParabolicCylinder
        | K::HyperboloidOneSheet
        | K::HyperboloidTwoSheets
        | K::EllipticParaboloid
        | K::HyperbolicParaboloid => {
            let mesh = level_set_mesh(&frame, job)?;
            solid.intersection(&mesh)
        }
    })
}

/// The closed mesh that the literal cuts out of the term, when it is the outside of an
/// ellipsoid or an elliptic cylinder (a ball or a hole subtracted); `None` for every other
/// literal, which [`apply`] applies. The term subtracts all its holes at once.
pub(crate) fn hole(job: &LiteralJob) -> Result<Option<Manifold>, ExportError> {
    let q = job.quadric;
    let frame = PrincipalFrame::new(q, &Tolerances::default());
    let kind = classify_frame(&frame, &Tolerances::default());
    let centre = frame.centre - job.origin;
    // As `apply` decides it, so that a literal is a hole exactly where `apply` would subtract.
    if q.value(centre + job.origin) < 0.0 {
        return Ok(None);
    }
    use QuadricKind as K;
    Ok(match kind {
        K::Sphere | K::Spheroid | K::Ellipsoid => Some(ellipsoid(&frame, centre, job)?),
        K::EllipticCylinder => Some(cylinder(&frame, centre, job)?),
        _ => None,
    })
}

/// Intersects with `mesh` when the literal's solid is its inside, else subtracts it.
fn combine(solid: &Manifold, mesh: &Manifold, inside: bool) -> Manifold {
    if inside {
        solid.intersection(mesh)
    } else {
        solid.difference(mesh)
    }
}

/// The largest distance from a triangle with corners on the unit sphere and longest edge `d` to
/// the sphere, scaled by the largest semi-axis `a` of the ellipsoid the sphere is mapped to.
///
/// A point `p = Σ λᵢ xᵢ` of the triangle has `|p|² = 1 − ½ Σᵢⱼ λᵢλⱼ |xᵢ − xⱼ|² ≥ 1 − d²/3`
/// (as `Σ_{i≠j} λᵢλⱼ ≤ 2/3`); its radial projection onto the sphere is `(1 − |p|)` away, and
/// the linear map to the ellipsoid stretches that by at most `a`.
pub(crate) fn sphere_deviation(a: f64, d: f64) -> f64 {
    a * (1.0 - (1.0 - d * d / 3.0).max(0.0).sqrt())
}

fn too_many(job: &LiteralJob, triangles: f64) -> ExportError {
    ExportError::TooManyTriangles {
        quadric: job.index,
        needed: if triangles.is_finite() {
            triangles as u64
        } else {
            u64::MAX
        },
        limit: job.max_triangles,
    }
}

/// Builds a Manifold from vertices and triangles, turning the triangles over when the signed
/// volume is negative (the constructions below are oriented by the frame's handedness).
fn manifold_of(vertices: &[DVec3], mut triangles: Vec<[u32; 3]>) -> Manifold {
    let volume: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            a.dot(b.cross(c))
        })
        .sum();
    if volume < 0.0 {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    let mesh: MeshGLP<f64, u32> = MeshGLP {
        num_prop: 3,
        vert_properties: vertices.iter().flat_map(|v| v.to_array()).collect(),
        tri_verts: triangles.into_iter().flatten().collect(),
        ..Default::default()
    };
    Manifold::from_mesh_glp(&mesh)
}

/// An ellipsoid as a latitude-longitude sphere mapped by the frame, refined until
/// [`sphere_deviation`] of its longest edge is within the tolerance.
fn ellipsoid(
    frame: &PrincipalFrame,
    centre: DVec3,
    job: &LiteralJob,
) -> Result<Manifold, ExportError> {
    let axes = frame.semi_axes();
    let a = axes.iter().fold(0.0f64, |m, s| m.max(*s));
    if !(a.is_finite() && a > 0.0) {
        return Ok(Manifold::empty());
    }
    let t = job.tolerance.min(a);
    // Longest edge ≈ √2 π / n for n latitude bands; d² ≤ 6t/a keeps the deviation within t.
    let mut n = ((2f64.sqrt() * std::f64::consts::PI) / (6.0 * t / a).sqrt())
        .ceil()
        .max(3.0);
    loop {
        if 4.0 * n * n > job.max_triangles as f64 {
            return Err(too_many(job, 4.0 * n * n));
        }
        let bands = n as usize;
        let (unit, triangles) = uv_sphere(bands, 2 * bands);
        let longest = longest_edge(&unit, &triangles);
        if sphere_deviation(a, longest) <= t {
            let vertices: Vec<DVec3> = unit
                .iter()
                .map(|y| {
                    centre
                        + y.x * axes[0] * frame.axes[0]
                        + y.y * axes[1] * frame.axes[1]
                        + y.z * axes[2] * frame.axes[2]
                })
                .collect();
            return Ok(manifold_of(&vertices, triangles));
        }
        n = (n * 1.25).ceil();
    }
}

fn longest_edge(vertices: &[DVec3], triangles: &[[u32; 3]]) -> f64 {
    triangles
        .iter()
        .flat_map(|t| {
            let [a, b, c] = t.map(|i| vertices[i as usize]);
            [(a - b).length(), (b - c).length(), (c - a).length()]
        })
        .fold(0.0, f64::max)
}

/// A unit sphere with `bands` latitude bands and `segments` meridians (poles as single
/// vertices).
fn uv_sphere(bands: usize, segments: usize) -> (Vec<DVec3>, Vec<[u32; 3]>) {
    let mut vertices = vec![DVec3::Z];
    for i in 1..bands {
        let theta = std::f64::consts::PI * i as f64 / bands as f64;
        for j in 0..segments {
            let phi = std::f64::consts::TAU * j as f64 / segments as f64;
            vertices.push(DVec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            ));
        }
    }
    vertices.push(-DVec3::Z);
    let south = (vertices.len() - 1) as u32;
    let ring = |i: usize, j: usize| (1 + (i - 1) * segments + j % segments) as u32;
    let mut triangles = Vec::with_capacity(2 * bands * segments);
    for j in 0..segments {
        triangles.push([0, ring(1, j), ring(1, j + 1)]);
        triangles.push([south, ring(bands - 1, j + 1), ring(bands - 1, j)]);
    }
    for i in 1..bands - 1 {
        for j in 0..segments {
            let (a, b, c, d) = (
                ring(i, j),
                ring(i, j + 1),
                ring(i + 1, j),
                ring(i + 1, j + 1),
            );
            triangles.push([a, c, d]);
            triangles.push([a, d, b]);
        }
    }
    (vertices, triangles)
}

/// The number of sides of a polygon inscribed in an ellipse of largest semi-axis `a` whose
/// sides stay within `t` of it (`a (1 − cos(π/n)) ≤ t`, the unit-circle sagitta stretched by at
/// most `a`).
fn polygon_sides(a: f64, t: f64) -> f64 {
    let c = 1.0 - (t / a).min(1.0);
    (std::f64::consts::PI / c.acos()).ceil().max(3.0)
}

/// The extent of the box (with a margin) along `axis` from `centre`.
fn extent(bounds: &Aabb, centre: DVec3, axis: DVec3) -> (f64, f64) {
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for corner in bounds.corners() {
        let h = (corner - centre).dot(axis);
        lo = lo.min(h);
        hi = hi.max(h);
    }
    let margin = 0.05 * (hi - lo) + 1e-9 * (lo.abs() + hi.abs()).max(1.0);
    (lo - margin, hi + margin)
}

/// A closed prism or pyramid: a base polygon at `base(i)`, `n` sides, and either a top polygon
/// or an apex.
fn extrusion(base: &[DVec3], top: Option<&[DVec3]>, apex: DVec3) -> Manifold {
    let n = base.len();
    let mut vertices: Vec<DVec3> = base.to_vec();
    let mut triangles = Vec::new();
    let base_centre = base.iter().copied().sum::<DVec3>() / n as f64;
    vertices.push(base_centre);
    let bc = n as u32;
    for i in 0..n {
        let (a, b) = (i as u32, ((i + 1) % n) as u32);
        triangles.push([bc, b, a]);
    }
    match top {
        Some(top) => {
            let first = vertices.len() as u32;
            vertices.extend_from_slice(top);
            let tc = vertices.len() as u32;
            vertices.push(top.iter().copied().sum::<DVec3>() / n as f64);
            for i in 0..n {
                let (a, b) = (i as u32, ((i + 1) % n) as u32);
                let (ta, tb) = (first + a, first + b);
                triangles.push([tc, ta, tb]);
                triangles.push([a, b, tb]);
                triangles.push([a, tb, ta]);
            }
        }
        None => {
            let ap = vertices.len() as u32;
            vertices.push(apex);
            for i in 0..n {
                let (a, b) = (i as u32, ((i + 1) % n) as u32);
                triangles.push([a, b, ap]);
            }
        }
    }
    manifold_of(&vertices, triangles)
}

/// An elliptic cylinder as an inscribed prism reaching past the box.
fn cylinder(
    frame: &PrincipalFrame,
    centre: DVec3,
    job: &LiteralJob,
) -> Result<Manifold, ExportError> {
    let axes = frame.semi_axes();
    let along = (0..3).find(|&k| frame.eigenvalues[k] == 0.0).unwrap_or(2);
    let (i, j) = ((along + 1) % 3, (along + 2) % 3);
    let a = axes[i].max(axes[j]);
    if !(a.is_finite() && a > 0.0) {
        return Ok(Manifold::empty());
    }
    let n = polygon_sides(a, job.tolerance);
    if 4.0 * n > job.max_triangles as f64 {
        return Err(too_many(job, 4.0 * n));
    }
    let axis = frame.axes[along];
    let (lo, hi) = extent(&job.scene, centre, axis);
    let ring = |h: f64| -> Vec<DVec3> {
        (0..n as usize)
            .map(|k| {
                let phi = std::f64::consts::TAU * k as f64 / n;
                centre
                    + h * axis
                    + phi.cos() * axes[i] * frame.axes[i]
                    + phi.sin() * axes[j] * frame.axes[j]
            })
            .collect()
    };
    let top = ring(hi);
    Ok(extrusion(&ring(lo), Some(&top), DVec3::ZERO))
}

/// A double cone: one inscribed pyramid per nappe that reaches into the box, each long enough to
/// leave it; the literal intersects with their union or subtracts it.
fn cone(
    solid: &Manifold,
    frame: &PrincipalFrame,
    apex: DVec3,
    job: &LiteralJob,
    inside_at: &dyn Fn(DVec3) -> bool,
) -> Result<Manifold, ExportError> {
    let lambda = frame.eigenvalues;
    let positive = lambda.iter().filter(|v| **v > 0.0).count();
    // The axis is the eigenvalue whose sign is in the minority.
    let along = if positive == 1 {
        (0..3).find(|&k| lambda[k] > 0.0)
    } else {
        (0..3).find(|&k| lambda[k] < 0.0)
    }
    .unwrap_or(2);
    let (i, j) = ((along + 1) % 3, (along + 2) % 3);
    let slope_i = (lambda[along] / lambda[i]).abs().sqrt();
    let slope_j = (lambda[along] / lambda[j]).abs().sqrt();
    let axis = frame.axes[along];
    let (lo, hi) = extent(&job.bounds, apex, axis);
    // The pyramids reach past the whole scene, and their number of sides follows from that
    // length, so that one cone in several terms is the same polyhedron.
    let (scene_lo, scene_hi) = extent(&job.scene, apex, axis);
    let scale = job.bounds.half_diagonal().max(apex.length());
    let mut nappes = Vec::new();
    let mut inside = None;
    for sign in [1.0, -1.0] {
        let reach_term = if sign > 0.0 { hi } else { -lo };
        if reach_term <= 1e-12 * scale {
            continue;
        }
        let reach = if sign > 0.0 { scene_hi } else { -scene_lo }.max(reach_term);
        let a = reach * slope_i.max(slope_j);
        let n = polygon_sides(a, job.tolerance);
        if 2.0 * n > job.max_triangles as f64 {
            return Err(too_many(job, 2.0 * n));
        }
        let base: Vec<DVec3> = (0..n as usize)
            .map(|k| {
                let phi = std::f64::consts::TAU * k as f64 / n;
                apex + sign * reach * axis
                    + reach
                        * (phi.cos() * slope_i * frame.axes[i]
                            + phi.sin() * slope_j * frame.axes[j])
            })
            .collect();
        inside.get_or_insert_with(|| inside_at(apex + sign * 0.5 * reach * axis));
        nappes.push(extrusion(&base, None, apex));
    }
    let Some(inside) = inside else {
        // The box reaches neither nappe: the literal holds nowhere or everywhere there.
        return Ok(if inside_at(apex + axis + frame.axes[i]) {
            solid.clone()
        } else {
            Manifold::empty()
        });
    };
    let mesh = match nappes.len() {
        1 => nappes.pop().unwrap_or_default(),
        _ => nappes[0].union(&nappes[1]),
    };
    Ok(combine(solid, &mesh, inside))
}

/// The smallest radius of curvature a quadric of these semi-axes and linear terms can have: the
/// smallest `sᵢ² / sⱼ` over finite semi-axes (a hyperbola's vertex, an ellipse's end), and
/// `|mₖ| / |λᵢ|` at a paraboloid's vertex.
fn smallest_curvature_radius(frame: &PrincipalFrame) -> f64 {
    let s = frame.semi_axes();
    let mut r = f64::INFINITY;
    for &a in &s {
        for &b in &s {
            if a.is_finite() && b.is_finite() && a > 0.0 && b > 0.0 {
                r = r.min(a * a / b);
            }
        }
    }
    let m = frame.linear.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    if m > 0.0 {
        for &l in &frame.eigenvalues {
            if l != 0.0 {
                r = r.min(m / l.abs());
            }
        }
    }
    r
}

/// How many times [`curvature_radius_in`] halves a box that the surface crosses.
const CURVATURE_DEPTH: u32 = 5;

/// A lower bound on the radius of curvature of the quadric's surface inside `bounds` (relative
/// to `origin`), at least `global` (the smallest over the whole surface).
///
/// A normal curvature is `vᵀHv / ‖∇q‖ ≤ ‖H‖ / ‖∇q‖` for the constant Hessian `H`, and over a
/// box of centre `c` and half-diagonal `R`, `‖∇q‖ ≥ ‖∇q(c)‖ − ‖H‖R`; boxes that the surface
/// cannot reach (`|q(c)| > ‖∇q(c)‖R + ½‖H‖R²`) are dropped and the others halved until that
/// bound is at least half of `‖∇q(c)‖`. A paraboloid that is nearly a cylinder (the hull of balls
/// of nearly equal radii) has its vertex, where the curvature is sharp, some 10⁹ lengths away:
/// only the box decides the grid.
fn curvature_radius_in(q: &Quadric, origin: DVec3, bounds: &Aabb, global: f64) -> f64 {
    // The gradient is affine: its differences along the axes are the Hessian's columns.
    let at = q.origin();
    let g0 = q.gradient(at);
    let hessian = [DVec3::X, DVec3::Y, DVec3::Z]
        .map(|e| q.gradient(at + e) - g0)
        .iter()
        .map(|c| c.length_squared())
        .sum::<f64>()
        .sqrt();
    if !(hessian > 0.0 && hessian.is_finite()) {
        return f64::INFINITY;
    }
    let mut smallest = f64::INFINITY;
    let mut stack = vec![(*bounds, 0u32)];
    while let Some((b, depth)) = stack.pop() {
        let c = b.centre();
        let r = b.half_diagonal();
        let g = q.gradient(c + origin).length();
        let v = q.value(c + origin).abs();
        if v > g * r + 0.5 * hessian * r * r {
            continue;
        }
        let lower = g - hessian * r;
        if lower >= 0.5 * g && lower > 0.0 {
            smallest = smallest.min(lower / hessian);
        } else if depth < CURVATURE_DEPTH {
            let (lo, hi) = (b.min, b.max);
            for k in 0..8 {
                let pick = |bit: usize, l: f64, m: f64, h: f64| {
                    if k >> bit & 1 == 0 { (l, m) } else { (m, h) }
                };
                let (x0, x1) = pick(0, lo.x, c.x, hi.x);
                let (y0, y1) = pick(1, lo.y, c.y, hi.y);
                let (z0, z1) = pick(2, lo.z, c.z, hi.z);
                stack.push((
                    Aabb::new(DVec3::new(x0, y0, z0), DVec3::new(x1, y1, z1)),
                    depth + 1,
                ));
            }
        } else {
            smallest = smallest.min(global.max(lower / hessian));
        }
    }
    smallest.max(global)
}

/// The literal's solid inside the box (with a margin) as a level set of `−q / ‖∇q‖`.
fn level_set_mesh(frame: &PrincipalFrame, job: &LiteralJob) -> Result<Manifold, ExportError> {
    let size = job.bounds.max - job.bounds.min;
    let largest = size.max_element();
    let global = smallest_curvature_radius(frame);
    // Curvature sharper than the tolerance (a hyperboloid's neck 10⁻³ wide meshed to 10⁻²) is a
    // feature the tolerance allows to be cut through: the grid stops at the tolerance's scale
    // there, and the check refines it when that is not enough.
    let radius = curvature_radius_in(job.quadric, job.origin, &job.bounds, global)
        .max(job.tolerance)
        .min(largest);
    // A triangle of diameter h on a surface of curvature radius ρ lies within h² / (6ρ) of it.
    let h = (3.0 * job.tolerance * radius)
        .sqrt()
        .min(largest / 4.0)
        .max(1e-300);
    let margin = 2.0 * h;
    let cells = ((size.x + 2.0 * margin) / h)
        * ((size.y + 2.0 * margin) / h)
        * ((size.z + 2.0 * margin) / h);
    // A surface crosses about (L/h)² cells of a grid of (L/h)³; each gives a few triangles.
    let estimate = 4.0 * cells.powf(2.0 / 3.0);
    if estimate > job.max_triangles as f64 || cells > 64.0 * job.max_triangles as f64 {
        return Err(too_many(job, estimate));
    }
    let lo = job.bounds.min - DVec3::splat(margin);
    let hi = job.bounds.max + DVec3::splat(margin);
    let q = *job.quadric;
    let origin = job.origin;
    let distance = move |p: Vec3| {
        let w = DVec3::new(p.x, p.y, p.z) + origin;
        let g = q.gradient(w).length();
        let v = q.value(w);
        if g > 0.0 { -v / g } else { -v.signum() * h }
    };
    let imp = level_set(
        distance,
        MBox::from_points(v3(lo), v3(hi)),
        h,
        0.0,
        job.tolerance / 16.0,
    );
    Ok(Manifold::from_impl(imp))
}
