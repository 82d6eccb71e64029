"""The live preview's benchmark: rewrites the section between the bench markers of docs/view.md.

Runs `target/release/qcsg view` (or `$QCSG_BIN`) and measures, as the page works: the time from a
saved edit to the updated 800x600 frame (the `change` event, then `/frame.png`) for a 30-quadric
scene; orbit frames per second at 640x480 for every gallery scene (frames asked one after the
other around a circle); the server's resident memory over 1,000 edits. Beside each wall time it
reports the server's CPU time (user + system, all its threads, from /proc) and the machine's load
average, so that a run on a machine shared with other work can be read: on a loaded machine the
wall times grow, the CPU time hardly. Standard library only.
"""

import http.client
import json
import math
import os
import pathlib
import platform
import statistics
import subprocess
import tempfile
import time
import urllib.parse

ROOT = pathlib.Path(__file__).resolve().parents[2]
QCSG = os.environ.get("QCSG_BIN") or str(ROOT / "target" / "release" / "qcsg")
DOC = ROOT / "docs" / "view.md"
CLOCK_TICKS = os.sysconf("SC_CLK_TCK")

# A block drilled by three cylinders with a 6x4 grid of balls, as in docs/render.md.
THIRTY = """size = {size};
difference() {{
    cube([6, 4, 2], center = true);
    for (r = [[0, 90, 0], [90, 0, 0], [0, 0, 0]]) rotate(r) cylinder(h = 10, r = 0.6, center = true);
}}
for (i = [0 : 5], j = [0 : 3]) translate([-2.5 + i, -1.5 + j, 1.2]) sphere(size);
"""


class View:
    def __init__(self, path):
        self.process = subprocess.Popen(
            [QCSG, "view", str(path), "--no-open", "--port", "0"], stdout=subprocess.PIPE, text=True
        )
        line = self.process.stdout.readline()
        self.port = int(line.split("http://127.0.0.1:", 1)[1].split("/", 1)[0])
        self.events = http.client.HTTPConnection("127.0.0.1", self.port)
        self.events.request("GET", "/events")
        self.stream = self.events.getresponse()
        self.latest = self.next_change()

    def next_change(self):
        while True:
            line = self.stream.readline().decode()
            if line.startswith("data: "):
                return json.loads(line[6:])

    def wait_generation(self, above):
        while self.latest["generation"] <= above:
            self.latest = self.next_change()
        return self.latest

    def get(self, path, **params):
        connection = http.client.HTTPConnection("127.0.0.1", self.port)
        connection.request("GET", f"{path}?{urllib.parse.urlencode(params)}")
        answer = connection.getresponse()
        body = answer.read()
        connection.close()
        assert answer.status == 200, (path, params, answer.status, body[:200])
        return body

    def rss_mib(self):
        for line in pathlib.Path(f"/proc/{self.process.pid}/status").read_text().splitlines():
            if line.startswith("VmRSS:"):
                return int(line.split()[1]) / 1024
        return float("nan")

    def cpu_seconds(self):
        """The server's CPU time so far, user and system, every thread (dead ones included)."""
        fields = pathlib.Path(f"/proc/{self.process.pid}/stat").read_text().rsplit(")", 1)[1].split()
        return (int(fields[11]) + int(fields[12])) / CLOCK_TICKS

    def close(self):
        self.process.kill()
        self.process.wait()


def edit_to_frame(folder, edits=30):
    """Wall and server CPU milliseconds of each of `edits` saved edits, to the updated frame."""
    path = folder / "thirty.qcsg"
    path.write_text(THIRTY.format(size=0.45))
    view = View(path)
    quadrics = view.latest["quadrics"]
    walls, cpus = [], []
    for i in range(edits):
        generation = view.latest["generation"]
        cpu = view.cpu_seconds()
        started = time.perf_counter()
        path.write_text(THIRTY.format(size=0.40 + 0.002 * (i % 10)))
        view.wait_generation(generation)
        view.get("/frame.png", width=800, height=600)
        walls.append(1e3 * (time.perf_counter() - started))
        cpus.append(1e3 * (view.cpu_seconds() - cpu))
    view.close()
    return quadrics, walls, cpus


def orbit(path, frames=24):
    """Frames per second of an orbit at 640x480, in wall time and in the server's CPU time."""
    view = View(path)
    quadrics = view.latest["quadrics"]
    camera = json.loads(view.get("/camera", width=640, height=480))
    eye, center = camera["eye"], camera["center"]
    d = [e - c for e, c in zip(eye, center)]
    radius = math.hypot(d[0], d[1])
    cpu = view.cpu_seconds()
    started = time.perf_counter()
    for i in range(frames):
        angle = math.atan2(d[1], d[0]) + 2 * math.pi * i / frames
        at = [center[0] + radius * math.cos(angle), center[1] + radius * math.sin(angle), eye[2]]
        view.get("/frame.png", width=640, height=480, camera=",".join(f"{v:.9g}" for v in at + center))
    took = time.perf_counter() - started
    cpu = view.cpu_seconds() - cpu
    view.close()
    return quadrics, frames / took, cpu / frames


def memory(folder, edits=1000):
    path = folder / "memory.qcsg"
    path.write_text(THIRTY.format(size=0.45))
    view = View(path)
    samples = {0: view.rss_mib()}
    for i in range(1, edits + 1):
        generation = view.latest["generation"]
        path.write_text(THIRTY.format(size=0.40 + 0.0001 * i))
        view.wait_generation(generation)
        if i % 10 == 0:
            view.get("/frame.png", width=200, height=150)
        if i in (100, 250, 500, 1000):
            samples[i] = view.rss_mib()
    view.close()
    return samples


def load():
    """The machine's load average over the last minute."""
    return os.getloadavg()[0]


def percentile(values, fraction):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(fraction * len(ordered)))]


def main():
    lines = []
    cores = os.cpu_count()
    with tempfile.TemporaryDirectory() as folder:
        folder = pathlib.Path(folder)
        before = load()
        quadrics, walls, cpus = edit_to_frame(folder)
        after = load()
        binary = pathlib.Path(QCSG)
        shown = binary.relative_to(ROOT) if binary.is_relative_to(ROOT) else binary
        lines.append(
            f"Measured on {cores} cores ({platform.processor() or platform.machine()}), "
            f"`{shown}`, {time.strftime('%Y-%m-%d')}. CPU time is the server's (user and "
            "system, all threads); the load average is the machine's over the last minute.\n"
        )
        lines.append(
            f"- Saved edit to updated 800×600 frame, 30-quadric scene ({quadrics} quadrics in the "
            f"normal form), {len(walls)} edits, load average {before:.1f} → {after:.1f}: wall time "
            f"median {statistics.median(walls):.0f} ms, 90th percentile {percentile(walls, 0.9):.0f} ms, "
            f"worst {max(walls):.0f} ms; the server's CPU time per edit {statistics.mean(cpus):.0f} ms "
            f"(mean; the kernel counts it in ticks of {1e3 / CLOCK_TICKS:.0f} ms)."
        )
        lines.append("")
        lines.append("| gallery scene | quadrics | orbit frames/s at 640×480 | CPU ms per frame | load average |")
        lines.append("| --- | --- | --- | --- | --- |")
        scenes = sorted(ROOT.glob("examples/*.qcsg")) + sorted(ROOT.glob("examples/*.scad"))
        for scene in scenes:
            quadrics, fps, cpu = orbit(scene)
            lines.append(f"| {scene.name} | {quadrics} | {fps:.1f} | {1e3 * cpu:.0f} | {load():.1f} |")
        samples = memory(folder)
        lines.append("")
        lines.append(
            "- Resident memory of the server over 1,000 edits of the 30-quadric scene (a frame every "
            "10th): " + ", ".join(f"{n} edits: {mib:.1f} MiB" for n, mib in samples.items()) + "."
        )
    section = "\n".join(lines)
    text = DOC.read_text()
    begin, end = "<!-- bench:begin -->", "<!-- bench:end -->"
    head, rest = text.split(begin, 1)
    _, tail = rest.split(end, 1)
    DOC.write_text(f"{head}{begin}\n{section}\n{end}{tail}")
    print(section)


if __name__ == "__main__":
    main()
