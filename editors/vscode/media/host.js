// The preview panel's host for view.js: frames and picks come from the language server through
// the extension (postMessage), changes are the document's edits, reveal goes to the editor.
"use strict";
(function () {
  const vscode = acquireVsCodeApi();
  const pending = new Map();
  let next = 1;
  let onChange = null;
  const ask = (type, params) =>
    new Promise((resolve, reject) => {
      const id = next++;
      pending.set(id, { resolve, reject });
      vscode.postMessage({ id, type, params });
    });
  window.addEventListener("message", (event) => {
    const message = event.data;
    if (message.type === "change" && onChange) onChange(message.change);
    else if (message.type === "highlight" && window.qcsgView) window.qcsgView.highlight(message.quadrics);
    else if (pending.has(message.id)) {
      const { resolve, reject } = pending.get(message.id);
      pending.delete(message.id);
      if (message.error) reject(new Error(message.error));
      else resolve(message.result);
    }
  });
  window.qcsgHost = {
    renderer: "CPU ray tracer (language server)",
    highlights: true,
    async frame(params) {
      const answer = await ask("frame", params);
      if (!answer || !answer.png) throw new Error((answer && answer.reason) || "no frame");
      return { url: `data:image/png;base64,${answer.png}`, ms: answer.renderMs };
    },
    pick: (params) => ask("pick", params),
    async camera(params) {
      // The camera comes with a frame; a small one of the same shape is enough.
      const small = {
        ...params,
        width: Math.max(1, Math.round(params.width / 8)),
        height: Math.max(1, Math.round(params.height / 8)),
      };
      const answer = await ask("frame", small);
      if (!answer || !answer.eye) throw new Error("no camera");
      return { eye: answer.eye, center: answer.center, radius: answer.radius };
    },
    subscribe(fn) {
      onChange = fn;
      vscode.postMessage({ type: "ready" });
    },
    reveal(place) {
      vscode.postMessage({ type: "reveal", place });
    },
  };
})();
