// Builds the browser entry of the extension into out/web/ (docs/browser.md, "The VS Code web
// extension"): extension.js (src/web/extension.ts), worker.js (src/web/worker.js, Pyodide's loader
// bundled in), pyodide/ (the WebAssembly, the lock file, the standard library trimmed and
// precompiled) and site.zip: the playground's own files, made by web/pyodide-files.mjs.
//
//   node scripts/web.mjs      (PYTHON: the Python that builds the wheel and runs pip; default python3)
import fs from 'node:fs';
import path from 'node:path';
import { fileURLToPath } from 'node:url';
import * as esbuild from 'esbuild';
import { pyodideFiles } from '../../web/pyodide-files.mjs';

const HERE = path.resolve(path.dirname(fileURLToPath(import.meta.url)), '..');
const OUT = path.join(HERE, 'out', 'web');

async function main() {
  fs.rmSync(OUT, { recursive: true, force: true });
  await pyodideFiles({
    pyodideDir: path.join(HERE, 'node_modules', 'pyodide'), out: OUT, python: process.env.PYTHON || 'python3',
    core: ['pyodide.asm.wasm'],
  });
  const common = { bundle: true, minify: true, platform: 'browser', target: 'es2022', logLevel: 'warning' };
  await esbuild.build({
    ...common, entryPoints: [path.join(HERE, 'src', 'web', 'extension.ts')], outfile: path.join(OUT, 'extension.js'),
    format: 'cjs', external: ['vscode'],
  });
  // Pyodide's loaders reach Node's modules only when they run under Node
  await esbuild.build({
    ...common, entryPoints: [path.join(HERE, 'src', 'web', 'worker.js')], outfile: path.join(OUT, 'worker.js'),
    format: 'iife', external: ['node:*', 'ws'],
  });
  process.stderr.write(`build: done: ${OUT}\n`);
  process.exit(0); // the server exercised in pyodideFiles() left its timers running
}

main().catch((error) => {
  process.stderr.write(`build: ${error.stack || error}\n`);
  process.exit(1);
});
