// The page's side of the language server in the worker: JSON-RPC requests with promises,
// notifications to handlers, the server's own requests answered (it asks for the settings and
// refreshes nothing the page shows).
export class Client {
  // worker.early (optional): the messages it sent before this client listened (index.html)
  constructor(worker) {
    this.worker = worker;
    this.nextId = 1;
    this.pending = new Map();
    this.handlers = new Map();
    worker.onmessage = (event) => this.received(event.data);
    this.early = worker.early || [];
  }

  on(method, handler) {
    this.handlers.set(method, handler);
  }

  // the messages that came before the handlers were set
  listen() {
    for (const event of this.early.splice(0)) this.received(event.data);
  }

  notify(method, params) {
    this.worker.postMessage({ jsonrpc: '2.0', method, params });
  }

  request(method, params) {
    const id = this.nextId++;
    this.worker.postMessage({ jsonrpc: '2.0', id, method, params });
    return new Promise((resolve, reject) => this.pending.set(id, { resolve, reject }));
  }

  command(command, ...args) {
    return this.request('workspace/executeCommand', { command, arguments: args });
  }

  received(message) {
    if (message.method && message.id !== undefined) {
      // a request of the server's: none needs more than an empty answer here
      this.worker.postMessage({ jsonrpc: '2.0', id: message.id, result: message.method === 'workspace/configuration' ? [{}] : null });
      return;
    }
    if (message.method) {
      const handler = this.handlers.get(message.method);
      if (handler) handler(message.params);
      return;
    }
    const waiting = this.pending.get(message.id);
    if (!waiting) return;
    this.pending.delete(message.id);
    if (message.error) waiting.reject(new Error(message.error.message));
    else waiting.resolve(message.result);
  }
}
