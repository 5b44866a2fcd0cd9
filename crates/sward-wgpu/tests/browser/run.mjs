// Runs the portable renderer's WGSL in headless Chromium's WebGPU (SwiftShader, no GPU needed):
// serves page.html, page.mjs and the fixture folder the Rust test wrote, starts Chromium on the
// page, and writes what the page posts back (buffers, messages) into the fixture folder. A
// fixture folder holding a page.html of its own (sward-web's page and its wasm build) is served
// that page instead.
//
//   node run.mjs FIXTURE_DIR [CHROMIUM]
//
// SWARD_PAGE_TIMEOUT_S sets how long the page may take (240 s unless set); SWARD_PAGE_PRESENTS=1
// starts Chromium for a page that presents frames to a canvas.
// Exits non-zero with one line when Chromium cannot be started or the page does not finish.
import { createServer } from 'node:http';
import { spawn } from 'node:child_process';
import { mkdtempSync, readFileSync, writeFileSync, existsSync, rmSync } from 'node:fs';
import { join, dirname, basename } from 'node:path';
import { tmpdir } from 'node:os';
import { fileURLToPath } from 'node:url';

const here = dirname(fileURLToPath(import.meta.url));
const [fixture, chromium = '/usr/bin/chromium'] = process.argv.slice(2);
// A cold Chromium with SwiftShader compiling every pipeline takes a while on two cores.
const TIMEOUT_MS = 1000 * Number(process.env.SWARD_PAGE_TIMEOUT_S || 240);

function fail(line) {
  console.error(line);
  process.exit(1);
}

if (!fixture || !existsSync(fixture)) fail('usage: node run.mjs FIXTURE_DIR [CHROMIUM]');
if (!existsSync(chromium)) fail(`no Chromium at ${chromium} (Debian/Ubuntu: apt-get install chromium)`);

const types = {
  '.html': 'text/html', '.mjs': 'text/javascript', '.js': 'text/javascript', '.json': 'application/json',
  '.wasm': 'application/wasm',
};
const ownPage = existsSync(join(fixture, 'page.html'));
let browser;
const server = createServer((req, res) => {
  const name = basename(req.url.split('?')[0]);
  if (req.method === 'POST') {
    const parts = [];
    req.on('data', (c) => parts.push(c));
    req.on('end', () => {
      writeFileSync(join(fixture, `out-${name}`), Buffer.concat(parts));
      res.end('ok');
      if (name === 'done') finish(0);
    });
    return;
  }
  const fromHere = !ownPage && ['page.html', 'page.mjs'].includes(name);
  const path = fromHere ? join(here, name) : join(fixture, name);
  if (!existsSync(path)) {
    res.statusCode = 404;
    res.end();
    return;
  }
  res.setHeader('Content-Type', types[name.slice(name.lastIndexOf('.'))] ?? 'application/octet-stream');
  res.end(readFileSync(path));
});

const profile = mkdtempSync(join(tmpdir(), 'sward-chromium-'));
let finished = false;
function finish(code, line) {
  if (finished) return;
  finished = true;
  if (line) console.error(line);
  if (browser) browser.kill('SIGKILL');
  server.close();
  // Chromium may still be writing its profile as it dies: what is left is a temporary folder.
  try {
    rmSync(profile, { recursive: true, force: true });
  } catch {}
  process.exit(code);
}

server.listen(0, '127.0.0.1', () => {
  const url = `http://127.0.0.1:${server.address().port}/page.html`;
  // WebGPU on SwiftShader's Vulkan, as the WebGPU adapter of a machine without a GPU.
  // A page that presents to a canvas (Bevy's window) needs Chromium's compositor on ANGLE's
  // Vulkan too: with its default GL, the canvas's swap chain has no shared image and the
  // device is lost at the first frame.
  const presents = process.env.SWARD_PAGE_PRESENTS === '1';
  const flags = [
    '--headless', '--no-sandbox', '--no-first-run', '--disable-gpu-sandbox', `--user-data-dir=${profile}`,
    '--enable-unsafe-webgpu', '--enable-features=Vulkan', '--use-vulkan=swiftshader',
    '--use-webgpu-adapter=swiftshader', ...(presents ? ['--use-angle=vulkan'] : ['--disable-vulkan-surface']), url,
  ];
  browser = spawn(chromium, flags, { stdio: ['ignore', 'ignore', 'pipe'] });
  let log = '';
  browser.stderr.on('data', (d) => { log = (log + d).slice(-4000); });
  browser.on('exit', (code) => finish(1, `Chromium ended (exit ${code}) before the page finished: ${log.split('\n').filter(Boolean).slice(-3).join(' | ')}`));
  setTimeout(() => finish(1, `the page did not finish within ${TIMEOUT_MS / 1000} s`), TIMEOUT_MS);
});
