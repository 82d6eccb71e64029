"""A small client of the Chrome DevTools protocol: starts headless Chromium, opens one page and
sends it commands (evaluate JavaScript, dispatch mouse events, take screenshots).

Only the standard library and `websockets` (pinned in requirements.txt): no browser download,
the browser is Debian's `chromium` (or `$CHROMIUM`).
"""

import base64
import itertools
import json
import os
import shutil
import subprocess
import tempfile
import time
import urllib.request

from websockets.sync.client import connect


def chromium_binary():
    found = os.environ.get("CHROMIUM") or shutil.which("chromium") or shutil.which("chromium-browser")
    if not found:
        raise RuntimeError("no chromium: install it (apt-get install chromium) or set $CHROMIUM")
    return found


class Browser:
    """Headless Chromium with one page, closed by `close()` (or a `with` block)."""

    def __init__(self, width=640, height=400):
        self.profile = tempfile.mkdtemp(prefix="qcsg-chromium-")
        self.process = subprocess.Popen(
            [
                chromium_binary(),
                "--headless=new",
                "--no-sandbox",
                "--disable-gpu",
                "--no-first-run",
                "--no-default-browser-check",
                "--disable-extensions",
                "--hide-scrollbars",
                "--force-device-scale-factor=1",
                f"--window-size={width},{height}",
                "--remote-debugging-port=0",
                f"--user-data-dir={self.profile}",
                "about:blank",
            ],
            stdout=subprocess.DEVNULL,
            stderr=subprocess.PIPE,
            text=True,
        )
        port = self._port()
        pages = []
        deadline = time.monotonic() + 30
        while not pages and time.monotonic() < deadline:
            with urllib.request.urlopen(f"http://127.0.0.1:{port}/json/list") as answer:
                pages = [t for t in json.load(answer) if t["type"] == "page"]
            time.sleep(0.05)
        self.socket = connect(pages[0]["webSocketDebuggerUrl"], max_size=64 << 20)
        self.ids = itertools.count(1)
        self.send("Page.enable")
        self.send("Runtime.enable")

    def _port(self):
        # Chromium says where it listens on standard error, among other lines.
        deadline = time.monotonic() + 30
        while time.monotonic() < deadline:
            line = self.process.stderr.readline()
            if "DevTools listening on ws://" in line:
                return int(line.split("ws://", 1)[1].split("/", 1)[0].rsplit(":", 1)[1])
            if not line and self.process.poll() is not None:
                break
        raise RuntimeError("chromium did not start its DevTools server")

    def send(self, method, **params):
        """Sends a command and returns its result (events that arrive meanwhile are dropped)."""
        ident = next(self.ids)
        self.socket.send(json.dumps({"id": ident, "method": method, "params": params}))
        while True:
            message = json.loads(self.socket.recv(timeout=60))
            if message.get("id") == ident:
                if "error" in message:
                    raise RuntimeError(f"{method}: {message['error']}")
                return message.get("result", {})

    def evaluate(self, expression):
        """The value of a JavaScript expression (awaited when it is a promise)."""
        result = self.send("Runtime.evaluate", expression=expression, awaitPromise=True, returnByValue=True)
        if "exceptionDetails" in result:
            raise RuntimeError(f"{expression}: {result['exceptionDetails']}")
        return result["result"].get("value")

    def wait_for(self, expression, timeout=10.0, interval=0.02):
        """Polls `expression` until it is truthy; returns its value and the seconds it took."""
        started = time.monotonic()
        # While the page loads, the expression may not be evaluable yet.
        guarded = f"(() => {{ try {{ return ({expression}); }} catch (_) {{ return null; }} }})()"
        while True:
            value = self.evaluate(guarded)
            if value:
                return value, time.monotonic() - started
            if time.monotonic() - started > timeout:
                raise AssertionError(f"not within {timeout} s: {expression}")
            time.sleep(interval)

    def navigate(self, url):
        self.send("Page.navigate", url=url)

    def mouse(self, kind, x, y, button="left", buttons=1):
        self.send(
            "Input.dispatchMouseEvent", type=kind, x=x, y=y, button=button, buttons=buttons, clickCount=1
        )

    def click(self, x, y):
        self.mouse("mousePressed", x, y)
        self.mouse("mouseReleased", x, y, buttons=0)

    def drag(self, start, end, steps=8):
        (x0, y0), (x1, y1) = start, end
        self.mouse("mousePressed", x0, y0)
        for i in range(1, steps + 1):
            self.mouse("mouseMoved", x0 + (x1 - x0) * i / steps, y0 + (y1 - y0) * i / steps)
            time.sleep(0.03)
        self.mouse("mouseReleased", x1, y1, buttons=0)

    def screenshot(self, path):
        data = self.send("Page.captureScreenshot", format="png")["data"]
        with open(path, "wb") as out:
            out.write(base64.b64decode(data))

    def close(self):
        try:
            self.socket.close()
        finally:
            self.process.kill()
            self.process.wait()
            shutil.rmtree(self.profile, ignore_errors=True)

    def __enter__(self):
        return self

    def __exit__(self, *_):
        self.close()
