// The VS Code extension's side of the preview panel, for the webview test (test_webview.py):
// the extension's own PanelSession (editors/vscode/out/panel.js, built by `npm run build`)
// talking to a real `qcsg lsp` through vscode-jsonrpc, as vscode-languageclient does. In VS Code
// the editor feeds it edits and cursor moves and shows what it reveals; here the test does,
// through lines of JSON:
//   stdin:  {"webview": message}            a message the webview posted
//           {"edit": text}                   the document's new (unsaved) text
//           {"cursor": {line, character}}    the editor's cursor moved
//   stdout: {"webview": message}            a message for the webview
//           {"reveal": place}               the editor reveals a place
//           {"ready": true}                 the server is initialized and the document open
// Usage: node panel_bridge.js QCSG_BINARY FILE
"use strict";

const childProcess = require("node:child_process");
const fs = require("node:fs");
const path = require("node:path");
const readline = require("node:readline");
const { pathToFileURL } = require("node:url");

const extension = path.resolve(__dirname, "..", "..", "editors", "vscode");
const { PanelSession, panelDiagnostic } = require(path.join(extension, "out", "panel.js"));
const rpc = require(path.join(extension, "node_modules", "vscode-jsonrpc", "node"));

const [qcsg, file] = process.argv.slice(2);
const uri = pathToFileURL(path.resolve(file)).toString();
const say = (message) => process.stdout.write(`${JSON.stringify(message)}\n`);

const server = childProcess.spawn(qcsg, ["lsp"], { stdio: ["pipe", "pipe", "inherit"] });
const connection = rpc.createMessageConnection(
  new rpc.StreamMessageReader(server.stdout),
  new rpc.StreamMessageWriter(server.stdin),
);
let diagnostics = [];
const session = new PanelSession({
  uri,
  file: path.resolve(file),
  request: (method, params) => connection.sendRequest(method, params),
  post: (message) => say({ webview: message }),
  reveal: (place) => say({ reveal: place }),
  diagnostics: () => diagnostics,
});
connection.onNotification("textDocument/publishDiagnostics", (params) => {
  if (params.uri !== uri) return;
  // LSP's severities count from 1, VS Code's from 0.
  diagnostics = params.diagnostics.map((d) => panelDiagnostic(path.resolve(file), { ...d, severity: (d.severity ?? 1) - 1 }));
  session.documentChanged();
});
connection.listen();

async function main() {
  await connection.sendRequest("initialize", { processId: process.pid, rootUri: null, capabilities: {} });
  connection.sendNotification("initialized", {});
  let version = 1;
  connection.sendNotification("textDocument/didOpen", {
    textDocument: { uri, languageId: "qcsg", version, text: fs.readFileSync(file, "utf8") },
  });
  say({ ready: true });
  for await (const line of readline.createInterface({ input: process.stdin })) {
    const message = JSON.parse(line);
    if (message.webview) void session.receive(message.webview);
    else if (typeof message.edit === "string") {
      version += 1;
      connection.sendNotification("textDocument/didChange", {
        textDocument: { uri, version },
        contentChanges: [{ text: message.edit }],
      });
    } else if (message.cursor) session.cursorMoved(message.cursor.line, message.cursor.character);
  }
  session.dispose();
  server.kill();
  process.exit(0);
}

main().catch((error) => {
  process.stderr.write(`${error.stack}\n`);
  server.kill();
  process.exit(1);
});
