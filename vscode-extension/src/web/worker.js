// The web extension's Web Worker: the playground's language server worker (web/src/serve.js), with
// Pyodide bundled in and its files from memory. web/extension.ts starts it from a blob: URL, from
// which nothing relative can be fetched, and posts the files first ({textladderFiles}: the
// WebAssembly, the standard library, the lock file, site.zip). A classic script: VS Code's web
// extension host starts workers through importScripts.
import './classic-worker.js';
import { loadPyodide } from 'pyodide';
import createPyodideModule from 'pyodide/pyodide.asm.mjs';
import { serve } from '../../../web/src/serve.js';

// Pyodide fetches its files under indexURL: those fetches are answered from memory
const INDEX = 'https://textladder.invalid/pyodide/';

let arrived;
const files = new Promise((resolve, reject) => {
  arrived = (data) => (data.textladderFiles ? resolve(data.textladderFiles) : reject(new Error(data.error)));
});

serve(
  async () => {
    const { wasm, stdlib, lock, site } = await files;
    const inMemory = {
      'pyodide.asm.wasm': [wasm, 'application/wasm'],
      'python_stdlib.zip': [stdlib, 'application/zip'],
      'pyodide-lock.json': [lock, 'application/json'],
    };
    const fetchOver = self.fetch.bind(self);
    self.fetch = (url, init) => {
      const text = String(url);
      const file = text.startsWith(INDEX) ? inMemory[text.slice(INDEX.length)] : undefined;
      return file ? Promise.resolve(new Response(file[0], { headers: { 'Content-Type': file[1] } })) : fetchOver(url, init);
    };
    return { loadPyodide, indexURL: INDEX, site, pyodide: { createPyodideModule } };
  },
  (data) => {
    if (data && 'textladderFiles' in data) {
      arrived(data);
      return true;
    }
    return false;
  },
);
