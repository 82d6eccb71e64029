"""The Python peers of the qcsg report: Manifold (mesh booleans) and build123d (OpenCascade's
exact booleans, tessellated on export).

Run by `qcsg-bench` as a subprocess:

    python peer.py manifold|build123d JOB.json OUT_DIR

JOB.json holds {"shape": <CSG tree>, "settings": [...]}; the tree is the one `qcsg-bench`
writes beside the OpenSCAD text of the same scene (`crates/qcsg-bench/src/shape.rs`). Every
result is one JSON line appended to OUT_DIR/results.jsonl and flushed at once, so that when the
report stops this process at its time limit the finished settings are kept. Times are wall
times of the peer's own work (`time.perf_counter` around it), without interpreter start-up and
imports, which the report measures separately as the process time.

- manifold: each setting is a circular segment count; one line per count with the time to build
  the solid (primitives, booleans and the mesh out), its triangle count, its status and an STL.
- build123d: the settings are linear tolerances (world units); first one line with the time of
  the exact boolean and whether OpenCascade finds the solid valid, then one line per tolerance
  with the time of tessellating and writing the STL (angular tolerance 0.5 rad, so that the
  linear one decides).
"""

import json
import os
import struct
import sys
import time


def emit(out, record):
    out.write(json.dumps(record) + "\n")
    out.flush()


def write_stl(path, vertices, triangles):
    """A binary STL from an (n, 3) vertex array and an (m, 3) index array."""
    with open(path, "wb") as f:
        f.write(b"\0" * 80)
        f.write(struct.pack("<I", len(triangles)))
        for a, b, c in triangles:
            f.write(struct.pack("<3f", 0.0, 0.0, 0.0))
            for k in (a, b, c):
                v = vertices[k]
                f.write(struct.pack("<3f", float(v[0]), float(v[1]), float(v[2])))
            f.write(b"\0\0")


def read_stl(path):
    """A binary STL's vertices (merged where bit-identical) and triangles, as numpy arrays."""
    import numpy as np

    with open(path, "rb") as f:
        data = f.read()
    (count,) = struct.unpack_from("<I", data, 80)
    record = np.dtype([("normal", "<f4", 3), ("corners", "<f4", (3, 3)), ("attr", "<u2")])
    corners = np.frombuffer(data, dtype=record, count=count, offset=84)["corners"].reshape(-1, 3)
    vertices, index = np.unique(corners, axis=0, return_inverse=True)
    return vertices, index.reshape(-1, 3).astype(np.uint32)


def manifold_build(m, node, segments):
    kind = node["kind"]
    if kind == "stl":
        vertices, triangles = read_stl(node["path"])
        return m.Manifold(m.Mesh(vert_properties=vertices, tri_verts=triangles))
    if kind == "sphere":
        return m.Manifold.sphere(node["r"], segments)
    if kind == "cylinder":
        return m.Manifold.cylinder(node["h"], node["r"], node["r"], segments, node["center"])
    if kind == "cube":
        return m.Manifold.cube(node["size"], node["center"])
    if kind == "translate":
        return manifold_build(m, node["child"], segments).translate(node["v"])
    if kind == "rotate":
        return manifold_build(m, node["child"], segments).rotate(node["v"])
    children = [manifold_build(m, c, segments) for c in node["children"]]
    op = {
        "union": m.OpType.Add,
        "difference": m.OpType.Subtract,
        "intersection": m.OpType.Intersect,
    }[kind]
    return m.Manifold.batch_boolean(children, op)


def run_manifold(job, out_dir, out):
    import manifold3d as m

    for segments in job["settings"]:
        start, cpu_start = time.perf_counter(), time.process_time()
        solid = manifold_build(m, job["shape"], int(segments))
        mesh = solid.to_mesh()
        elapsed = time.perf_counter() - start
        cpu = time.process_time() - cpu_start
        status = str(solid.status()).split(".")[-1]
        path = os.path.join(out_dir, f"manifold-{segments}.stl")
        write_stl(path, mesh.vert_properties[:, :3], mesh.tri_verts)
        emit(out, {
            "setting": segments,
            "build_s": elapsed,
            "cpu_s": cpu,
            "triangles": int(len(mesh.tri_verts)),
            "status": status,
            "valid": status == "NoError",
            "stl": path,
        })


def build123d_build(b, node):
    kind = node["kind"]
    if kind == "sphere":
        return b.Sphere(node["r"])
    if kind == "cylinder":
        z = b.Align.CENTER if node["center"] else b.Align.MIN
        return b.Cylinder(node["r"], node["h"], align=(b.Align.CENTER, b.Align.CENTER, z))
    if kind == "cube":
        a = b.Align.CENTER if node["center"] else b.Align.MIN
        x, y, z = node["size"]
        return b.Box(x, y, z, align=(a, a, a))
    if kind == "translate":
        return b.Pos(*node["v"]) * build123d_build(b, node["child"])
    if kind == "rotate":
        # OpenSCAD's rotate([x, y, z]) turns about the fixed x, then y, then z axes.
        x, y, z = node["v"]
        return b.Rot(x, y, z, ordering=b.Extrinsic.XYZ) * build123d_build(b, node["child"])
    children = [build123d_build(b, c) for c in node["children"]]
    head, tail = children[0], children[1:]
    if not tail:
        return head
    if kind == "union":
        return one_shape(b, head.fuse(*tail))
    if kind == "difference":
        return one_shape(b, head.cut(*tail))
    result = head
    for c in tail:
        result = one_shape(b, result.intersect(c))
    return result


def one_shape(b, result):
    """A boolean may answer a list of shapes; the next boolean needs one shape."""
    if isinstance(result, b.ShapeList):
        return result[0] if len(result) == 1 else b.Compound(list(result))
    return result


def run_build123d(job, out_dir, out):
    import build123d as b

    start = time.perf_counter()
    solid = build123d_build(b, job["shape"])
    elapsed = time.perf_counter() - start
    start = time.perf_counter()
    check_valid = solid.is_valid
    valid = bool(check_valid() if callable(check_valid) else check_valid)
    check = time.perf_counter() - start
    emit(out, {"setting": None, "build_s": elapsed, "check_s": check, "valid": valid})
    for tolerance in job["settings"]:
        path = os.path.join(out_dir, f"build123d-{tolerance:.3e}.stl")
        start = time.perf_counter()
        b.export_stl(solid, path, tolerance=tolerance, angular_tolerance=0.5)
        elapsed = time.perf_counter() - start
        emit(out, {"setting": tolerance, "build_s": elapsed, "valid": valid, "stl": path})


def main():
    peer, job_path, out_dir = sys.argv[1:4]
    with open(job_path) as f:
        job = json.load(f)
    with open(os.path.join(out_dir, "results.jsonl"), "w") as out:
        try:
            if peer == "manifold":
                run_manifold(job, out_dir, out)
            elif peer == "build123d":
                run_build123d(job, out_dir, out)
            else:
                raise SystemExit(f"unknown peer {peer}")
        except Exception as err:  # reported as the outcome of the setting in progress
            emit(out, {"error": f"{type(err).__name__}: {err}"})
            raise


if __name__ == "__main__":
    main()
