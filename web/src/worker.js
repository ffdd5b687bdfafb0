// The Web Worker: the language server (server.js) behind postMessage. Messages are JSON-RPC
// objects both ways, as vscode-languageclient's browser client exchanges them with a worker, so a
// web extension can use this worker as the playground does. Messages that arrive while Pyodide
// loads wait in order; a failure to start is told as window/showMessage, and every request then
// gets an error answer instead of none.
import { startServer } from './server.js';

const base = new URL('./', import.meta.url);
const waiting = [];
let receive = null;
let failed = null;

self.onmessage = (event) => {
  if (receive) {
    receive(JSON.stringify(event.data));
  } else if (failed) {
    refuse(event.data);
  } else {
    waiting.push(event.data);
  }
};

function refuse(message) {
  if (message && message.id !== undefined && message.method) {
    self.postMessage({ jsonrpc: '2.0', id: message.id, error: { code: -32002, message: `the server did not start: ${failed}` } });
  }
}

async function start() {
  const { loadPyodide } = await import(new URL('pyodide/pyodide.mjs', base).href);
  const site = fetch(new URL('site.zip', base)).then((r) => {
    if (!r.ok) throw new Error(`site.zip: HTTP ${r.status}`);
    return r.arrayBuffer();
  });
  const timings = {};
  const take = await startServer({
    loadPyodide, indexURL: new URL('pyodide/', base).href, site, timings,
    post: (text) => self.postMessage(JSON.parse(text)),
  });
  // where the start-up went, for the client's log (docs/browser.md, "Cold start and speed")
  self.postMessage({ jsonrpc: '2.0', method: 'window/logMessage', params: { type: 4, message: `ladder: started ${JSON.stringify(timings)}` } });
  for (const message of waiting.splice(0)) take(JSON.stringify(message));
  receive = take;
}

start().catch((error) => {
  failed = String(error && error.message ? error.message : error);
  self.postMessage({ jsonrpc: '2.0', method: 'window/showMessage', params: { type: 1, message: `ladder: the server did not start: ${failed}` } });
  for (const message of waiting.splice(0)) refuse(message);
});
