// The preview panel's logic without VS Code: the page as the webview loads it, the messages
// between the webview (media/host.js) and the language server, and the debouncing of edits and
// cursor moves. preview.ts wires it to VS Code; test/panel.test.js and tests/view/ exercise it
// as it is.

/** How long the panel waits after an edit or a cursor move before asking again. */
export const DEBOUNCE_MS = 150;

/** A place in the sources, as `qcsg/pick` answers it. */
export type Place = { file: string; range: { start: { line: number; character: number } } };

/** A message from the webview (host.js). */
export type WebviewMessage = {
  id?: number;
  type: string;
  params?: Record<string, unknown>;
  place?: Place;
};

type Range = { start: { line: number; character: number }; end: { line: number; character: number } };

/** A diagnostic as the page lists it (an element of `qcsg check --format json`). */
export type PanelDiagnostic = {
  severity: string;
  code: string;
  message: string;
  file: string;
  range: Range;
};

/** What the panel needs from its surroundings: the editor, the language server, the webview. */
export interface PanelHost {
  /** The document's URI, as the language server knows it. */
  readonly uri: string;
  /** The document's path, for the page's title and links. */
  readonly file: string;
  /** Sends a request to the language server; rejects when it fails or no server runs. */
  request(method: string, params: Record<string, unknown>): Promise<unknown>;
  /** Posts a message to the webview. */
  post(message: unknown): void;
  /** Shows a place in the editor. */
  reveal(place: Place): void | Promise<void>;
  /** The document's current diagnostics. */
  diagnostics(): PanelDiagnostic[];
}

/** The timer functions (the global ones by default; tests pass their own clock). */
export type Timers = {
  setTimeout(work: () => void, ms: number): unknown;
  clearTimeout(handle: unknown): void;
};

const globalTimers: Timers = {
  setTimeout: (work, ms) => setTimeout(work, ms),
  clearTimeout: (handle) => clearTimeout(handle as ReturnType<typeof setTimeout>),
};

/** Runs the latest of the works given to it once no other came for `delayMs`. */
export class Debouncer {
  private handle: unknown = undefined;

  constructor(
    private readonly delayMs: number,
    private readonly timers: Timers = globalTimers,
  ) {}

  run(work: () => void): void {
    this.cancel();
    this.handle = this.timers.setTimeout(() => {
      this.handle = undefined;
      work();
    }, this.delayMs);
  }

  cancel(): void {
    if (this.handle !== undefined) this.timers.clearTimeout(this.handle);
    this.handle = undefined;
  }
}

/** The severities in the order of VS Code's `DiagnosticSeverity` (and LSP's, less one). */
const SEVERITIES = ["error", "warning", "info", "hint"];

/** A diagnostic for the page, from VS Code's fields (`severity` zero-based: 0 is an error). */
export function panelDiagnostic(
  file: string,
  d: { severity: number; code?: string | number | { value: string | number }; message: string; range: Range },
): PanelDiagnostic {
  const code = typeof d.code === "object" ? String(d.code.value) : String(d.code ?? "");
  return {
    severity: SEVERITIES[d.severity] ?? "info",
    code,
    message: d.message,
    file,
    range: {
      start: { line: d.range.start.line, character: d.range.start.character },
      end: { line: d.range.end.line, character: d.range.end.character },
    },
  };
}

/** The language server request for a webview message, or `undefined` if it asks for none. */
export function serverRequest(
  uri: string,
  message: WebviewMessage,
): { method: string; params: Record<string, unknown> } | undefined {
  const method = ({ frame: "qcsg/frame", pick: "qcsg/pick" } as Record<string, string>)[message.type];
  if (!method || message.id === undefined) return undefined;
  const params: Record<string, unknown> = { ...message.params, textDocument: { uri } };
  // The page passes the tinted quadrics as its URL parameter, "3,7"; the server takes numbers.
  if (typeof params.highlight === "string") {
    params.highlight = params.highlight.split(",").map(Number);
  }
  return { method, params };
}

/**
 * One open panel: answers the webview's requests through the language server (each answer
 * carries its request's id), tells the page of the document's changes after a pause, and tints
 * the part under the cursor. Edits and cursor moves are debounced separately, so a cursor move
 * never swallows a pending change; an answer to `qcsg/partsAt` for a cursor position that has
 * since moved is dropped.
 */
export class PanelSession {
  private generation = 0;
  private cursorAsked = 0;
  private readonly changes: Debouncer;
  private readonly cursor: Debouncer;
  private disposed = false;

  constructor(
    private readonly host: PanelHost,
    delayMs: number = DEBOUNCE_MS,
    timers: Timers = globalTimers,
  ) {
    this.changes = new Debouncer(delayMs, timers);
    this.cursor = new Debouncer(delayMs, timers);
  }

  /** Handles a message of the webview. */
  async receive(message: WebviewMessage): Promise<void> {
    if (this.disposed) return;
    if (message.type === "ready") return this.change();
    if (message.type === "reveal" && message.place) {
      await this.host.reveal(message.place);
      return;
    }
    const request = serverRequest(this.host.uri, message);
    if (!request) return;
    let answer: { id: number; result?: unknown; error?: string };
    try {
      answer = { id: message.id!, result: await this.host.request(request.method, request.params) };
    } catch (error) {
      answer = { id: message.id!, error: error instanceof Error ? error.message : String(error) };
    }
    if (!this.disposed) this.host.post(answer);
  }

  /** The document's diagnostics changed (it was edited): the page is told after a pause. */
  documentChanged(): void {
    this.changes.run(() => this.change());
  }

  /** The cursor moved to a position of the document: its part is tinted after a pause. */
  cursorMoved(line: number, character: number): void {
    const asked = ++this.cursorAsked;
    this.cursor.run(async () => {
      let quadrics: unknown = [];
      try {
        quadrics = await this.host.request("qcsg/partsAt", {
          textDocument: { uri: this.host.uri },
          position: { line, character },
        });
      } catch (_) {
        quadrics = [];
      }
      if (this.disposed || asked !== this.cursorAsked) return;
      this.host.post({ type: "highlight", quadrics: Array.isArray(quadrics) ? quadrics : [] });
    });
  }

  dispose(): void {
    this.disposed = true;
    this.changes.cancel();
    this.cursor.cancel();
  }

  /** Posts a `change` event, as `qcsg view`'s `/events` sends one per rebuild. */
  private change(): void {
    if (this.disposed) return;
    this.generation += 1;
    const diagnostics = this.host.diagnostics();
    const ok = !diagnostics.some((d) => d.severity === "error");
    this.host.post({
      type: "change",
      change: {
        generation: this.generation,
        ok,
        image_generation: this.generation,
        file: this.host.file,
        diagnostics,
      },
    });
  }
}

/**
 * The page of `qcsg view` (index.html) as the webview loads it: a Content-Security-Policy for
 * the webview's own resources, its assets at the webview's URIs (`asset(name)`), and host.js
 * before view.js, so that view.js finds `window.qcsgHost`.
 */
export function webviewHtml(html: string, asset: (name: string) => string, cspSource: string): string {
  const policy =
    `default-src 'none'; img-src ${cspSource} data:; ` + `style-src ${cspSource}; script-src ${cspSource};`;
  const replace = (text: string, from: string, to: string) => {
    if (!text.includes(from)) throw new Error(`the preview page has no ${from}`);
    return text.replace(from, to);
  };
  let page = replace(html, "<head>", `<head>\n<meta http-equiv="Content-Security-Policy" content="${policy}">`);
  page = replace(page, 'href="view.css"', `href="${asset("view.css")}"`);
  return replace(
    page,
    '<script src="view.js"></script>',
    `<script src="${asset("host.js")}"></script>\n<script src="${asset("view.js")}"></script>`,
  );
}
