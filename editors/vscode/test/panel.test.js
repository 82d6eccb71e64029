// The preview panel's logic (src/panel.ts, compiled to out/ by `npm test`) without VS Code:
// requests of the webview reach the language server and their answers go back with the
// request's id, in whatever order they come; edits and cursor moves are debounced apart; a
// stale cursor answer is dropped; the page loads host.js before view.js under a policy that
// allows the webview's own resources only.
"use strict";

const assert = require("node:assert/strict");
const fs = require("node:fs");
const path = require("node:path");
const { test } = require("node:test");
const { Debouncer, PanelSession, serverRequest, webviewHtml, panelDiagnostic } = require("../out/panel.js");

/** A clock that runs timers only when told to. */
function fakeTimers() {
  let now = 0;
  let nextHandle = 1;
  const due = new Map();
  return {
    setTimeout(work, ms) {
      const handle = nextHandle++;
      due.set(handle, { at: now + ms, work });
      return handle;
    },
    clearTimeout(handle) {
      due.delete(handle);
    },
    advance(ms) {
      now += ms;
      for (const [handle, timer] of [...due].sort((a, b) => a[1].at - b[1].at)) {
        if (timer.at <= now && due.has(handle)) {
          due.delete(handle);
          timer.work();
        }
      }
    },
    pending: () => due.size,
  };
}

/** A promise with its resolve and reject at hand. */
function deferred() {
  let resolve, reject;
  const promise = new Promise((res, rej) => ((resolve = res), (reject = rej)));
  return { promise, resolve, reject };
}

const settle = () => new Promise((resolve) => setImmediate(resolve));

/** A host whose server requests wait until the test answers them. */
function fakeHost(diagnostics = []) {
  const host = {
    uri: "file:///work/scene.qcsg",
    file: "/work/scene.qcsg",
    posted: [],
    requests: [],
    revealed: [],
    request(method, params) {
      const answer = deferred();
      host.requests.push({ method, params, answer });
      return answer.promise;
    },
    post: (message) => host.posted.push(message),
    reveal: (place) => host.revealed.push(place),
    diagnostics: () => diagnostics,
  };
  return host;
}

const ERROR = panelDiagnostic("/work/scene.qcsg", {
  severity: 0,
  code: { value: "E0101" },
  message: "expected an expression",
  range: { start: { line: 5, character: 13 }, end: { line: 5, character: 14 } },
});

test("a debouncer runs only the latest work, once nothing came for its delay", () => {
  const timers = fakeTimers();
  const ran = [];
  const debouncer = new Debouncer(150, timers);
  debouncer.run(() => ran.push(1));
  timers.advance(100);
  debouncer.run(() => ran.push(2));
  timers.advance(100);
  assert.deepEqual(ran, []);
  timers.advance(50);
  assert.deepEqual(ran, [2]);
  debouncer.run(() => ran.push(3));
  debouncer.cancel();
  timers.advance(1000);
  assert.deepEqual(ran, [2]);
});

test("the webview's frame and pick become the server's requests, with the document and numeric highlights", () => {
  const uri = "file:///a.qcsg";
  const frame = serverRequest(uri, {
    id: 4,
    type: "frame",
    params: { width: 80, height: 60, camera: "iso", projection: "ortho", highlight: "3,17" },
  });
  assert.deepEqual(frame, {
    method: "qcsg/frame",
    params: { width: 80, height: 60, camera: "iso", projection: "ortho", highlight: [3, 17], textDocument: { uri } },
  });
  // The page cannot name another document.
  const pick = serverRequest(uri, { id: 5, type: "pick", params: { x: 1, y: 2, textDocument: { uri: "file:///b" } } });
  assert.deepEqual(pick, { method: "qcsg/pick", params: { x: 1, y: 2, textDocument: { uri } } });
  assert.equal(serverRequest(uri, { type: "frame", params: {} }), undefined, "no id: no answer to send");
  assert.equal(serverRequest(uri, { id: 6, type: "format", params: {} }), undefined);
});

test("answers go back with their request's id, also out of order, and failures as errors", async () => {
  const host = fakeHost();
  const session = new PanelSession(host, 150, fakeTimers());
  const first = session.receive({ id: 1, type: "frame", params: { width: 8, height: 6 } });
  const second = session.receive({ id: 2, type: "pick", params: { width: 8, height: 6, x: 1, y: 1 } });
  const third = session.receive({ id: 3, type: "frame", params: { width: 4, height: 3 } });
  assert.deepEqual(
    host.requests.map((r) => r.method),
    ["qcsg/frame", "qcsg/pick", "qcsg/frame"],
  );
  host.requests[1].answer.resolve(null);
  host.requests[0].answer.resolve({ png: "iVBORw0KGgo=", generation: 1 });
  host.requests[2].answer.reject(new Error("width: 0 is not between 1 and 4096"));
  await Promise.all([first, second, third]);
  assert.deepEqual(host.posted, [
    { id: 2, result: null },
    { id: 1, result: { png: "iVBORw0KGgo=", generation: 1 } },
    { id: 3, error: "width: 0 is not between 1 and 4096" },
  ]);
});

test("ready tells the page the document's state at once; reveal goes to the editor", async () => {
  const host = fakeHost([ERROR]);
  const session = new PanelSession(host, 150, fakeTimers());
  await session.receive({ type: "ready" });
  assert.deepEqual(host.posted, [
    {
      type: "change",
      change: { generation: 1, ok: false, image_generation: 1, file: "/work/scene.qcsg", diagnostics: [ERROR] },
    },
  ]);
  assert.equal(ERROR.severity, "error");
  assert.equal(ERROR.code, "E0101");
  const place = { file: "/work/scene.qcsg", range: { start: { line: 3, character: 4 } } };
  await session.receive({ type: "reveal", place });
  assert.deepEqual(host.revealed, [place]);
  assert.equal(host.requests.length, 0);
});

test("edits are debounced into one change, and a cursor move does not swallow it", () => {
  const timers = fakeTimers();
  const host = fakeHost();
  const session = new PanelSession(host, 150, timers);
  session.documentChanged();
  timers.advance(50);
  session.documentChanged();
  timers.advance(100);
  // The cursor moves after the edit, while the change waits.
  session.cursorMoved(2, 4);
  timers.advance(50);
  const changes = host.posted.filter((m) => m.type === "change");
  assert.equal(changes.length, 1);
  assert.equal(changes[0].change.generation, 1);
  assert.equal(changes[0].change.ok, true);
  timers.advance(100);
  assert.deepEqual(
    host.requests.map((r) => [r.method, r.params.position]),
    [["qcsg/partsAt", { line: 2, character: 4 }]],
  );
});

test("a cursor answer for a position the cursor has left is dropped", async () => {
  const timers = fakeTimers();
  const host = fakeHost();
  const session = new PanelSession(host, 150, timers);
  session.cursorMoved(1, 0);
  timers.advance(150);
  session.cursorMoved(7, 2);
  timers.advance(150);
  assert.equal(host.requests.length, 2);
  // The newer answer comes first; the older one, arriving later, must not win.
  host.requests[1].answer.resolve([4, 5]);
  await settle();
  host.requests[0].answer.resolve([0]);
  await settle();
  assert.deepEqual(host.posted, [{ type: "highlight", quadrics: [4, 5] }]);
  // A failed request clears the tint rather than leaving the last one.
  session.cursorMoved(8, 0);
  timers.advance(150);
  host.requests[2].answer.reject(new Error("no server"));
  await settle();
  assert.deepEqual(host.posted.at(-1), { type: "highlight", quadrics: [] });
});

test("a closed panel posts nothing more", async () => {
  const timers = fakeTimers();
  const host = fakeHost();
  const session = new PanelSession(host, 150, timers);
  const frame = session.receive({ id: 1, type: "frame", params: {} });
  session.documentChanged();
  session.dispose();
  host.requests[0].answer.resolve({ png: "" });
  await frame;
  timers.advance(1000);
  assert.equal(timers.pending(), 0);
  assert.deepEqual(host.posted, []);
});

test("the page loads the host before view.js, its assets at webview URIs, under the webview's policy", () => {
  const html = fs.readFileSync(path.join(__dirname, "..", "media", "index.html"), "utf8");
  const page = webviewHtml(html, (name) => `vscode-resource://media/${name}`, "vscode-resource:");
  const policy = page.match(/<meta http-equiv="Content-Security-Policy" content="([^"]*)">/);
  assert.ok(policy, "a policy");
  assert.match(policy[1], /default-src 'none'/);
  assert.match(policy[1], /script-src vscode-resource:;/);
  assert.ok(page.indexOf(policy[0]) < page.indexOf("<link"), "the policy comes before any asset");
  const scripts = [...page.matchAll(/<script src="([^"]*)"><\/script>/g)].map((m) => m[1]);
  assert.deepEqual(scripts, ["vscode-resource://media/host.js", "vscode-resource://media/view.js"]);
  assert.match(page, /href="vscode-resource:\/\/media\/view.css"/);
  assert.throws(() => webviewHtml("<html></html>", (n) => n, "x"), /no <head>/);
});
