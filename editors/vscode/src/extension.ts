// The qcsg VS Code extension: starts the language server (`qcsg lsp` on stdio) for .qcsg and
// .scad files, and the preview panel (preview.ts). Highlighting comes from the TextMate grammar in syntaxes/ and works without it.
import * as vscode from "vscode";
import {
  LanguageClient,
  LanguageClientOptions,
  ServerOptions,
  TransportKind,
} from "vscode-languageclient/node";
import { openPreview } from "./preview";

let client: LanguageClient | undefined;

/** The `qcsg` executable: the `qcsg.serverPath` setting, or `qcsg` on PATH. */
function serverPath(): string {
  const configured = vscode.workspace.getConfiguration("qcsg").get<string>("serverPath");
  return configured && configured.trim() !== "" ? configured.trim() : "qcsg";
}

async function startClient(context: vscode.ExtensionContext): Promise<void> {
  const command = serverPath();
  const serverOptions: ServerOptions = {
    run: { command, args: ["lsp"], transport: TransportKind.stdio },
    debug: { command, args: ["lsp"], transport: TransportKind.stdio },
  };
  const clientOptions: LanguageClientOptions = {
    documentSelector: [
      { scheme: "file", language: "qcsg" },
      { scheme: "untitled", language: "qcsg" },
    ],
  };
  client = new LanguageClient("qcsg", "qcsg language server", serverOptions, clientOptions);
  try {
    await client.start();
  } catch (err) {
    void vscode.window.showErrorMessage(
      `Could not start the qcsg language server (\`${command} lsp\`): ${String(err)}. ` +
        "Install qcsg or set `qcsg.serverPath`.",
    );
  }
  context.subscriptions.push(client);
}

async function stopClient(): Promise<void> {
  const running = client;
  client = undefined;
  if (running && running.isRunning()) {
    await running.stop();
  }
}

export async function activate(context: vscode.ExtensionContext): Promise<void> {
  context.subscriptions.push(
    vscode.commands.registerCommand("qcsg.openPreview", () => openPreview(context, () => client)),
    vscode.commands.registerCommand("qcsg.restartServer", async () => {
      await stopClient();
      await startClient(context);
    }),
    vscode.workspace.onDidChangeConfiguration(async (event) => {
      if (event.affectsConfiguration("qcsg.serverPath")) {
        await stopClient();
        await startClient(context);
      }
    }),
  );
  await startClient(context);
}

export async function deactivate(): Promise<void> {
  await stopClient();
}
