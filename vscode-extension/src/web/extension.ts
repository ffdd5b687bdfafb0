/// <reference lib="webworker" />
// textladder for VS Code in the browser (vscode.dev, VS Code for the Web; the `browser` entry of
// package.json): the language server runs on Pyodide in a Web Worker (worker.js), and the client,
// the simulation UI and the commands are the desktop's (activate.ts).
//
// A web extension host starts no worker from an extension's folder when that folder is not a
// plain http(s) address: code-server's are vscode-remote: URIs, which VS Code refuses ("Creating
// workers from remote extensions is currently not supported"), and a worker could not fetch from
// them either. So the extension reads the worker's script and Pyodide's files itself, through the
// workspace's file system (or fetch, for an http(s) folder), starts the worker from a blob: URL
// and posts it the files first.
import * as vscode from 'vscode';
import { LanguageClient } from 'vscode-languageclient/browser';
import { activateWith } from '../activate';
import { LADDER_LANGUAGES } from '../state';

export { deactivate } from '../activate';

/** The files the worker needs, under out/web/ (scripts/web.mjs): what worker.js takes as textladderFiles. */
const FILES = {
  wasm: 'pyodide/pyodide.asm.wasm',
  stdlib: 'pyodide/python_stdlib.zip',
  lock: 'pyodide/pyodide-lock.json',
  site: 'site.zip',
} as const;

export function activate(context: vscode.ExtensionContext): Promise<void> {
  const web = vscode.Uri.joinPath(context.extensionUri, 'out', 'web');
  return activateWith(context, {
    // any scheme: a browser's documents are vscode-vfs:, vscode-remote:, memfs:, untitled:...
    selector: LADDER_LANGUAGES.map((language) => ({ language })),
    serverWritesFiles: false,
    findServer: async () => {
      let script: ArrayBuffer;
      try {
        script = await read(web, 'worker.js');
      } catch (err) {
        return { message: `The browser's language server could not be read: ${err instanceof Error ? err.message : String(err)}` };
      }
      const worker = new Worker(URL.createObjectURL(new Blob([script], { type: 'text/javascript' })));
      void sendFiles(worker, web);
      return {
        name: 'textladder on Pyodide in a Web Worker',
        source: 'the browser entry of the extension',
        hint: 'See the "Ladder" output.',
        create: (options) => new LanguageClient('ladder', 'Ladder language server', options, worker),
      };
    },
  });
}

async function read(folder: vscode.Uri, name: string): Promise<ArrayBuffer> {
  const uri = vscode.Uri.joinPath(folder, name);
  if (uri.scheme === 'http' || uri.scheme === 'https') {
    const response = await fetch(uri.toString(true));
    if (!response.ok) {
      throw new Error(`${uri.toString(true)}: HTTP ${response.status}`);
    }
    return response.arrayBuffer();
  }
  const bytes = await vscode.workspace.fs.readFile(uri);
  return bytes.buffer.slice(bytes.byteOffset, bytes.byteOffset + bytes.byteLength) as ArrayBuffer;
}

/** Pyodide's files and site.zip to the worker, which waits for them (or for why they cannot come). */
async function sendFiles(worker: Worker, web: vscode.Uri): Promise<void> {
  try {
    const entries = await Promise.all(Object.entries(FILES).map(async ([key, name]) => [key, await read(web, name)] as const));
    worker.postMessage({ textladderFiles: Object.fromEntries(entries) }, entries.map(([, bytes]) => bytes));
  } catch (err) {
    worker.postMessage({ textladderFiles: null, error: err instanceof Error ? err.message : String(err) });
  }
}
