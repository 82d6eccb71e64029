"""The VS Code preview panel's webview in a real headless Chromium: the page of `qcsg view` as
the extension loads it (its HTML from the extension's own `webviewHtml`, `media/host.js` before
`view.js`), with a stub of VS Code's webview API (`acquireVsCodeApi`, messages both ways), and
behind it the extension's own panel logic (`PanelSession`, in `panel_bridge.js`) talking to a
real `qcsg lsp`. It checks that the webview asks for frames and shows them, follows an unsaved
edit, reveals the line of a clicked part in the editor, tints the part under the editor's cursor,
never queues frames behind a drag, ignores answers it did not ask for, and keeps its image on an
error.

Needs the extension built (`npm ci && npm run build` in editors/vscode) and `$QCSG_BIN` (default:
target/debug/qcsg).
"""

import functools
import http.server
import json
import os
import pathlib
import queue
import shutil
import subprocess
import threading
import time

import pytest

from cdp import Browser
from test_page import IMAGE

ROOT = pathlib.Path(__file__).resolve().parents[2]
QCSG = os.environ.get("QCSG_BIN") or str(ROOT / "target" / "debug" / "qcsg")
EXTENSION = ROOT / "editors" / "vscode"
PANEL = EXTENSION / "out" / "panel.js"

SCENE = """module post(h) {
    cylinder(h = h, r = 1.5);
}
sphere(r = 10);
translate([12, 0, 0]) post(6);
"""

# VS Code's webview API, as a page sees it: `acquireVsCodeApi` (once), whose `postMessage` goes
# to the extension (here: a list the test empties), and messages from the extension arrive as
# `message` events on the window.
STUB = """"use strict";
window.toExtension = [];
window.acquireVsCodeApi = (() => {
  let acquired = false;
  return () => {
    if (acquired) throw new Error("An instance of the VS Code API has already been acquired");
    acquired = true;
    return {
      postMessage: (message) => window.toExtension.push(JSON.parse(JSON.stringify(message))),
      getState: () => undefined,
      setState: () => {},
    };
  };
})();
"""

# The RGB of a pixel of the shown frame, at a fraction of its width and height.
PIXEL = """((fx, fy) => {
  const img = document.getElementById('frame');
  const c = document.createElement('canvas');
  c.width = img.naturalWidth; c.height = img.naturalHeight;
  const g = c.getContext('2d'); g.drawImage(img, 0, 0);
  return [...g.getImageData(Math.floor(fx * c.width), Math.floor(fy * c.height), 1, 1).data.slice(0, 3)];
})"""


class Quiet(http.server.SimpleHTTPRequestHandler):
    def log_message(self, *_):
        pass


@pytest.fixture
def webview_page(tmp_path):
    """The webview's files served from a folder, as VS Code serves the extension's media/."""
    if not PANEL.exists() or not (EXTENSION / "media" / "view.js").exists():
        pytest.fail("the extension is not built: run `npm ci && npm run build` in editors/vscode")
    site = tmp_path / "site"
    site.mkdir()
    for name in ["host.js", "view.js", "view.css"]:
        shutil.copy(EXTENSION / "media" / name, site / name)
    (site / "stub.js").write_text(STUB)
    server = http.server.ThreadingHTTPServer(
        ("127.0.0.1", 0), functools.partial(Quiet, directory=str(site))
    )
    origin = f"http://127.0.0.1:{server.server_address[1]}"
    script = (
        f"const {{webviewHtml}} = require({json.dumps(str(PANEL))});"
        f"const html = require('fs').readFileSync({json.dumps(str(EXTENSION / 'media' / 'index.html'))}, 'utf8');"
        f"process.stdout.write(webviewHtml(html, (n) => {json.dumps(origin)} + '/' + n, {json.dumps(origin)}));"
    )
    html = subprocess.run(["node", "-e", script], check=True, capture_output=True, text=True).stdout
    host_tag = f'<script src="{origin}/host.js"></script>'
    assert host_tag in html
    (site / "index.html").write_text(html.replace(host_tag, f'<script src="{origin}/stub.js"></script>\n{host_tag}'))
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield f"{origin}/index.html"
    server.shutdown()


class Panel:
    """The extension's side (panel_bridge.js with `qcsg lsp`) and the pump between it and the
    webview: what the webview posts goes to the extension unless held, what the extension posts
    is delivered to the webview."""

    def __init__(self, browser, file):
        self.browser = browser
        self.process = subprocess.Popen(
            ["node", str(ROOT / "tests" / "view" / "panel_bridge.js"), QCSG, str(file)],
            stdin=subprocess.PIPE,
            stdout=subprocess.PIPE,
            text=True,
        )
        self.lines = queue.Queue()
        threading.Thread(target=self._read, daemon=True).start()
        self.from_webview = []  # every message the webview posted
        self.revealed = []  # the places the editor revealed
        self.held = []
        self.holding = False
        assert self.lines.get(timeout=30) == {"ready": True}

    def _read(self):
        for line in self.process.stdout:
            self.lines.put(json.loads(line))

    def send(self, message):
        self.process.stdin.write(json.dumps(message) + "\n")
        self.process.stdin.flush()

    def deliver(self, message):
        self.browser.evaluate(f"window.dispatchEvent(new MessageEvent('message', {{data: {json.dumps(message)}}})), 0")

    def pump(self):
        for message in self.browser.evaluate("window.toExtension ? window.toExtension.splice(0) : []"):
            self.from_webview.append(message)
            (self.held if self.holding else []).append(message)
            if not self.holding:
                self.send({"webview": message})
        while True:
            try:
                message = self.lines.get_nowait()
            except queue.Empty:
                return
            if "webview" in message:
                self.deliver(message["webview"])
            elif "reveal" in message:
                self.revealed.append(message["reveal"])

    def release(self):
        self.holding = False
        for message in self.held:
            self.send({"webview": message})
        self.held = []

    def wait_for(self, expression, timeout=20.0):
        """Pumps messages until the page's `expression` is truthy; returns its value."""
        deadline = time.monotonic() + timeout
        while True:
            self.pump()
            value = self.browser.evaluate(f"(() => {{ try {{ return ({expression}); }} catch (_) {{ return null; }} }})()")
            if value:
                return value
            if time.monotonic() > deadline:
                raise AssertionError(f"not within {timeout} s: {expression}")
            time.sleep(0.02)

    def wait_until(self, predicate, what, timeout=20.0):
        """Pumps messages until `predicate()` is true."""
        deadline = time.monotonic() + timeout
        while not predicate():
            if time.monotonic() > deadline:
                raise AssertionError(f"not within {timeout} s: {what}")
            self.pump()
            time.sleep(0.02)

    def settle(self, seconds=0.4):
        """Pumps for a while, for messages that must not come."""
        deadline = time.monotonic() + seconds
        while time.monotonic() < deadline:
            self.pump()
            time.sleep(0.02)

    def frames_asked(self):
        return [m for m in self.from_webview if m.get("type") == "frame"]

    def close(self):
        self.process.stdin.close()
        try:
            self.process.wait(timeout=10)
        except subprocess.TimeoutExpired:
            self.process.kill()
            self.process.wait()


def test_the_webview_with_the_extension_and_the_language_server(webview_page, tmp_path):
    file = tmp_path / "scene.qcsg"
    file.write_text(SCENE)
    with Browser(width=800, height=600) as browser:
        browser.navigate(webview_page)
        panel = Panel(browser, file)
        try:
            # The webview says it is ready, the extension answers with the document's state, and
            # the webview asks for frames (through `qcsg/frame`) and shows them.
            panel.wait_for("document.body.dataset.frames >= 1")
            assert panel.from_webview[0] == {"type": "ready"}
            asked = panel.frames_asked()
            assert asked and all(isinstance(m["id"], int) for m in asked)
            assert len({m["id"] for m in panel.from_webview if "id" in m}) == len([m for m in panel.from_webview if "id" in m])
            loaded = browser.evaluate(IMAGE)
            assert loaded["fraction"] > 0.05, loaded
            width = browser.evaluate("document.getElementById('viewport').clientWidth")
            assert loaded["width"] == width
            assert "language server" in browser.evaluate("document.getElementById('status').textContent")
            assert browser.evaluate("document.body.dataset.ok") == "true"
            # The server's first diagnostics make one more change, and its frame.
            panel.settle(0.6)

            # A click on the ball (the middle of the frame) asks `qcsg/pick`, and the extension
            # reveals the ball's call in the editor.
            left, top, w, h = browser.evaluate(
                "(r => [r.left, r.top, r.width, r.height])(document.getElementById('frame').getBoundingClientRect())"
            )
            browser.click(left + w / 2, top + h / 2)
            panel.wait_for("document.getElementById('pick').dataset.line")
            picks = [m for m in panel.from_webview if m.get("type") == "pick"]
            assert len(picks) == 1 and picks[0]["params"]["x"] == width // 2
            deadline = time.monotonic() + 10
            while not panel.revealed and time.monotonic() < deadline:
                panel.settle(0.05)
            assert len(panel.revealed) == 1, panel.revealed
            place = panel.revealed[0]
            assert pathlib.Path(place["file"]).name == "scene.qcsg"
            assert place["range"]["start"]["line"] == 3, place  # sphere(r = 10);
            assert browser.evaluate("document.getElementById('pick').dataset.line") == "4"

            # The editor's cursor on the ball's call: the extension asks `qcsg/partsAt`, the
            # webview gets a highlight and asks for a frame with those quadrics tinted.
            plain_ball = browser.evaluate(f"{PIXEL}(0.5, 0.5)")
            plain_corner = browser.evaluate(f"{PIXEL}(0.01, 0.01)")
            asked = len(panel.frames_asked())
            panel.send({"cursor": {"line": 3, "character": 3}})
            panel.wait_until(
                lambda: any(m["params"].get("highlight") for m in panel.frames_asked()[asked:]),
                "a frame asked with the cursor's part tinted",
            )
            tinted_ask = [m for m in panel.frames_asked()[asked:] if m["params"].get("highlight")][0]
            assert tinted_ask["params"]["highlight"] == "0", tinted_ask  # the ball's quadric
            frames = browser.evaluate("+document.body.dataset.frames")
            panel.wait_for(f"+document.body.dataset.frames > {frames}")
            panel.settle(0.3)
            tinted_ball = browser.evaluate(f"{PIXEL}(0.5, 0.5)")
            assert tinted_ball != plain_ball, "the ball is tinted"
            assert browser.evaluate(f"{PIXEL}(0.01, 0.01)") == plain_corner, "the background is not"

            # Stale frames are never queued: while a frame is on its way (held here), a whole
            # drag asks for nothing more; once it is shown, the webview asks once, for the
            # full-size frame of where the drag ended.
            panel.settle(0.3)
            asked_before = len(panel.frames_asked())
            frames = browser.evaluate("+document.body.dataset.frames")
            panel.holding = True
            browser.drag((left + 200, top + 200), (left + 330, top + 260), steps=10)
            panel.settle(0.4)
            during = panel.frames_asked()[asked_before:]
            assert len(during) == 1, during
            assert during[0]["params"]["width"] < width, "a small frame while dragging"
            panel.release()
            panel.wait_for(f"+document.body.dataset.frames >= {frames + 2} && document.body.dataset.frameWidth == {width}")
            panel.settle(0.4)
            after = panel.frames_asked()[asked_before:]
            assert len(after) == 2, after
            camera = browser.evaluate(
                "[...qcsgView.state.eye, ...qcsgView.state.center].map(v => +v.toPrecision(12)).join(',')"
            )
            assert after[1]["params"]["camera"] == camera and after[1]["params"]["width"] == width
            turned = browser.evaluate(IMAGE)
            assert turned["hash"] != loaded["hash"]

            # An answer to no request of the webview's (a panel reloaded meanwhile) is ignored.
            frames = browser.evaluate("+document.body.dataset.frames")
            panel.deliver({"id": 987654, "result": {"png": "AAAA"}})
            panel.settle(0.3)
            assert browser.evaluate("+document.body.dataset.frames") == frames
            assert browser.evaluate(IMAGE)["hash"] == turned["hash"]

            # An unsaved edit: the extension tells the webview after the debounce, and the
            # webview shows the new solid.
            generation = int(browser.evaluate("document.body.dataset.generation"))
            panel.send({"edit": SCENE.replace("sphere(r = 10)", "sphere(r = 6)")})
            panel.wait_for(f"+document.body.dataset.generation > {generation}")
            panel.wait_for(f"+document.body.dataset.frames > {frames}")
            panel.settle(0.3)
            edited = browser.evaluate(IMAGE)
            assert edited["hash"] != turned["hash"]

            # A syntax error: listed, and the last image stays, dimmed.
            panel.send({"edit": SCENE.replace("sphere(r = 10)", "sphere(r = )")})
            panel.wait_for("document.body.dataset.ok === 'false'")
            errors = panel.wait_for("[...document.querySelectorAll('#diagnostics li.error')].map(li => li.textContent)")
            assert "scene.qcsg:4:" in errors[0], errors
            assert browser.evaluate("document.getElementById('frame').classList.contains('stale')")
            panel.settle(0.3)
            assert browser.evaluate(IMAGE)["hash"] == edited["hash"]
        finally:
            panel.close()
