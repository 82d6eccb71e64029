// "qcsg: Open Preview to the Side": the page of `qcsg view` in a webview beside the editor, fed
// by the language server from the unsaved document (the custom requests `qcsg/frame`,
// `qcsg/pick` and `qcsg/partsAt`, docs/view.md). Edits are followed after a short pause; a click
// on the model reveals the call's line; the cursor on a primitive's call tints its part.
import * as fs from "fs";
import * as path from "path";
import * as vscode from "vscode";
import type { LanguageClient } from "vscode-languageclient/node";

/** How long the panel waits after an edit or a cursor move before asking again. */
const DEBOUNCE_MS = 150;

type Message = { id?: number; type: string; params?: Record<string, unknown>; place?: Place };
type Place = { file: string; range: { start: { line: number; character: number } } };

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
  panel.webview.html = page(panel.webview, media);
  const uri = document.uri.toString();
  let generation = 0;

  const change = () => {
    generation += 1;
    const diagnostics = vscode.languages.getDiagnostics(document.uri).map((d) => ({
      severity: ["error", "warning", "info", "hint"][d.severity] ?? "info",
      code: typeof d.code === "object" ? String(d.code.value) : String(d.code ?? ""),
      message: d.message,
      file: document.fileName,
      range: {
        start: { line: d.range.start.line, character: d.range.start.character },
        end: { line: d.range.end.line, character: d.range.end.character },
      },
    }));
    const ok = !diagnostics.some((d) => d.severity === "error");
    void panel.webview.postMessage({
      type: "change",
      change: { generation, ok, image_generation: generation, file: document.fileName, diagnostics },
    });
  };
  let timer: NodeJS.Timeout | undefined;
  const later = (work: () => void) => {
    if (timer) clearTimeout(timer);
    timer = setTimeout(work, DEBOUNCE_MS);
  };

  const disposables: vscode.Disposable[] = [
    vscode.languages.onDidChangeDiagnostics((event) => {
      if (event.uris.some((u) => u.toString() === uri)) later(change);
    }),
    vscode.window.onDidChangeTextEditorSelection((event) => {
      if (event.textEditor.document.uri.toString() !== uri) return;
      const position = event.selections[0].active;
      later(async () => {
        const quadrics = await client()?.sendRequest("qcsg/partsAt", {
          textDocument: { uri },
          position: { line: position.line, character: position.character },
        });
        void panel.webview.postMessage({ type: "highlight", quadrics: quadrics ?? [] });
      });
    }),
    panel.webview.onDidReceiveMessage(async (message: Message) => {
      if (message.type === "ready") return change();
      if (message.type === "reveal" && message.place) return reveal(message.place);
      const method = { frame: "qcsg/frame", pick: "qcsg/pick" }[message.type];
      if (!method || message.id === undefined) return;
      const params: Record<string, unknown> = { textDocument: { uri }, ...message.params };
      if (typeof params.highlight === "string") {
        params.highlight = (params.highlight as string).split(",").map(Number);
      }
      try {
        const running = client();
        if (!running) throw new Error("the language server is not running");
        const result = await running.sendRequest(method, params);
        void panel.webview.postMessage({ id: message.id, result });
      } catch (error) {
        void panel.webview.postMessage({ id: message.id, error: String(error) });
      }
    }),
  ];
  panel.onDidDispose(() => disposables.forEach((d) => d.dispose()));
}

async function reveal(place: Place): Promise<void> {
  const at = new vscode.Position(place.range.start.line, place.range.start.character);
  const document = await vscode.workspace.openTextDocument(vscode.Uri.file(place.file));
  const editor = await vscode.window.showTextDocument(document, vscode.ViewColumn.One);
  editor.selection = new vscode.Selection(at, at);
  editor.revealRange(new vscode.Range(at, at), vscode.TextEditorRevealType.InCenterIfOutsideViewport);
}

/** The page of `qcsg view` with its assets as webview URIs and the host script before view.js. */
function page(webview: vscode.Webview, media: vscode.Uri): string {
  const asset = (name: string) => webview.asWebviewUri(vscode.Uri.joinPath(media, name)).toString();
  const html = fs.readFileSync(path.join(media.fsPath, "index.html"), "utf8");
  const policy =
    `default-src 'none'; img-src ${webview.cspSource} data:; ` +
    `style-src ${webview.cspSource}; script-src ${webview.cspSource};`;
  return html
    .replace("<head>", `<head>\n<meta http-equiv="Content-Security-Policy" content="${policy}">`)
    .replace('href="view.css"', `href="${asset("view.css")}"`)
    .replace('<script src="view.js"></script>', `<script src="${asset("host.js")}"></script>\n<script src="${asset("view.js")}"></script>`);
}
