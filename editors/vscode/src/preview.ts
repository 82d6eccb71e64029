// "qcsg: Open Preview to the Side": the page of `qcsg view` in a webview beside the editor, fed
// by the language server from the unsaved document (the custom requests `qcsg/frame`,
// `qcsg/pick` and `qcsg/partsAt`, docs/view.md). Edits are followed after a short pause; a click
// on the model reveals the call's line; the cursor on a primitive's call tints its part. The
// logic lives in panel.ts, which runs without VS Code; this file connects it to the editor.
import * as fs from "fs";
import * as path from "path";
import * as vscode from "vscode";
import type { LanguageClient } from "vscode-languageclient/node";
import { PanelSession, Place, WebviewMessage, panelDiagnostic, webviewHtml } from "./panel";

export function openPreview(context: vscode.ExtensionContext, client: () => LanguageClient | undefined): void {
  const editor = vscode.window.activeTextEditor;
  if (!editor) {
    void vscode.window.showInformationMessage("Open a .qcsg file to preview it.");
    return;
  }
  const document = editor.document;
  const media = vscode.Uri.joinPath(context.extensionUri, "media");
  const panel = vscode.window.createWebviewPanel(
    "qcsg.preview",
    `Preview ${path.basename(document.fileName)}`,
    { viewColumn: vscode.ViewColumn.Beside, preserveFocus: true },
    { enableScripts: true, localResourceRoots: [media], retainContextWhenHidden: true },
  );
  const webview = panel.webview;
  webview.html = webviewHtml(
    fs.readFileSync(path.join(media.fsPath, "index.html"), "utf8"),
    (name) => webview.asWebviewUri(vscode.Uri.joinPath(media, name)).toString(),
    webview.cspSource,
  );
  const uri = document.uri.toString();
  const session = new PanelSession({
    uri,
    file: document.fileName,
    request: (method, params) => {
      const running = client();
      if (!running) return Promise.reject(new Error("the language server is not running"));
      return running.sendRequest(method, params);
    },
    post: (message) => void webview.postMessage(message),
    reveal,
    diagnostics: () =>
      vscode.languages.getDiagnostics(document.uri).map((d) =>
        panelDiagnostic(document.fileName, {
          severity: d.severity,
          code: d.code as string | number | { value: string | number } | undefined,
          message: d.message,
          range: d.range,
        }),
      ),
  });

  const disposables: vscode.Disposable[] = [
    vscode.languages.onDidChangeDiagnostics((event) => {
      if (event.uris.some((u) => u.toString() === uri)) session.documentChanged();
    }),
    vscode.window.onDidChangeTextEditorSelection((event) => {
      if (event.textEditor.document.uri.toString() !== uri) return;
      const position = event.selections[0].active;
      session.cursorMoved(position.line, position.character);
    }),
    webview.onDidReceiveMessage((message: WebviewMessage) => session.receive(message)),
  ];
  panel.onDidDispose(() => {
    session.dispose();
    disposables.forEach((d) => d.dispose());
  });
}

async function reveal(place: Place): Promise<void> {
  const at = new vscode.Position(place.range.start.line, place.range.start.character);
  const document = await vscode.workspace.openTextDocument(vscode.Uri.file(place.file));
  const editor = await vscode.window.showTextDocument(document, vscode.ViewColumn.One);
  editor.selection = new vscode.Selection(at, at);
  editor.revealRange(new vscode.Range(at, at), vscode.TextEditorRevealType.InCenterIfOutsideViewport);
}
