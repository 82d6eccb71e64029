"""Whether a triangle mesh bounds a solid, judged by libraries that share no code with qcsg.

- trimesh: watertight (every edge in exactly two triangles), winding consistent (each shared
  edge used in opposite directions), positive signed volume (facing outwards);
- manifold3d (Manifold's own constructor, in double precision): the mesh is a valid manifold
  (status `NoError`), with the same volume;
- here, on the indexed triangles: every vertex's triangles form one fan (2-manifold at vertices
  too), no triangle has zero area, and no two triangles cross each other (self-intersection).

The self-intersection test is exact in its logic and floating-point in its arithmetic, with a
margin `eps` (a length, 1e-10 of the diagonal: the check's resolution): two triangles cross when
the segment that each cuts from the other's plane overlaps the other's by more than `eps`;
coplanar ones (within `eps`) when their interiors overlap by more than `eps`; neighbours across
an edge when they fold onto each other and the lower of the two is more than `eps` high. Contact in a
single point (a shared corner, two fans pinched at one position) is not a crossing. Candidate
pairs come from overlapping bounding boxes, so every pair that can cross is tested.
"""

import dataclasses

import manifold3d
import numpy as np
import trimesh


@dataclasses.dataclass
class Report:
    triangles: int
    watertight: bool
    winding_consistent: bool
    volume: float
    manifold_status: str
    manifold_volume: float
    nonmanifold_vertices: int
    degenerate_triangles: int
    self_intersections: int
    example_crossing: tuple | None = None

    def problems(self) -> list[str]:
        found = []
        if self.triangles == 0:
            found.append("no triangles")
        if not self.watertight:
            found.append("not watertight (trimesh)")
        if not self.winding_consistent:
            found.append("winding not consistent (trimesh)")
        if not self.volume > 0:
            found.append(f"volume {self.volume:.6g} is not positive (trimesh)")
        if self.manifold_status != "NoError":
            found.append(f"manifold3d rejects the mesh: {self.manifold_status}")
        elif not np.isclose(self.manifold_volume, self.volume, rtol=1e-6, atol=0):
            found.append(f"manifold3d's volume {self.manifold_volume:.9g} differs from trimesh's {self.volume:.9g}")
        if self.nonmanifold_vertices:
            found.append(f"{self.nonmanifold_vertices} vertices whose triangles are not one fan")
        if self.degenerate_triangles:
            found.append(f"{self.degenerate_triangles} triangles of zero area")
        if self.self_intersections:
            found.append(f"{self.self_intersections} crossing triangle pairs, e.g. {self.example_crossing}")
        return found


def read_obj(path) -> tuple[np.ndarray, np.ndarray]:
    """Vertices (float64) and triangles (0-based) of an OBJ file, indices as written."""
    vertices, faces = [], []
    with open(path) as f:
        for line in f:
            words = line.split()
            if not words:
                continue
            if words[0] == "v":
                vertices.append([float(w) for w in words[1:4]])
            elif words[0] == "f":
                corners = [int(w.split("/")[0]) for w in words[1:]]
                if len(corners) != 3:
                    raise ValueError(f"not a triangle: {line.strip()}")
                faces.append([c - 1 if c > 0 else len(vertices) + c for c in corners])
    return np.array(vertices, dtype=np.float64).reshape(-1, 3), np.array(faces, dtype=np.int64).reshape(-1, 3)


def check(vertices: np.ndarray, faces: np.ndarray) -> Report:
    # Centred: every check is invariant under translation, and a part 10⁹ from the origin
    # keeps its digits (subtracting nearby doubles is exact).
    centre = (vertices.min(axis=0) + vertices.max(axis=0)) / 2 if len(vertices) else np.zeros(3)
    v = vertices - centre
    mesh = trimesh.Trimesh(vertices=v, faces=faces, process=False, validate=False)
    manifold = manifold3d.Manifold(manifold3d.Mesh64(vert_properties=v, tri_verts=faces.astype(np.uint64)))
    status = manifold.status().name
    diagonal = float(np.linalg.norm(v.max(axis=0) - v.min(axis=0))) if len(v) else 0.0
    # The margin: far above f64 rounding of centred coordinates, and above the rounding of the
    # world coordinates the file holds (8 ulps at the largest).
    largest = float(np.abs(vertices).max()) if len(vertices) else 0.0
    eps = max(1e-10 * diagonal, 8 * np.spacing(largest))
    crossings, example = self_intersections(v, faces, eps)
    return Report(
        triangles=len(faces),
        watertight=bool(mesh.is_watertight),
        winding_consistent=bool(mesh.is_winding_consistent),
        volume=float(mesh.volume),
        manifold_status=status,
        manifold_volume=float(manifold.volume()) if status == "NoError" else float("nan"),
        nonmanifold_vertices=nonmanifold_vertices(faces),
        degenerate_triangles=int(np.count_nonzero(areas(v, faces) == 0)),
        self_intersections=crossings,
        example_crossing=example,
    )


def areas(v: np.ndarray, faces: np.ndarray) -> np.ndarray:
    a, b, c = v[faces[:, 0]], v[faces[:, 1]], v[faces[:, 2]]
    repeated = (faces[:, 0] == faces[:, 1]) | (faces[:, 1] == faces[:, 2]) | (faces[:, 2] == faces[:, 0])
    area = np.linalg.norm(np.cross(b - a, c - a), axis=1) / 2
    return np.where(repeated, 0.0, area)


def nonmanifold_vertices(faces: np.ndarray) -> int:
    """Vertices whose triangles do not form one closed fan: the links (the edge opposite the
    vertex in each of its triangles) must make a single cycle."""
    links: dict[int, dict[int, list[int]]] = {}
    for a, b, c in faces.tolist():
        for v, p, q in ((a, b, c), (b, c, a), (c, a, b)):
            links.setdefault(v, {}).setdefault(p, []).append(q)
    bad = 0
    for link in links.values():
        if any(len(n) != 1 for n in link.values()):
            bad += 1
            continue
        start = next(iter(link))
        seen, at = 1, link[start][0]
        while at != start and at in link and seen <= len(link):
            at = link[at][0]
            seen += 1
        if at != start or seen != len(link):
            bad += 1
    return bad


def candidate_pairs(v: np.ndarray, faces: np.ndarray, eps: float) -> np.ndarray:
    """Pairs (i < j) of triangles whose bounding boxes, grown by `eps`, overlap."""
    tri = v[faces]
    lo, hi = tri.min(axis=1) - eps, tri.max(axis=1) + eps
    order = np.argsort(lo[:, 0], kind="stable")
    lo_x = lo[order, 0]
    # In x order, triangle k overlaps in x the ones after it whose start is before its end.
    ends = np.searchsorted(lo_x, hi[order, 0], side="right")
    counts = ends - np.arange(len(order)) - 1
    pairs = []
    chunk = 2_000_000
    k = 0
    while k < len(order):
        total, stop = 0, k
        while stop < len(order) and (total + counts[stop] <= chunk or stop == k):
            total += counts[stop]
            stop += 1
        firsts = np.repeat(np.arange(k, stop), counts[k:stop])
        offsets = np.arange(len(firsts)) - np.repeat(np.cumsum(counts[k:stop]) - counts[k:stop], counts[k:stop])
        seconds = firsts + 1 + offsets
        i, j = order[firsts], order[seconds]
        keep = np.all((lo[i] <= hi[j]) & (lo[j] <= hi[i]), axis=1)
        pairs.append(np.stack([np.minimum(i, j)[keep], np.maximum(i, j)[keep]], axis=1))
        k = stop
    return np.concatenate(pairs) if pairs else np.zeros((0, 2), dtype=np.int64)


def self_intersections(v: np.ndarray, faces: np.ndarray, eps: float) -> tuple[int, tuple | None]:
    """The number of crossing triangle pairs and one of them (indices and corners)."""
    if len(faces) < 2:
        return 0, None
    pairs = candidate_pairs(v, faces, eps)
    fa, fb = faces[pairs[:, 0]], faces[pairs[:, 1]]
    shared = (fa[:, :, None] == fb[:, None, :]).sum(axis=(1, 2))
    a, b = v[fa], v[fb]
    na, nb = _unit_normals(a), _unit_normals(b)
    # Signed distances of each triangle's corners to the other's plane, snapped to 0 within eps.
    da = np.einsum("pk,pjk->pj", nb, a - b[:, :1])
    db = np.einsum("pk,pjk->pj", na, b - a[:, :1])
    da[np.abs(da) <= eps] = 0
    db[np.abs(db) <= eps] = 0
    crossing = np.zeros(len(pairs), dtype=bool)

    # Neighbours across an edge cross only by folding onto each other; the overlap is then the
    # lower of the two, which must be more than eps high to count.
    across = shared == 2
    heights = 2 * _areas(np.concatenate([a[across], b[across]])) / np.concatenate(
        [_longest(a[across]), _longest(b[across])]).clip(min=np.finfo(float).tiny)
    lower = np.minimum(*np.split(heights, 2)) if across.any() else heights
    crossing[across] = (np.all(db[across] == 0, axis=1)
                        & (np.einsum("pk,pk->p", na[across], nb[across]) < 0) & (lower > eps))

    apart = (shared < 2) & ~(np.all(da > 0, axis=1) | np.all(da < 0, axis=1) | np.all(db > 0, axis=1) | np.all(db < 0, axis=1))
    coplanar = apart & np.all(da == 0, axis=1) & np.all(db == 0, axis=1)
    general = apart & ~coplanar
    if general.any():
        line = np.cross(na[general], nb[general])
        # A zero-area triangle has no normal, hence no line: it is counted as degenerate above,
        # and its pairs here as not crossing.
        length = np.linalg.norm(line, axis=1)
        line /= np.where(length > 0, length, np.inf)[:, None]
        lo_a, hi_a = _interval(a[general], da[general], line)
        lo_b, hi_b = _interval(b[general], db[general], line)
        # A crossing passes through both interiors, so each triangle has corners strictly on
        # both sides of the other's plane; overlapping intervals without that are a contact
        # (an edge or corner lying on the other triangle), which two parts touching along a
        # line have and which is not a crossing.
        straddle = (np.any(da[general] > 0, axis=1) & np.any(da[general] < 0, axis=1)
                    & np.any(db[general] > 0, axis=1) & np.any(db[general] < 0, axis=1))
        crossing[general] = (np.minimum(hi_a, hi_b) - np.maximum(lo_a, lo_b) > eps) & straddle
    if coplanar.any():
        crossing[coplanar] = _coplanar_overlap(a[coplanar], b[coplanar], na[coplanar], eps)
    count = int(np.count_nonzero(crossing))
    if not count:
        return 0, None
    p = int(np.flatnonzero(crossing)[0])
    i, j = (int(x) for x in pairs[p])
    return count, (i, j, v[faces[i]].tolist(), v[faces[j]].tolist())


def _areas(t: np.ndarray) -> np.ndarray:
    return np.linalg.norm(np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0]), axis=1) / 2


def _longest(t: np.ndarray) -> np.ndarray:
    return np.linalg.norm(t - np.roll(t, 1, axis=1), axis=2).max(axis=1)


def _unit_normals(t: np.ndarray) -> np.ndarray:
    n = np.cross(t[:, 1] - t[:, 0], t[:, 2] - t[:, 0])
    length = np.linalg.norm(n, axis=1)
    return n / np.where(length > 0, length, 1)[:, None]


def _interval(t: np.ndarray, d: np.ndarray, line: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The segment a triangle cuts from the other's plane, as an interval along `line`: corners
    on the plane and the crossings of edges whose ends lie strictly on both sides."""
    p = np.einsum("pk,pjk->pj", line, t)
    lo = np.full(len(t), np.inf)
    hi = np.full(len(t), -np.inf)
    for j in range(3):
        on = d[:, j] == 0
        lo = np.where(on, np.minimum(lo, p[:, j]), lo)
        hi = np.where(on, np.maximum(hi, p[:, j]), hi)
        k = (j + 1) % 3
        cut = d[:, j] * d[:, k] < 0
        with np.errstate(divide="ignore", invalid="ignore"):
            x = p[:, j] + (p[:, k] - p[:, j]) * d[:, j] / (d[:, j] - d[:, k])
        lo = np.where(cut, np.minimum(lo, x), lo)
        hi = np.where(cut, np.maximum(hi, x), hi)
    return lo, hi


def _coplanar_overlap(a: np.ndarray, b: np.ndarray, normal: np.ndarray, eps: float) -> np.ndarray:
    """Whether coplanar triangles' interiors overlap: a corner or the centroid of one deeper
    than eps inside the other, or two edges crossing each other by more than eps."""
    # Drop the normal's largest axis: a 2D picture of the plane.
    axis = np.argmax(np.abs(normal), axis=1)
    keep = np.array([[1, 2], [0, 2], [0, 1]])[axis]
    a2 = np.take_along_axis(a, keep[:, None, :], axis=2)
    b2 = np.take_along_axis(b, keep[:, None, :], axis=2)
    # The 2D picture shrinks lengths by at most sqrt(3).
    e = eps / np.sqrt(3)
    overlap = np.zeros(len(a), dtype=bool)
    for s, t in ((a2, b2), (b2, a2)):
        points = np.concatenate([s, s.mean(axis=1, keepdims=True)], axis=1)
        for q in range(4):
            overlap |= _inside(t, points[:, q], e)
    for j in range(3):
        for k in range(3):
            overlap |= _edges_cross(a2[:, j], a2[:, (j + 1) % 3], b2[:, k], b2[:, (k + 1) % 3], e)
    return overlap


def _side(p, q, r):
    """Distance of r from the line pq, signed (left positive)."""
    d = q - p
    length = np.linalg.norm(d, axis=1)
    cross = d[:, 0] * (r[:, 1] - p[:, 1]) - d[:, 1] * (r[:, 0] - p[:, 0])
    return cross / np.where(length > 0, length, 1)


def _inside(t, r, e):
    s = [_side(t[:, j], t[:, (j + 1) % 3], r) for j in range(3)]
    return (np.minimum.reduce(s) > e) | (np.maximum.reduce(s) < -e)


def _edges_cross(p, q, r, s, e):
    return (_side(p, q, r) * _side(p, q, s) < 0) & (np.abs(_side(p, q, r)) > e) & (np.abs(_side(p, q, s)) > e) \
        & (_side(r, s, p) * _side(r, s, q) < 0) & (np.abs(_side(r, s, p)) > e) & (np.abs(_side(r, s, q)) > e)
