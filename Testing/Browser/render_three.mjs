// SPDX-License-Identifier: BSD-3-Clause
// Renders a glTF file with three.js (an independent glTF renderer) in Debian's headless
// Chromium, driven by playwright-core, from a page this script serves itself on 127.0.0.1
// (no CDN: three.js comes from .ci/npm-tools). The camera and the light are given on the
// command line, so that MorphNode's render of the same file can use the same ones
// (TestThreeJsSideBySide, docs/materials.md).
//
// node render_three.mjs --npm DIR --glb FILE --out FILE.png [--size 400]
//   [--camera px,py,pz,fx,fy,fz,fovDegrees] [--light intensity] [--background r,g,b]
//   [--chromium /usr/bin/chromium]
// The light is a directional light from the camera towards the focal point (white).
// Exit code 0 with the PNG written, 1 with a message otherwise.
import http from 'node:http';
import fs from 'node:fs';
import path from 'node:path';
import { createRequire } from 'node:module';

function parseArgs(argv) {
  const args = { size: 400, camera: '0,1.545,0.55,0,1.545,0.125,30', light: '3.0', background: '0.3,0.3,0.35',
    chromium: '/usr/bin/chromium' };
  for (let i = 2; i < argv.length; i += 2) {
    const key = argv[i].replace(/^--/, '');
    args[key] = argv[i + 1];
  }
  for (const required of ['npm', 'glb', 'out']) {
    if (!args[required]) {
      throw new Error(`--${required} is required`);
    }
  }
  return args;
}

const page = (size, camera, light, background) => `<!doctype html>
<html><head><meta charset="utf-8">
<script type="importmap">{"imports": {"three": "/three/build/three.module.js",
  "three/addons/": "/three/examples/jsm/"}}</script>
<style>body{margin:0;background:#000}canvas{display:block}</style></head>
<body><script type="module">
import * as THREE from 'three';
import { GLTFLoader } from 'three/addons/loaders/GLTFLoader.js';
import { MeshoptDecoder } from 'three/addons/libs/meshopt_decoder.module.js';
const size = ${size};
const c = [${camera}];
const renderer = new THREE.WebGLRenderer({ antialias: false, preserveDrawingBuffer: true });
renderer.setPixelRatio(1);
renderer.setSize(size, size);
document.body.appendChild(renderer.domElement);
const scene = new THREE.Scene();
scene.background = new THREE.Color().setRGB(${background}, THREE.SRGBColorSpace); // as VTK shows it
const camera = new THREE.PerspectiveCamera(c[6], 1, 0.01, 100);
camera.position.set(c[0], c[1], c[2]);
camera.lookAt(c[3], c[4], c[5]);
const light = new THREE.DirectionalLight(0xffffff, ${light});
light.position.set(c[0], c[1], c[2]);
light.target.position.set(c[3], c[4], c[5]);
scene.add(light, light.target);
const loader = new GLTFLoader();
loader.setMeshoptDecoder(MeshoptDecoder);
loader.load('/model.glb', (gltf) => {
  scene.add(gltf.scene);
  renderer.render(scene, camera);
  window.THREE_REVISION = THREE.REVISION;
  window.renderDone = 'ok';
}, undefined, (error) => { window.renderDone = 'error: ' + error; });
</script></body></html>`;

async function main() {
  const args = parseArgs(process.argv);
  const npm = path.resolve(args.npm);
  const three = path.join(npm, 'node_modules', 'three');
  const require = createRequire(path.join(npm, 'node_modules', 'playwright-core', 'package.json'));
  const { chromium } = require('playwright-core');
  const html = page(Number(args.size), args.camera, args.light, args.background);
  const server = http.createServer((request, response) => {
    const url = decodeURIComponent(new URL(request.url, 'http://localhost').pathname);
    let file = null;
    let type = 'application/octet-stream';
    if (url === '/') {
      response.writeHead(200, { 'Content-Type': 'text/html' });
      response.end(html);
      return;
    }
    if (url === '/model.glb') {
      file = path.resolve(args.glb);
      type = 'model/gltf-binary';
    } else if (url.startsWith('/three/')) {
      file = path.join(three, path.normalize(url.slice('/three/'.length)).replace(/^(\.\.[/\\])+/, ''));
      type = 'text/javascript';
      if (!file.startsWith(three + path.sep)) {
        file = null;
      }
    }
    if (!file || !fs.existsSync(file)) {
      response.writeHead(404);
      response.end();
      return;
    }
    response.writeHead(200, { 'Content-Type': type });
    fs.createReadStream(file).pipe(response);
  });
  await new Promise((resolve) => server.listen(0, '127.0.0.1', resolve));
  const port = server.address().port;
  const browser = await chromium.launch({
    executablePath: args.chromium,
    args: ['--enable-unsafe-swiftshader', '--use-angle=swiftshader', '--no-sandbox', '--disable-gpu',
      '--disable-background-networking', '--disable-extensions', '--disable-default-apps', '--no-first-run',
      '--disable-sync', '--metrics-recording-only', '--mute-audio'],
  });
  try {
    const tab = await browser.newPage({ viewport: { width: Number(args.size), height: Number(args.size) } });
    const messages = [];
    tab.on('console', (m) => messages.push(m.text()));
    tab.on('pageerror', (e) => messages.push(String(e)));
    await tab.goto(`http://127.0.0.1:${port}/`);
    await tab.waitForFunction(() => window.renderDone !== undefined, null, { timeout: 120000 });
    const done = await tab.evaluate(() => window.renderDone);
    if (done !== 'ok') {
      throw new Error(`three.js: ${done}\n${messages.join('\n')}`);
    }
    await tab.locator('canvas').screenshot({ path: args.out });
    console.log(`wrote ${args.out} (three.js r${await tab.evaluate(() => window.THREE_REVISION)})`);
  } finally {
    await browser.close();
    server.close();
  }
}

main().catch((error) => {
  console.error(`render_three: ${error.message || error}`);
  process.exit(1);
});
