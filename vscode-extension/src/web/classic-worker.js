// Imported first by worker.js, so that it runs before Pyodide's loader is set up. Pyodide refuses
// to start in a classic worker, which it detects by an `importScripts` of a data: URL that
// succeeds. VS Code's web extension host starts this worker as a classic script. Recent versions
// (1.100 in code-server) forbid data: scripts there, so the probe fails and Pyodide starts; older
// ones (1.91, tested with @vscode/test-web) allow them, and Pyodide stopped with "Classic web
// workers are not supported". Pyodide's files are bundled or posted, so nothing here imports
// scripts: without importScripts the probe fails everywhere.
self.importScripts = undefined;
