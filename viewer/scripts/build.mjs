// Builds the viewer into dist/: esbuild bundles src/main.js (three.js
// included) and its CSS into dist/assets/, and index.html is copied as is.
// `node scripts/build.mjs --watch` rebuilds on change (pair it with
// `node scripts/serve.mjs` for development).
import { copyFileSync, mkdirSync, rmSync } from 'node:fs';
import { join, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';
import * as esbuild from 'esbuild';

const here = resolve(fileURLToPath(import.meta.url), '../..');
const dist = join(here, 'dist');
rmSync(dist, { recursive: true, force: true });
mkdirSync(join(dist, 'assets'), { recursive: true });
copyFileSync(join(here, 'index.html'), join(dist, 'index.html'));

const options = {
  entryPoints: [join(here, 'src/main.js')],
  bundle: true,
  format: 'esm',
  target: 'es2022',
  minify: true,
  sourcemap: true,
  outdir: join(dist, 'assets'),
  logLevel: 'warning',
};
if (process.argv.includes('--watch')) {
  const ctx = await esbuild.context(options);
  await ctx.watch();
  console.log('watching src/ ...');
} else {
  await esbuild.build(options);
}
