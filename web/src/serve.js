// A Web Worker's side of the language server: postMessage in, postMessage out. Messages are
// JSON-RPC objects both ways, as vscode-languageclient's browser client exchanges them with a
// worker, so the playground's worker (worker.js) and the VS Code web extension's
// (vscode-extension/src/web/worker.js) are this one piece, each with its own way to reach
// Pyodide's files. Messages that arrive while Pyodide loads wait in order; a failure to start is
// told as window/showMessage, and every request then gets an error answer instead of none.
//
// locate(): resolves to startServer's options but post and timings (server.js).
// claim(data) (optional): true for a message of the worker's own, which is not passed to the server.
import { startServer } from './server.js';

export function serve(locate, claim = () => false) {
  const waiting = [];
  let receive = null;
  let failed = null;

  const refuse = (message) => {
    if (message && message.id !== undefined && message.method) {
      self.postMessage({ jsonrpc: '2.0', id: message.id, error: { code: -32002, message: `the server did not start: ${failed}` } });
    }
  };

  self.onmessage = (event) => {
    if (claim(event.data)) {
      return;
    }
    if (receive) {
      receive(JSON.stringify(event.data));
    } else if (failed) {
      refuse(event.data);
    } else {
      waiting.push(event.data);
    }
  };

  const start = async () => {
    const timings = {};
    const take = await startServer({ ...(await locate()), timings, post: (text) => self.postMessage(JSON.parse(text)) });
    // where the start-up went, for the client's log (docs/browser.md, "Cold start and speed")
    self.postMessage({ jsonrpc: '2.0', method: 'window/logMessage', params: { type: 4, message: `ladder: started ${JSON.stringify(timings)}` } });
    for (const message of waiting.splice(0)) take(JSON.stringify(message));
    receive = take;
  };

  start().catch((error) => {
    failed = String(error && error.message ? error.message : error);
    self.postMessage({ jsonrpc: '2.0', method: 'window/showMessage', params: { type: 1, message: `ladder: the server did not start: ${failed}` } });
    for (const message of waiting.splice(0)) refuse(message);
  });
}
