"""`qcsg view`'s page in a real headless Chromium: it shows the solid, follows a saved edit within
a second, turns with a drag, reports the file and line of a clicked part, and keeps the last
image (dimmed) with the error when the program breaks.

The server is `$QCSG_BIN view` (default: target/debug/qcsg). With `$QCSG_VIEW_SCREENSHOTS` set
to a folder, the screenshots of the steps are written there (docs/view/ keeps them).
"""

import json
import os
import pathlib
import shutil
import subprocess
import urllib.parse
import urllib.request

import pytest

from cdp import Browser

ROOT = pathlib.Path(__file__).resolve().parents[2]
QCSG = os.environ.get("QCSG_BIN") or str(ROOT / "target" / "debug" / "qcsg")
SHOTS = os.environ.get("QCSG_VIEW_SCREENSHOTS")

# The frame's pixels: a hash and the fraction that is not the background (the top-left pixel).
IMAGE = """(() => {
  const img = document.getElementById('frame');
  if (!img.naturalWidth) return null;
  const c = document.createElement('canvas');
  c.width = img.naturalWidth; c.height = img.naturalHeight;
  const g = c.getContext('2d'); g.drawImage(img, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data;
  let h = 0, fg = 0;
  for (let i = 0; i < d.length; i += 4) {
    h = (Math.imul(h, 31) + d[i] * 65536 + d[i + 1] * 256 + d[i + 2]) >>> 0;
    if (d[i] !== d[0] || d[i + 1] !== d[1] || d[i + 2] !== d[2]) fg++;
  }
  return {hash: `${h}:${c.width}x${c.height}`, fraction: fg / (d.length / 4), width: c.width};
})()"""


def shot(browser, name):
    if SHOTS:
        pathlib.Path(SHOTS).mkdir(parents=True, exist_ok=True)
        browser.screenshot(str(pathlib.Path(SHOTS) / name))


@pytest.fixture
def scene(tmp_path):
    path = tmp_path / "wheel.qcsg"
    shutil.copy(ROOT / "examples" / "wheel.qcsg", path)
    server = subprocess.Popen(
        [QCSG, "view", str(path), "--no-open", "--port", "0"],
        stdout=subprocess.PIPE,
        stderr=subprocess.DEVNULL,
        text=True,
    )
    line = server.stdout.readline()
    url = "http://" + line.split("http://", 1)[1].split()[0]
    yield path, url
    server.kill()
    server.wait()


def get_json(url):
    with urllib.request.urlopen(url) as answer:
        return json.load(answer)


def find_rim_pixel(browser, url, text):
    """A pixel of the current frame that shows the rim (the outer cylinder of `tube`)."""
    width, height = browser.evaluate("(v => [v.clientWidth, v.clientHeight])(document.getElementById('viewport'))")
    for y in range(4, height, 12):
        for x in range(4, width, 12):
            query = urllib.parse.urlencode({"width": width, "height": height, "camera": "iso", "x": x, "y": y})
            picked = get_json(f"{url}pick?{query}")
            if picked and picked.get("byte_range"):
                start, _ = picked["byte_range"]
                if text.encode()[start:].startswith(b"cylinder(h = height, r = outer)"):
                    return x, y, picked
    raise AssertionError("no pixel shows the rim")


def test_the_page_follows_edits_drags_clicks_and_errors(scene):
    path, url = scene
    text = path.read_text()
    with Browser(width=800, height=600) as browser:
        browser.navigate(url)
        # 1. The page loads and shows the solid.
        browser.wait_for("document.body.dataset.frames >= 1", timeout=20)
        loaded = browser.evaluate(IMAGE)
        assert loaded["fraction"] > 0.05, loaded
        assert "CPU ray tracer" in browser.evaluate("document.getElementById('status').textContent")
        shot(browser, "1-loaded.png")

        # 2. A click on a part reports its file and line, and the module call that made it.
        x, y, picked = find_rim_pixel(browser, url, text)
        left, top = browser.evaluate("(r => [r.left, r.top])(document.getElementById('frame').getBoundingClientRect())")
        browser.click(left + x + 0.5, top + y + 0.5)
        line, _ = browser.wait_for("document.getElementById('pick').dataset.line")
        assert int(line) == picked["range"]["start"]["line"] + 1
        assert browser.evaluate("document.getElementById('pick').dataset.file").endswith("wheel.qcsg")
        assert "tube() at" in browser.evaluate("document.getElementById('pick').textContent")
        shot(browser, "2-picked.png")

        # 3. A saved edit changes the image within a second.
        frames = browser.evaluate("+document.body.dataset.frames")
        path.write_text(text.replace("rim_radius = 30;", "rim_radius = 22;"))
        _, took = browser.wait_for(
            f"+document.body.dataset.frames > {frames} && document.body.dataset.ok === 'true'", timeout=5
        )
        edited = browser.evaluate(IMAGE)
        assert edited["hash"] != loaded["hash"]
        assert took < 1.0, f"the edit took {took:.2f} s to show"
        shot(browser, "3-edited.png")

        # 4. A drag turns the view: small frames while dragging, the full size after.
        frames = browser.evaluate("+document.body.dataset.frames")
        browser.drag((left + 150, top + 150), (left + 260, top + 190))
        browser.wait_for(f"+document.body.dataset.frames > {frames} && document.body.dataset.frameWidth == document.getElementById(\"viewport\").clientWidth")
        turned = browser.evaluate(IMAGE)
        assert turned["hash"] != edited["hash"]
        assert browser.evaluate("qcsgView.state.view") is None
        shot(browser, "4-turned.png")

        # 5. A syntax error: the error is listed, the last image stays, dimmed.
        path.write_text(text.replace("rim_radius = 30;", "rim_radius = ;"))
        browser.wait_for("document.body.dataset.ok === 'false'", timeout=5)
        banner = browser.evaluate("document.getElementById('banner').hidden ? '' : banner.textContent")
        assert "last version that compiled" in banner
        errors = browser.evaluate(
            "[...document.querySelectorAll('#diagnostics li.error')].map(li => li.textContent)"
        )
        assert errors and "wheel.qcsg:6:" in errors[0], errors
        assert browser.evaluate("frame.classList.contains('stale')")
        assert browser.evaluate(IMAGE)["hash"] == turned["hash"]
        shot(browser, "5-error.png")
