//! The live preview's two questions about a compiled scene: the image seen through a camera (the
//! pixels `qcsg render` makes with the same arguments) and what one pixel of it shows (the
//! primitive's call, the chain of module calls that led to it, the quadric and the term).
//!
//! `qcsg view` serves both over HTTP and the language server answers them as the custom requests
//! `qcsg/frame` and `qcsg/pick`, so both front ends give the same answers. A [`Preview`] is built
//! once per compiled scene and answers any number of requests.
//!
//! The chain of calls is read back from the DAG: the path from the root down to a leaf made by
//! the picked call, through the world transforms of its edges, that passes closest to the picked
//! point (a part instantiated several times is one leaf under several transforms), and the user
//! module calls that produced the nodes of that path ([`qcsg_eval::Evaluation::instantiations`]),
//! ordered so that each call is written inside the module the previous one called. Nodes are
//! hash-consed: two calls that build exactly the same solid at the same place share a node, and
//! the chain then names the first of them in source order.

use std::collections::HashMap;

use qcsg_csg::{Dag, DnfQuadric, Edge, Layers, NodeId, NodeKind, Source};
use qcsg_diag::{FileId, LineCol, SourceMap, Span};
use qcsg_quadric::{DMat4, DVec3};
use qcsg_render::raytrace::Scratch;
use qcsg_render::scene::Layer;
use qcsg_render::{Camera, CameraError, Frame, ImageSize, Projection, RenderOptions, Scene, View};
use qcsg_sema::{Analysis, DefKind, Namespace, Target};
use serde::Serialize;

/// How many root-to-leaf paths a pick follows at most when it looks for the instance it hit.
const MAX_PICK_PATHS: usize = 10_000;

/// The colour blended half-and-half over the parts under the editor's cursor.
const CURSOR_TINT: [u8; 3] = [255, 140, 0];

/// What to look at: the arguments `qcsg render` takes for the same image.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewRequest {
    /// The image size.
    pub size: ImageSize,
    /// A named view fitted to the scene, or an explicit eye and centre.
    pub view: View,
    /// Perspective or orthographic.
    pub projection: Projection,
}

impl ViewRequest {
    /// The camera for this request, fitted to `scene` as `qcsg render` fits it.
    pub fn camera(&self, scene: &Scene) -> Result<Camera, CameraError> {
        Camera::fit(&self.view, self.projection, &scene.bounds(), self.size)
    }
}

/// A position as in LSP: zero-based line, character in UTF-16 code units.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Position {
    /// Zero-based line.
    pub line: u32,
    /// Zero-based UTF-16 column.
    pub character: u32,
}

/// A range of positions.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct Range {
    /// Where it starts.
    pub start: Position,
    /// Where it ends (exclusive).
    pub end: Position,
}

/// A place in the sources, as tools want it: the file's name, the UTF-16 range and the bytes.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Place {
    /// The file's name as the pipeline read it.
    pub file: String,
    /// Zero-based lines, UTF-16 characters.
    pub range: Range,
    /// The same span in bytes, `[start, end)`.
    pub byte_range: [u32; 2],
}

/// One module call of a pick's chain.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct Call {
    /// The module called.
    pub module: String,
    /// The whole call statement.
    #[serde(flatten)]
    pub place: Place,
}

/// What one pixel shows.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Picked {
    /// `solid`, `highlight` (a `#` part) or `background` (a `%` part).
    pub layer: &'static str,
    /// The primitive's call statement; `None` on a face of a term's box (a solid cut off by
    /// the normal form's region), which no call made.
    #[serde(flatten)]
    pub place: Option<Place>,
    /// The user module calls that led to the primitive, outermost first.
    pub chain: Vec<Call>,
    /// The quadric's index in the layer's DNF (`None` on a box face).
    pub quadric: Option<u32>,
    /// The term's index in the layer's DNF.
    pub term: u32,
    /// The world-space point seen.
    pub point: [f64; 3],
}

/// A user module call statement and the module it calls.
#[derive(Clone, Debug)]
struct CallSite {
    statement: Source,
    module: String,
    /// The module's definition (whole statement), in which the calls it makes are written.
    definition: Source,
}

/// A compiled scene, ready to render frames and answer picks.
#[derive(Debug)]
pub struct Preview {
    scene: Scene,
    sources: SourceMap,
    /// The user module calls that produced each node.
    calls: HashMap<NodeId, Vec<CallSite>>,
    /// Every module definition's span, to tell a top-level call from one inside a module.
    modules: Vec<Source>,
}

impl Preview {
    /// The preview of a scene compiled without error: its DNF layers, and which DAG node each
    /// instantiation statement produced, with the analysis that names them. The DAG itself
    /// stays with the evaluation, and a pick is handed it: a copy here doubled the memory a
    /// document's geometry takes.
    pub fn new(analysis: &Analysis, layers: Layers, instantiations: &[(Source, NodeId)]) -> Self {
        let modules = analysis
            .definitions
            .iter()
            .filter(|d| d.kind == DefKind::Module)
            .map(|d| Source::new(d.file, d.span))
            .collect();
        let mut references: Vec<_> = analysis
            .references
            .iter()
            .filter(|r| r.namespace == Namespace::Module)
            .filter_map(|r| match r.target {
                Target::Definition(def) => Some((r.file, r.span, def)),
                _ => None,
            })
            .collect();
        references.sort_unstable_by_key(|&(file, span, _)| (file, span.start));
        let mut calls: HashMap<NodeId, Vec<CallSite>> = HashMap::new();
        for &(statement, node) in instantiations {
            let Some(site) = call_site(analysis, &references, statement) else {
                continue;
            };
            calls.entry(node).or_default().push(site);
        }
        for sites in calls.values_mut() {
            sites.sort_unstable_by_key(|s| (s.statement.file, s.statement.span.start));
        }
        Self {
            scene: Scene::from_layers(layers),
            sources: analysis.sources.clone(),
            calls,
            modules,
        }
    }

    /// The scene drawn.
    pub fn scene(&self) -> &Scene {
        &self.scene
    }

    /// The sources of the scene.
    pub fn sources(&self) -> &SourceMap {
        &self.sources
    }

    /// Renders the frame of `request` with the CPU ray tracer, on the current rayon pool.
    pub fn render(&self, request: &ViewRequest) -> Result<Frame, CameraError> {
        let camera = request.camera(&self.scene)?;
        Ok(qcsg_render::render(
            &self.scene,
            &camera,
            request.size,
            &RenderOptions::default(),
            &|_| {},
        ))
    }

    /// [`Preview::render`] with the parts made by `quadrics` (indices of the solid's DNF)
    /// tinted, for the editor's cursor.
    pub fn render_highlighted(
        &self,
        request: &ViewRequest,
        quadrics: &[u32],
    ) -> Result<Frame, CameraError> {
        let mut frame = self.render(request)?;
        if quadrics.is_empty() {
            return Ok(frame);
        }
        let tinted: std::collections::HashSet<u32> = quadrics.iter().copied().collect();
        for (i, id) in frame.ids.iter().enumerate() {
            if tinted.contains(&id.quadric) {
                for (channel, tint) in frame.rgb[3 * i..3 * i + 3].iter_mut().zip(CURSOR_TINT) {
                    *channel = ((u16::from(*channel) + u16::from(tint)) / 2) as u8;
                }
            }
        }
        Ok(frame)
    }

    /// What pixel `(x, y)` of the frame of `request` shows (the ray through its centre, as the
    /// frame traces it): the nearest surface of any layer, `None` for the background; `dag` is
    /// the scene's DAG, which the chain of module calls is found in.
    pub fn pick(
        &self,
        dag: &Dag,
        request: &ViewRequest,
        x: u32,
        y: u32,
    ) -> Result<Option<Picked>, CameraError> {
        let camera = request.camera(&self.scene)?;
        let ray = camera.ray(f64::from(x) + 0.5, f64::from(y) + 0.5, request.size);
        let mut scratch = Scratch::default();
        let layers = [
            ("solid", &self.scene.solid),
            ("highlight", &self.scene.highlights),
            ("background", &self.scene.backgrounds),
        ];
        let nearest = layers
            .into_iter()
            .filter_map(|(name, layer)| {
                let layer = layer.as_ref()?;
                let hit = qcsg_render::trace(layer.dnf(), layer.index(), &ray, 0.0, &mut scratch)?;
                Some((name, layer, hit))
            })
            .min_by(|a, b| a.2.t.total_cmp(&b.2.t));
        let Some((name, layer, hit)) = nearest else {
            return Ok(None);
        };
        let quadric: Option<&DnfQuadric> = hit.quadric.and_then(|q| layer_quadric(layer, q));
        let place = quadric.map(|q| self.place(q.source));
        let chain = quadric
            .map(|q| self.chain(dag, q.source, hit.point, name == "background"))
            .unwrap_or_default();
        Ok(Some(Picked {
            layer: name,
            place,
            chain,
            quadric: hit.quadric,
            term: hit.term,
            point: hit.point.to_array(),
        }))
    }

    /// The place of `source` for tools.
    pub fn place(&self, source: Source) -> Place {
        place(&self.sources, source)
    }

    /// The calls of every primitive whose statement covers byte `offset` of `file` (the parts
    /// an editor's cursor is on): the quadric indices of the solid's DNF made by it.
    pub fn quadrics_at(&self, file: FileId, offset: u32) -> Vec<u32> {
        let Some(solid) = &self.scene.solid else {
            return Vec::new();
        };
        let inside = |s: Source| s.file == file && s.span.start <= offset && offset < s.span.end;
        // The innermost statement under the cursor that made a quadric.
        let innermost = solid
            .dnf()
            .quadrics
            .iter()
            .map(|q| q.source)
            .filter(|&s| inside(s))
            .min_by_key(|s| s.span.len());
        let Some(innermost) = innermost else {
            return Vec::new();
        };
        (0..solid.dnf().quadrics.len() as u32)
            .filter(|&i| solid.dnf().quadrics[i as usize].source == innermost)
            .collect()
    }

    /// The module calls that led to the leaf made by `source` and seen at `point`: the path
    /// from the root to such a leaf whose surface passes closest to the point.
    fn chain(&self, dag: &Dag, source: Source, point: DVec3, background: bool) -> Vec<Call> {
        let roots: Vec<Edge> = if background {
            dag.backgrounds().to_vec()
        } else {
            dag.root().into_iter().collect()
        };
        let reaches = Self::reaches(dag, source);
        let mut best: Option<(f64, Vec<NodeId>)> = None;
        let mut paths = 0;
        // Depth-first over (edge, world transform, path length) with one shared path.
        let mut path: Vec<NodeId> = Vec::new();
        let mut stack: Vec<(Edge, DMat4, usize)> = roots
            .iter()
            .rev()
            .map(|&e| (e, DMat4::IDENTITY, 0))
            .collect();
        while let Some((edge, above, depth)) = stack.pop() {
            if !reaches[edge.child.0 as usize] || paths >= MAX_PICK_PATHS {
                continue;
            }
            path.truncate(depth);
            path.push(edge.child);
            let world = above * dag.matrix(edge.transform);
            let Some(node) = dag.node(edge.child) else {
                continue;
            };
            if let NodeKind::Leaf(quadric) = &node.kind {
                paths += 1;
                let local = world.inverse().transform_point3(point);
                let gradient = quadric.gradient(local).length();
                let distance = if gradient > 0.0 {
                    quadric.value(local).abs() / gradient
                } else {
                    f64::INFINITY
                };
                if best.as_ref().is_none_or(|(d, _)| distance < *d) {
                    best = Some((distance, path.clone()));
                }
                continue;
            }
            for &child in node.kind.children().iter().rev() {
                stack.push((child, world, depth + 1));
            }
        }
        let Some((_, path)) = best else {
            return Vec::new();
        };
        self.calls_along(&path)
    }

    /// Per node, whether a leaf made by `source` lies below it (or is it).
    fn reaches(dag: &Dag, source: Source) -> Vec<bool> {
        // Children are created before their parents, so one pass in creation order suffices.
        let mut reaches = vec![false; dag.len()];
        for (i, node) in dag.nodes().iter().enumerate() {
            reaches[i] = match &node.kind {
                NodeKind::Leaf(_) => node.source == source,
                kind => kind
                    .children()
                    .iter()
                    .any(|e| reaches.get(e.child.0 as usize).copied().unwrap_or(false)),
            };
        }
        reaches
    }

    /// The user module calls that produced the nodes of `path`, each written inside the module
    /// the one before it called (the first at a top level).
    fn calls_along(&self, path: &[NodeId]) -> Vec<Call> {
        let candidates: Vec<&CallSite> = path
            .iter()
            .filter_map(|node| self.calls.get(node))
            .flatten()
            .collect();
        let mut chain: Vec<&CallSite> = Vec::new();
        loop {
            let next = candidates.iter().find(|site| {
                !chain.iter().any(|c| c.statement == site.statement)
                    && match chain.last() {
                        Some(previous) => within(site.statement, previous.definition),
                        None => !self.modules.iter().any(|&m| within(site.statement, m)),
                    }
            });
            match next {
                Some(site) => chain.push(site),
                None => break,
            }
        }
        chain
            .into_iter()
            .map(|site| Call {
                module: site.module.clone(),
                place: self.place(site.statement),
            })
            .collect()
    }
}

/// Whether `inner` lies within `outer` (same file).
fn within(inner: Source, outer: Source) -> bool {
    inner.file == outer.file
        && outer.span.start <= inner.span.start
        && inner.span.end <= outer.span.end
}

/// The quadric `index` of a layer's DNF.
fn layer_quadric(layer: &Layer, index: u32) -> Option<&DnfQuadric> {
    layer.dnf().quadrics.get(index as usize)
}

/// The call site of `statement` when it calls a user module: its own name (after any
/// modifiers) is a module reference that resolved to a definition.
fn call_site(
    analysis: &Analysis,
    references: &[(FileId, Span, qcsg_sema::DefId)],
    statement: Source,
) -> Option<CallSite> {
    let key = (statement.file, statement.span.start);
    let first = references.partition_point(|&(file, span, _)| (file, span.start) < key);
    let &(file, span, def) = references.get(first)?;
    if file != statement.file || span.start >= statement.span.end {
        return None;
    }
    let text = &analysis.sources.get(file).text;
    let before = text.get(statement.span.start as usize..span.start as usize)?;
    if !before
        .chars()
        .all(|c| c.is_whitespace() || "!#%*".contains(c))
    {
        return None;
    }
    let definition = analysis.definition(def)?;
    Some(CallSite {
        statement,
        module: definition.name.clone(),
        definition: Source::new(definition.file, definition.span),
    })
}

/// The place of `source` in `sources`.
pub fn place(sources: &SourceMap, source: Source) -> Place {
    let file = sources.get(source.file);
    let position = |offset: u32| {
        let LineCol { line, character } = file.line_index.line_col(&file.text, offset as usize);
        Position { line, character }
    };
    Place {
        file: file.name.clone(),
        range: Range {
            start: position(source.span.start),
            end: position(source.span.end),
        },
        byte_range: [source.span.start, source.span.end],
    }
}
