"""Randomly generated scenes for the export checks: seeded, reproducible.

Each scene is a random boolean tree (union, difference, intersection) of random quadric
primitives (cubes, balls, cylinders, frustums, cones, ellipsoids, and now and then a paraboloid
or a hyperboloid, whose surfaces the exporter meshes as level sets) under random translations,
rotations and scales, with planted hard cases:

- tangent: balls touching a face or another ball from outside or inside, a cylinder lying on
  a face;
- coincident: parts sharing a face (a pocket flush with a face, abutting boxes, a peg filling
  its hole exactly);
- thin: walls and gaps from 1e-2 down to 1e-6 of the part's size.

Every subtree is built around a centre that all its parts contain, and a difference removes a
part smaller than what it cuts, so that no scene is empty.

The scenes are written to `random/` beside this file (`python3 random_scenes.py` rewrites them);
`test_export_mesh.py` checks that the files are this generator's output for `SEED` and judges
their exported meshes; being files, they can be read by the Rust tests as well.
"""

import argparse
import math
import pathlib
import random

SEED = 20261206
COUNT = 16
FOLDER = pathlib.Path(__file__).resolve().parent / "random"


def fmt(x: float) -> str:
    """A number to 9 decimals (sums such as `a + r` would otherwise print their rounding
    error), in the shortest form that reads back to the same double."""
    text = repr(round(float(x), 9) + 0.0)
    return text[:-2] if text.endswith(".0") else text


def vec(v) -> str:
    return "[" + ", ".join(fmt(x) for x in v) + "]"


class Scene:
    """One scene's generator: a seeded stream of draws and the level-set surfaces used so far."""

    def __init__(self, seed: int, index: int):
        self.rng = random.Random(f"{seed}/{index}")
        self.level_sets = 0
        self.max_level_sets = index % 2

    def uniform(self, a: float, b: float) -> float:
        # Rounded so that the scene reads well; the hard cases below are exact in these numbers.
        return round(self.rng.uniform(a, b), 3)

    def angle(self) -> list:
        return [self.rng.choice([0, 0, 90, round(self.rng.uniform(-180, 180), 1)]) for _ in range(3)]

    def primitive(self, size: float) -> str:
        """A primitive that contains a ball of radius `size / 4` around the origin."""
        s = size
        kinds = ["cube", "cube", "sphere", "sphere", "cylinder", "frustum", "cone", "ellipsoid"]
        # Level sets are the slow surfaces of a debug build: at most one, in every other scene.
        if self.level_sets < self.max_level_sets:
            kinds += ["paraboloid", "hyperboloid"]
        kind = self.rng.choice(kinds)
        if kind == "cube":
            return f"cube({vec([self.uniform(0.6 * s, 1.4 * s) for _ in range(3)])}, center = true);"
        if kind == "sphere":
            return f"sphere(r = {fmt(self.uniform(0.4 * s, 0.8 * s))});"
        if kind == "cylinder":
            h, r = self.uniform(0.8 * s, 1.6 * s), self.uniform(0.3 * s, 0.7 * s)
            return f"cylinder(h = {fmt(h)}, r = {fmt(r)}, center = true);"
        if kind == "frustum":
            h = self.uniform(0.8 * s, 1.6 * s)
            r1, r2 = self.uniform(0.3 * s, 0.8 * s), self.uniform(0.05 * s, 0.8 * s)
            return f"cylinder(h = {fmt(h)}, r1 = {fmt(r1)}, r2 = {fmt(r2)}, center = true);"
        if kind == "cone":
            h, r = self.uniform(1.2 * s, 2 * s), self.uniform(0.5 * s, 1.0 * s)
            # Apex at the origin, opening upwards: moved down so that it holds the centre.
            return f"translate([0, 0, {fmt(-h / 2)}]) cone(h = {fmt(h)}, r = {fmt(r)});"
        if kind == "ellipsoid":
            return f"ellipsoid(r = {vec([self.uniform(0.3 * s, 0.9 * s) for _ in range(3)])});"
        self.level_sets += 1
        if kind == "paraboloid":
            h = self.uniform(1.0 * s, 1.6 * s)
            r = [self.uniform(0.4 * s, 0.9 * s) for _ in range(2)]
            return f"translate([0, 0, {fmt(-h / 2)}]) paraboloid(h = {fmt(h)}, r = {vec(r)});"
        h, r, c = self.uniform(0.8 * s, 1.4 * s), self.uniform(0.3 * s, 0.6 * s), self.uniform(0.3 * s, 0.8 * s)
        return f"translate([0, 0, {fmt(-h / 2)}]) hyperboloid(h = {fmt(h)}, r = {fmt(r)}, c = {fmt(c)});"

    def placed(self, body: str, size: float) -> str:
        """`body` under a random similarity or affine map that keeps the origin inside it."""
        shift = [self.uniform(-0.15 * size, 0.15 * size) for _ in range(3)]
        parts = []
        if any(shift):
            parts.append(f"translate({vec(shift)})")
        angles = self.angle()
        if any(angles):
            parts.append(f"rotate({vec(angles)})")
        if self.rng.random() < 0.25:
            parts.append(f"scale({vec([self.uniform(0.7, 1.3) for _ in range(3)])})")
        return " ".join(parts + [body])

    def tangent(self, size: float) -> str:
        """Parts touching at a point or along a line."""
        s = size
        a = self.uniform(0.5 * s, 0.8 * s)
        r = self.uniform(0.1 * s, 0.3 * s)
        case = self.rng.choice(["ball_on_face", "balls_outside", "ball_inside", "ball_dent", "rod_on_face"])
        if case == "ball_on_face":
            return (f"union() {{ cube({fmt(2 * a)}, center = true); "
                    f"translate([0, 0, {fmt(a + r)}]) sphere(r = {fmt(r)}); }}")
        if case == "balls_outside":
            return (f"union() {{ sphere(r = {fmt(a)}); "
                    f"translate([{fmt(a + r)}, 0, 0]) sphere(r = {fmt(r)}); }}")
        if case == "ball_inside":
            return (f"difference() {{ sphere(r = {fmt(a)}); "
                    f"translate([{fmt(a - r)}, 0, 0]) sphere(r = {fmt(r)}); }}")
        if case == "ball_dent":
            # A ball cut from a box, touching its top face from inside.
            return (f"difference() {{ cube({fmt(2 * a)}, center = true); "
                    f"translate([0, 0, {fmt(a - r)}]) sphere(r = {fmt(r)}); }}")
        return (f"union() {{ cube({fmt(2 * a)}, center = true); "
                f"translate([0, 0, {fmt(a + r)}]) rotate([0, 90, 0]) "
                f"cylinder(h = {fmt(a)}, r = {fmt(r)}, center = true); }}")

    def coincident(self, size: float) -> str:
        """Parts sharing a face."""
        s = size
        a = self.uniform(0.5 * s, 0.8 * s)
        b = self.uniform(0.2 * a, 0.6 * a)
        case = self.rng.choice(["pocket", "abutting", "peg", "slot"])
        if case == "pocket":
            return (f"difference() {{ cube({fmt(2 * a)}, center = true); "
                    f"translate([{fmt(-b / 2)}, {fmt(-b / 2)}, {fmt(a - b)}]) cube({fmt(b)}); }}")
        if case == "abutting":
            return (f"union() {{ cube({fmt(2 * a)}, center = true); "
                    f"translate([{fmt(a)}, {fmt(-b / 2)}, {fmt(-b / 2)}]) cube({fmt(b)}); }}")
        if case == "peg":
            return (f"union() {{ difference() {{ cube({fmt(2 * a)}, center = true); "
                    f"cylinder(h = {fmt(4 * a)}, r = {fmt(b / 2)}, center = true); }} "
                    f"cylinder(h = {fmt(2 * a)}, r = {fmt(b / 2)}, center = true); }}")
        # A slot whose floor is flush with a step.
        return (f"difference() {{ cube({fmt(2 * a)}, center = true); "
                f"translate([{fmt(-a)}, {fmt(-b / 2)}, 0]) cube([{fmt(2 * a)}, {fmt(b)}, {fmt(a)}]); "
                f"translate([0, {fmt(-a)}, 0]) cube([{fmt(a)}, {fmt(2 * a)}, {fmt(a)}]); }}")

    def thin(self, size: float) -> str:
        """A thin wall or a narrow gap."""
        s = size
        a = self.uniform(0.5 * s, 0.8 * s)
        t = fmt(a * 10 ** -self.rng.choice([2, 3, 4, 6]))
        case = self.rng.choice(["plate", "shell", "gap"])
        if case == "plate":
            return (f"difference() {{ cube({fmt(2 * a)}, center = true); "
                    f"translate([{t}, {fmt(-2 * a)}, {fmt(-2 * a)}]) cube({fmt(4 * a)}); "
                    f"translate([{fmt(-4 * a)}, {fmt(-2 * a)}, {fmt(-2 * a)}]) cube({fmt(4 * a)}); }}")
        if case == "shell":
            return (f"difference() {{ sphere(r = {fmt(a)}); sphere(r = {fmt(a)} - {t}); "
                    f"translate([0, 0, {fmt(a)}]) cube({fmt(2 * a)}, center = true); }}")
        return (f"difference() {{ cube({fmt(2 * a)}, center = true); "
                f"cube([{fmt(2 * a - 2 * float(t))}, {fmt(2 * a - 2 * float(t))}, {t}], center = true); "
                f"translate([{fmt(a / 2)}, 0, 0]) cube({fmt(a / 2)}, center = true); }}")

    def tree(self, size: float, depth: int) -> str:
        if depth == 0 or self.rng.random() < 0.2:
            roll = self.rng.random()
            if roll < 0.15:
                return self.placed(self.tangent(size), size)
            if roll < 0.28:
                return self.placed(self.coincident(size), size)
            if roll < 0.38:
                return self.placed(self.thin(size), size)
            return self.placed(self.primitive(size), size)
        op = self.rng.choice(["union", "union", "difference", "intersection"])
        if op == "difference":
            # The cutters are smaller and off-centre, so they cannot take all of the first part.
            first = self.tree(size, depth - 1)
            cutters = []
            for _ in range(self.rng.randint(1, 2)):
                offset = [self.uniform(-0.5 * size, 0.5 * size) for _ in range(3)]
                cutters.append(f"translate({vec(offset)}) " + self.tree(0.45 * size, depth - 1))
            body = " ".join([first] + cutters)
        else:
            body = " ".join(self.tree(size, depth - 1) for _ in range(self.rng.randint(2, 3)))
        return f"{op}() {{ {body} }}"


def generate(seed: int, index: int) -> str:
    """The source of scene `index` of `seed`."""
    scene = Scene(seed, index)
    depth = 1 + index % 2
    body = scene.tree(10.0, depth)
    return (
        f"// A random scene for the export checks (tests/export/random_scenes.py), seed {seed}, "
        f"index {index}.\n{body}\n"
    )


def file_name(seed: int, index: int) -> str:
    return f"seed{seed}_{index:03}.qcsg"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seed", type=int, default=SEED)
    parser.add_argument("--count", type=int, default=COUNT)
    parser.add_argument("--out", type=pathlib.Path, default=FOLDER)
    args = parser.parse_args()
    args.out.mkdir(parents=True, exist_ok=True)
    for old in args.out.glob("*.qcsg"):
        old.unlink()
    for index in range(args.count):
        (args.out / file_name(args.seed, index)).write_text(generate(args.seed, index))


if __name__ == "__main__":
    main()
