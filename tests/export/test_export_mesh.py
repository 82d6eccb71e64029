"""`qcsg export`'s meshes judged by independent mesh libraries (trimesh, manifold3d) and the
checks of `mesh_checks.py`: every example, every stability scene and the random scenes of
`random_scenes.py` export to a watertight, 2-manifold, outward-oriented mesh without degenerate
triangles or self-intersections.

The binary is `$QCSG_BIN`, or `target/debug/qcsg` of the repository (`cargo build -p qcsg-cli`).
The tolerance is that of `crates/qcsg-export/tests/scenes.rs` (3 % of the diagonal), which
measures the examples' and stability scenes' two-way deviation from the exact surface with the
benchmarks' oracle.
"""

import json
import os
import pathlib
import subprocess

import numpy as np
import pytest
import trimesh

import mesh_checks
import random_scenes

ROOT = pathlib.Path(__file__).resolve().parents[2]
QCSG = os.environ.get("QCSG_BIN") or str(ROOT / "target" / "debug" / "qcsg")
TOLERANCE = "3%"
HERE = pathlib.Path(__file__).resolve().parent

# Scenes whose export is known to fail, with the reason: the test fails when one passes, so
# that a fix is noticed (and the entry removed here and in `scenes.rs`).
KNOWN: dict[str, str] = {}

# Surfaces the exporter meshes as level sets; a scene with more than MAX_LEVEL_SETS of them
# (text: a parabolic cylinder per glyph stroke) is skipped, as in `scenes.rs`: it exports, but
# for minutes in a debug build.
LEVEL_SET_KINDS = {
    "parabolic_cylinder",
    "hyperbolic_cylinder",
    "elliptic_paraboloid",
    "hyperbolic_paraboloid",
    "hyperboloid_one_sheet",
    "hyperboloid_two_sheets",
}
MAX_LEVEL_SETS = 8

# Scenes that have no mesh, with the diagnostic the export must give instead.
NO_MESH = {
    "unbounded.qcsg": "unbounded",
}


def scenes() -> list[pathlib.Path]:
    files = []
    for folder in (ROOT / "examples", ROOT / "tests" / "stability", random_scenes.FOLDER):
        files += sorted(p for p in folder.iterdir() if p.suffix in (".qcsg", ".scad"))
    return files


def scene_id(path: pathlib.Path) -> str:
    return str(path.relative_to(ROOT))


def params() -> list:
    result = []
    for path in scenes():
        marks = []
        if path.name in KNOWN:
            marks.append(pytest.mark.xfail(reason=KNOWN[path.name], strict=True))
        result.append(pytest.param(path, id=scene_id(path), marks=marks))
    return result


def normal_form(path: pathlib.Path) -> dict | None:
    """The scene's DNF as `qcsg compile --emit dnf --format json` prints it (None on errors)."""
    run = subprocess.run(
        [QCSG, "compile", "--emit", "dnf", "--format", "json", str(path)],
        capture_output=True,
        text=True,
        timeout=600,
    )
    return json.loads(run.stdout) if run.returncode == 0 else None


def export(path: pathlib.Path, out: pathlib.Path) -> subprocess.CompletedProcess:
    return subprocess.run(
        [QCSG, "export", str(path), "-o", str(out), "--tolerance", TOLERANCE, "--quiet"],
        capture_output=True,
        text=True,
        timeout=600,
    )


def seed_note(path: pathlib.Path) -> str:
    if path.parent == random_scenes.FOLDER:
        return (
            f" (random scene: seed {random_scenes.SEED}, index {int(path.stem.rsplit('_', 1)[1])}, "
            f"tests/export/random_scenes.py)"
        )
    return ""


@pytest.mark.parametrize("path", params())
def test_exported_mesh_bounds_a_solid(path: pathlib.Path, tmp_path: pathlib.Path):
    dnf = normal_form(path)
    count = sum(q["kind"] in LEVEL_SET_KINDS for q in dnf["quadrics"]) if dnf else 0
    if count > MAX_LEVEL_SETS:
        pytest.skip(f"{count} level-set surfaces")
    out = tmp_path / "mesh.obj"
    run = export(path, out)
    if path.name in NO_MESH:
        assert run.returncode == 1, run.stderr
        assert NO_MESH[path.name] in run.stderr
        assert not out.exists()
        return
    assert run.returncode == 0, f"qcsg export failed{seed_note(path)}:\n{run.stderr}"
    vertices, faces = mesh_checks.read_obj(out)
    if dnf is not None and not dnf["terms"]:
        # An empty solid (a part minus itself, a scale by zero): an empty mesh.
        assert len(faces) == 0, f"{len(faces)} triangles for an empty solid"
        return
    report = mesh_checks.check(vertices, faces)
    assert not report.problems(), f"{scene_id(path)}{seed_note(path)}: " + "; ".join(report.problems())


def test_random_scenes_are_the_generators_output():
    """The committed random scenes are what the generator makes for its seed (rewrite them
    with `python3 tests/export/random_scenes.py`)."""
    written = sorted(p.name for p in random_scenes.FOLDER.glob("*.qcsg"))
    expected = [random_scenes.file_name(random_scenes.SEED, i) for i in range(random_scenes.COUNT)]
    assert written == expected
    for index, name in enumerate(expected):
        text = (random_scenes.FOLDER / name).read_text()
        assert text == random_scenes.generate(random_scenes.SEED, index), name


def test_random_scenes_hold_the_hard_cases():
    """The generator plants tangent, coincident and thin parts and level-set surfaces."""
    text = "".join(random_scenes.generate(random_scenes.SEED, i) for i in range(random_scenes.COUNT))
    assert "sphere(r = " in text and "cube(" in text and "cylinder(" in text
    for needle in ("paraboloid(", "ellipsoid(", "cone(", "scale(", "difference()", "intersection()",
                   "rotate(["):
        assert needle in text, needle


# The checks themselves, on meshes whose answer is known: each must be able to fail.


def box(offset=(0.0, 0.0, 0.0)):
    mesh = trimesh.creation.box()
    mesh.apply_translation(offset)
    return mesh


def joined(*meshes):
    mesh = trimesh.util.concatenate(list(meshes))
    return mesh.vertices, mesh.faces


def test_check_passes_closed_meshes():
    for mesh in (box(), trimesh.creation.icosphere(3), trimesh.creation.cylinder(1, 2, sections=24)):
        assert mesh_checks.check(mesh.vertices, mesh.faces).problems() == []
    far = trimesh.creation.icosphere(3)
    far.apply_translation([1e9, -1e9, 1e9])
    assert mesh_checks.check(far.vertices, far.faces).problems() == []
    # Parts touching at a corner or along an edge do not cross.
    assert mesh_checks.check(*joined(box(), box((1, 1, 1)))).problems() == []
    assert mesh_checks.check(*joined(box(), box((1, 1, 0)))).problems() == []


def test_check_finds_crossings_and_double_walls():
    report = mesh_checks.check(*joined(box(), box((0.5, 0.3, 0.2))))
    assert report.watertight and report.manifold_status == "NoError"
    assert report.self_intersections > 0
    ball = trimesh.creation.icosphere(2, radius=0.3)
    ball.apply_translation([0.5, 0, 0])
    assert mesh_checks.check(*joined(box(), ball)).self_intersections > 0
    # Two boxes sharing a face: coplanar triangles facing each other.
    assert mesh_checks.check(*joined(box(), box((1, 0, 0)))).self_intersections > 0


def test_check_finds_holes_flips_pinches_and_degenerate_triangles():
    mesh = box()
    report = mesh_checks.check(mesh.vertices, mesh.faces[1:])
    assert not report.watertight and report.manifold_status != "NoError"
    flipped = mesh.faces.copy()
    flipped[0] = flipped[0][::-1]
    report = mesh_checks.check(mesh.vertices, flipped)
    assert not report.winding_consistent and report.manifold_status != "NoError"
    inverted = mesh.faces[:, ::-1]
    assert mesh_checks.check(mesh.vertices, inverted).volume < 0
    # Two boxes sharing one corner vertex: watertight at edges, not 2-manifold at the corner.
    a, b = box(), box((1, 1, 1))
    vertices = np.concatenate([a.vertices, b.vertices])
    faces = np.concatenate([a.faces, b.faces + len(a.vertices)])
    corner_a = int(np.argmin(np.linalg.norm(a.vertices - [0.5, 0.5, 0.5], axis=1)))
    corner_b = int(np.argmin(np.linalg.norm(b.vertices - [0.5, 0.5, 0.5], axis=1))) + len(a.vertices)
    faces[faces == corner_b] = corner_a
    assert mesh_checks.check(vertices, faces).nonmanifold_vertices == 1
    # Zero-area triangles: a repeated corner, and three collinear corners (an edge's ends and
    # its midpoint).
    i, j = mesh.edges_unique[0]
    v = np.concatenate([mesh.vertices, [(mesh.vertices[i] + mesh.vertices[j]) / 2]])
    extra = np.array([[0, 0, 1], [i, 8, j]])
    assert mesh_checks.check(v, np.concatenate([mesh.faces, extra])).degenerate_triangles == 2


def test_check_finds_folds():
    # Two triangles across the edge 0-2: flat and apart, then folded onto each other.
    v = np.array([[0.0, 0, 0], [1, -1, 0], [2, 0, 0], [1, 1, 0], [1, -0.5, 0]])
    faces = np.array([[0, 1, 2], [0, 2, 3]])
    assert mesh_checks.self_intersections(v, faces, 1e-9)[0] == 0
    folded = np.array([[0, 1, 2], [0, 2, 4]])
    assert mesh_checks.self_intersections(v, folded, 1e-9)[0] == 1
    # A fold lower than the margin is below the check's resolution.
    v[4] = [1, -1e-12, 0]
    assert mesh_checks.self_intersections(v, folded, 1e-9)[0] == 0
