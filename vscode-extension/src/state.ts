// The simulation state the server pushes with `ladder/simulationState` (docs/lsp-protocol.md), kept
// per document.
import * as vscode from 'vscode';

export interface LspPosition {
  line: number;
  character: number;
}

export interface LspRange {
  start: LspPosition;
  end: LspPosition;
}

export interface SimulationState {
  uri: string;
  running: boolean;
  realtime: boolean;
  timeMs: number;
  scan: number;
  energized: LspRange[];
  values: Record<string, number>;
  error: string | null;
  reached?: boolean;
  /** the inputs replayed from a recorded sequence (a counterexample of `ladder.verify`), if any */
  replay?: Replaying | null;
}

export interface Replaying {
  name: string;
  applied: number;
  total: number;
  /** the time of the scan the sequence leads to (where a counterexample breaks its property) */
  endMs: number;
}

export const LADDER_LANGUAGES = ['ladder', 'ldmicro'];

export function isLadderDocument(doc: vscode.TextDocument | undefined): doc is vscode.TextDocument {
  return doc !== undefined && LADDER_LANGUAGES.includes(doc.languageId);
}

/** One form of a document URI for map keys: the server may escape characters differently. */
export function uriKey(uri: string | vscode.Uri): string {
  try {
    return (typeof uri === 'string' ? vscode.Uri.parse(uri) : uri).toString();
  } catch {
    return String(uri);
  }
}

export function isSimulationState(value: unknown): value is SimulationState {
  if (typeof value !== 'object' || value === null) {
    return false;
  }
  const v = value as Partial<SimulationState>;
  return typeof v.uri === 'string' && typeof v.running === 'boolean';
}

export function toRange(r: LspRange): vscode.Range {
  return new vscode.Range(r.start.line, r.start.character, r.end.line, r.end.character);
}

/** `1230` -> `1.230 s`; `57.5` -> `57.5 ms`. */
export function formatTime(ms: number): string {
  if (!Number.isFinite(ms)) {
    return '?';
  }
  if (Math.abs(ms) >= 1000) {
    return `${(ms / 1000).toFixed(3)} s`;
  }
  return `${Number(ms.toFixed(3))} ms`;
}

/** Reads `500`, `500ms`, `2.5 s`, `1 min` as milliseconds; undefined when not a duration. */
export function parseDurationMs(text: string): number | undefined {
  const m = /^\s*([0-9]+(?:\.[0-9]*)?|\.[0-9]+)\s*(us|ms|s|min|h)?\s*$/i.exec(text);
  if (!m) {
    return undefined;
  }
  const n = parseFloat(m[1]);
  const unit = (m[2] ?? 'ms').toLowerCase();
  const factor: Record<string, number> = { us: 0.001, ms: 1, s: 1000, min: 60000, h: 3600000 };
  return n * factor[unit];
}

/** Keeps the last state of every running simulation and tells listeners when one changes. */
export class SimulationStore implements vscode.Disposable {
  private readonly states = new Map<string, SimulationState>();
  private readonly emitter = new vscode.EventEmitter<string>();
  /** fires with the document URI (as uriKey) whose simulation changed */
  readonly onDidChange = this.emitter.event;
  /** the document of the last state received: the commands' target when no ladder editor is active */
  lastUri: string | undefined;

  update(state: SimulationState): void {
    const key = uriKey(state.uri);
    this.lastUri = key;
    if (state.running) {
      this.states.set(key, { ...state, energized: state.energized ?? [], values: state.values ?? {} });
    } else {
      this.states.delete(key);
    }
    this.emitter.fire(key);
  }

  clear(uri: string): void {
    const key = uriKey(uri);
    if (this.states.delete(key)) {
      this.emitter.fire(key);
    }
  }

  clearAll(): void {
    const keys = [...this.states.keys()];
    this.states.clear();
    keys.forEach((k) => this.emitter.fire(k));
  }

  get(uri: string | vscode.Uri | undefined): SimulationState | undefined {
    return uri === undefined ? undefined : this.states.get(uriKey(uri));
  }

  running(): SimulationState[] {
    return [...this.states.values()];
  }

  dispose(): void {
    this.emitter.dispose();
  }
}
