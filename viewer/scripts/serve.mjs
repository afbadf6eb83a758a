// A tiny static file server for the viewer test (and for trying the viewer
// by hand: `node scripts/serve.mjs [port]` serves dist/ and out/viewer-test/).
// Only 127.0.0.1 is bound. `/live` accepts WebSocket upgrades and hands each
// connection to `onLive(send)`, enough for the live-mode test (server to
// client text frames only, RFC 6455 section 5.2).
import { createHash } from 'node:crypto';
import { createReadStream, statSync } from 'node:fs';
import { createServer } from 'node:http';
import { extname, join, normalize, resolve } from 'node:path';
import { fileURLToPath } from 'node:url';

const TYPES = {
  '.html': 'text/html; charset=utf-8',
  '.js': 'text/javascript; charset=utf-8',
  '.css': 'text/css; charset=utf-8',
  '.glb': 'model/gltf-binary',
  '.png': 'image/png',
  '.json': 'application/json',
  '.csv': 'text/csv',
};

function safeJoin(root, urlPath) {
  const p = normalize(decodeURIComponent(urlPath)).replace(/^(\.\.[/\\])+/, '');
  const full = resolve(join(root, p));
  return full.startsWith(resolve(root)) ? full : null;
}

function wsFrame(text) {
  const payload = Buffer.from(text, 'utf8');
  const n = payload.length;
  let header;
  if (n < 126) header = Buffer.from([0x81, n]);
  else if (n < 65536) {
    header = Buffer.alloc(4);
    header[0] = 0x81;
    header[1] = 126;
    header.writeUInt16BE(n, 2);
  } else {
    header = Buffer.alloc(10);
    header[0] = 0x81;
    header[1] = 127;
    header.writeBigUInt64BE(BigInt(n), 2);
  }
  return Buffer.concat([header, payload]);
}

/** Serves `root` at / and `fixtureDir` at /fixture/; resolves to { port, close }. */
export function startServer({ root, fixtureDir, port = 0, onLive = null }) {
  const server = createServer((req, res) => {
    const url = new URL(req.url, 'http://127.0.0.1');
    let path = url.pathname;
    let base = root;
    if (path.startsWith('/fixture/')) {
      base = fixtureDir;
      path = path.slice('/fixture'.length);
    }
    if (path.endsWith('/')) path += 'index.html';
    const file = safeJoin(base, path);
    let st = null;
    try {
      st = file && statSync(file);
    } catch {
      st = null;
    }
    if (!st || !st.isFile()) {
      res.writeHead(404, { 'content-type': 'text/plain' });
      res.end('not found');
      return;
    }
    res.writeHead(200, {
      'content-type': TYPES[extname(file)] ?? 'application/octet-stream',
      'content-length': st.size,
      'cache-control': 'no-store',
    });
    createReadStream(file).pipe(res);
  });
  const upgraded = new Set();
  server.on('upgrade', (req, socket) => {
    upgraded.add(socket);
    socket.on('close', () => upgraded.delete(socket));
    const key = req.headers['sec-websocket-key'];
    if (!onLive || !key || !req.url.startsWith('/live')) {
      socket.destroy();
      return;
    }
    const accept = createHash('sha1').update(`${key}258EAFA5-E914-47DA-95CA-C5AB0DC85B11`).digest('base64');
    socket.write(
      'HTTP/1.1 101 Switching Protocols\r\nUpgrade: websocket\r\nConnection: Upgrade\r\n' +
        `Sec-WebSocket-Accept: ${accept}\r\n\r\n`,
    );
    socket.on('error', () => socket.destroy());
    socket.on('data', (buf) => {
      if ((buf[0] & 0x0f) === 0x8) socket.end(); // client close frame
    });
    onLive((text) => socket.write(wsFrame(text)));
  });
  return new Promise((ok, fail) => {
    server.once('error', fail);
    server.listen(port, '127.0.0.1', () =>
      ok({
        port: server.address().port,
        close: () =>
          new Promise((done) => {
            for (const s of upgraded) s.destroy();
            server.closeAllConnections?.();
            server.close(() => done());
          }),
      }),
    );
  });
}

if (process.argv[1] === fileURLToPath(import.meta.url)) {
  const here = resolve(fileURLToPath(import.meta.url), '../..');
  const port = Number(process.argv[2] ?? 8123);
  const { port: p } = await startServer({
    root: join(here, 'dist'),
    fixtureDir: resolve(here, '../out/viewer-test'),
    port,
  });
  console.log(`serving viewer/dist on http://127.0.0.1:${p}/  (try ?file=/fixture/fixture.glb)`);
}
