// Starts textladder's language server on Pyodide (lsp/worker.py) and returns the function that
// takes the client's messages. Shared by the Web Workers (serve.js) and the Node test
// (tests/web_worker_node.mjs), so that both run the same start-up.
//
// site: the bytes of site.zip (textladder and its packages, precompiled by build.mjs).
// post(text): receives each message of the server, as JSON text.
// timings (optional): filled with the milliseconds of each stage (docs/browser.md, "Cold start").
// pyodide (optional): more options of loadPyodide, which replace these (the web extension gives
// Pyodide its files from memory: vscode-extension/src/web/worker.js).
export async function startServer({ loadPyodide, indexURL, site, post, timings = {}, pyodide = {} }) {
  let last = performance.now();
  const stage = (name) => {
    const now = performance.now();
    timings[name] = Math.round(now - last);
    last = now;
  };
  const py = await loadPyodide({
    indexURL,
    // the precompiled standard library (build.mjs), not the one Pyodide's package ships with
    stdLibURL: `${indexURL}python_stdlib.zip`,
    stdout: () => {},
    stderr: (line) => console.warn(line),
    ...pyodide,
  });
  stage('loadPyodideMs');
  py.unpackArchive(await site, 'zip', { extractDir: '/site' });
  stage('unpackMs');
  py.runPython('import sys; sys.path.insert(0, "/site")');
  // the methods attrs and cattrs write as the server starts, compiled by the build (lsp/worker_compile.py)
  const precompiled = py.pyimport('lsp.worker_compile');
  precompiled.install('/site/lsp/start-code.marshal');
  precompiled.destroy();
  const worker = py.pyimport('lsp.worker');
  stage('importMs');
  const receive = worker.connect((text) => post(text));
  worker.destroy();
  stage('connectMs');
  return (text) => receive(text);
}
