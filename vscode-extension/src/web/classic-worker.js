// Imported first by worker.js, so that it runs before Pyodide's loader is set up. Pyodide refuses
// to start in a classic worker, which it detects by an `importScripts` of a data: URL that
// succeeds. VS Code's web extension host starts this worker as a classic script. In VS Code 1.100
// (code-server) the probe fails there and Pyodide starts; in 1.91 (tested with @vscode/test-web)
// it succeeds, and Pyodide stopped with "Classic web workers are not supported". Pyodide's files
// are bundled or posted, so nothing here imports scripts: without importScripts the probe fails
// everywhere.
self.importScripts = undefined;
