// The tumble viewer page: loads a recording (?file=URL, file picker or
// drag-and-drop) or connects to a live stream (?live=ws://...), plays it with
// an orbit camera, and draws contact / OBB overlays and an energy plot.
// Other query parameters: ?t=SECONDS (start time), ?paused=1, ?speed=X.
// In live mode a click (without dragging) in the 3D view throws a ball at the
// point clicked (throw.js; a `spawn` message to the simulation).
// window.tumbleViewer exposes the state for scripts/test.mjs.
import {
  ACESFilmicToneMapping,
  Box3,
  Color,
  DirectionalLight,
  GridHelper,
  HemisphereLight,
  PerspectiveCamera,
  Scene,
  Sphere,
  SRGBColorSpace,
  Vector3,
  WebGLRenderer,
} from 'three';
import { OrbitControls } from 'three/examples/jsm/controls/OrbitControls.js';
import { loadGlb, loadGlbUrl } from './loader.js';
import { connectLive } from './live.js';
import { ContactOverlay, ObbOverlay } from './overlays.js';
import { EnergyPlot } from './plot.js';
import { formatTime, frameIndexAt } from './timeline.js';
import { clickRequest } from './throw.js';
import './style.css';

const $ = (id) => document.getElementById(id);
const params = new URLSearchParams(location.search);

const renderer = new WebGLRenderer({ antialias: true });
renderer.setPixelRatio(window.devicePixelRatio);
renderer.outputColorSpace = SRGBColorSpace;
renderer.toneMapping = ACESFilmicToneMapping;
$('viewport').appendChild(renderer.domElement);

const scene = new Scene();
scene.background = new Color(0x1d2026);
scene.add(new HemisphereLight(0xdde8ff, 0x403830, 1.2));
const sun = new DirectionalLight(0xffffff, 2.0);
sun.position.set(3, 8, 5);
scene.add(sun);
const camera = new PerspectiveCamera(45, 1, 0.01, 1000);
camera.position.set(4, 3, 6);
const controls = new OrbitControls(camera, renderer.domElement);
controls.enableDamping = true;

const state = {
  status: 'empty', // empty | loading | ready | error
  rec: null,
  time: Number(params.get('t') ?? 0) || 0,
  playing: params.get('paused') !== '1',
  speed: Number(params.get('speed') ?? 1) || 1,
  follow: true, // live mode: stay at the newest frame while playing
  contacts: null,
  obb: null,
  grid: null,
  framesRendered: 0,
  thrown: 0, // live mode: balls the simulation added for this page
};
$('speed').value = String(state.speed);

const plot = new EnergyPlot($('plot'), (t) => seek(t));

function setStatus(text, isError = false) {
  $('status').textContent = text;
  $('status').classList.toggle('error', isError);
}

function seek(t) {
  state.time = Math.min(Math.max(t, 0), state.rec?.duration ?? 0);
  state.follow = false;
  applyTime();
}

function setPlaying(p) {
  state.playing = p;
  $('play').textContent = p ? 'pause' : 'play';
  if (p && state.rec && state.rec.kind === 'file' && state.time >= state.rec.duration) state.time = 0;
  if (p) state.follow = true;
}

function applyTime() {
  const rec = state.rec;
  if (!rec) return;
  rec.apply(state.time);
  const f = frameIndexAt(rec.times, state.time);
  state.contacts?.update(rec.extras.contacts?.[f]);
  $('scrubber').max = String(rec.duration || 1);
  $('scrubber').value = String(state.time);
  $('clock').textContent = `${formatTime(state.time)} / ${formatTime(rec.duration)}`;
  plot.setCursor(state.time);
}

/** Replaces the shown recording and frames the camera on it. */
function show(rec, { reframe = true } = {}) {
  if (state.rec) scene.remove(state.rec.root);
  if (state.grid) scene.remove(state.grid);
  state.rec = rec;
  scene.add(rec.root);
  rec.apply(0);
  rec.root.updateMatrixWorld(true);
  // Frame everything, unless static bodies dwarf the moving ones (a
  // half-space is drawn as a slab tens of metres wide): then frame the
  // moving bodies with room around them.
  const all = new Box3().setFromObject(rec.root);
  let sphere = all.isEmpty() ? new Sphere(new Vector3(), 1) : all.getBoundingSphere(new Sphere());
  const moving = new Box3();
  for (const node of rec.bodyNodes) if (!node.userData.tumbleStatic) moving.expandByObject(node);
  if (!moving.isEmpty()) {
    const m = moving.getBoundingSphere(new Sphere());
    if (sphere.radius > 3 * m.radius) sphere = new Sphere(m.center, 3 * m.radius);
  }
  const R = Math.max(sphere.radius, 1e-3);
  state.contacts = new ContactOverlay(rec.world, R);
  state.obb = new ObbOverlay(rec.extras.obb_boxes, rec.bodyNodes);
  $('show-obb').disabled = state.obb.count === 0;
  $('obb-label').textContent = state.obb.count ? `OBBTree boxes (${state.obb.count})` : 'OBBTree boxes (none in file)';
  applyToggles();
  // The ground grid lies in tumble's z = 0 plane (y = 0 after the root rotation).
  state.grid = new GridHelper(Math.ceil(4 * R), Math.ceil(4 * R) * 2, 0x556070, 0x343a44);
  scene.add(state.grid);
  if (reframe) {
    controls.target.copy(sphere.center);
    camera.position.copy(sphere.center).add(new Vector3(1.1, 0.8, 1.6).multiplyScalar(0.95 * R));
    camera.near = R / 100;
    camera.far = R * 100;
    camera.updateProjectionMatrix();
    controls.update();
  }
  updatePlot();
  state.time = Math.min(state.time, rec.duration);
  state.status = 'ready';
  applyTime();
}

function updatePlot() {
  const x = state.rec.extras;
  plot.setData(state.rec.times, x.kinetic_energy, x.potential_energy, x.contact_count);
}

function applyToggles() {
  state.contacts?.setVisible($('show-contacts').checked, $('show-normals').checked);
  state.obb?.setVisible($('show-obb').checked);
}

async function open(what, label) {
  state.status = 'loading';
  setStatus(`loading ${label} ...`);
  try {
    const rec = typeof what === 'string' ? await loadGlbUrl(what) : await loadGlb(await what.arrayBuffer());
    show(rec);
    setStatus(`${label}: ${rec.bodyNodes.length} bodies, ${rec.times.length} frames, ${formatTime(rec.duration)}`);
  } catch (e) {
    state.status = 'error';
    setStatus(`cannot load ${label}: ${e.message ?? e}`, true);
  }
}

// --- UI wiring ---------------------------------------------------------------
$('play').addEventListener('click', () => setPlaying(!state.playing));
$('scrubber').addEventListener('input', (e) => seek(Number(e.target.value)));
$('speed').addEventListener('change', (e) => (state.speed = Number(e.target.value)));
for (const id of ['show-contacts', 'show-normals', 'show-obb']) $(id).addEventListener('change', applyToggles);
$('file-input').addEventListener('change', (e) => e.target.files[0] && open(e.target.files[0], e.target.files[0].name));
window.addEventListener('keydown', (e) => {
  if (e.code === 'Space' && e.target === document.body) {
    e.preventDefault();
    setPlaying(!state.playing);
  }
});
window.addEventListener('dragover', (e) => {
  e.preventDefault();
  $('drop-hint').classList.remove('hidden');
});
window.addEventListener('dragleave', () => $('drop-hint').classList.add('hidden'));
window.addEventListener('drop', (e) => {
  e.preventDefault();
  $('drop-hint').classList.add('hidden');
  const file = e.dataTransfer?.files?.[0];
  if (file) open(file, file.name);
});

function resize() {
  const w = window.innerWidth;
  const h = window.innerHeight;
  renderer.setSize(w, h);
  camera.aspect = w / h;
  camera.updateProjectionMatrix();
  plot.draw();
}
window.addEventListener('resize', resize);
resize();
setPlaying(state.playing);

// --- main loop -----------------------------------------------------------------
let last = performance.now();
function frame(now) {
  const dt = Math.min((now - last) / 1000, 0.1);
  last = now;
  const rec = state.rec;
  if (rec && state.playing) {
    if (rec.kind === 'live') {
      state.time = state.follow ? rec.duration : Math.min(state.time + dt * state.speed, rec.duration);
    } else {
      state.time += dt * state.speed;
      if (state.time > rec.duration) state.time = rec.duration > 0 ? state.time % rec.duration : 0; // loop
    }
    applyTime();
  }
  controls.update();
  renderer.render(scene, camera);
  state.framesRendered++;
  requestAnimationFrame(frame);
}
requestAnimationFrame(frame);

// --- sources -------------------------------------------------------------------
const live = params.get('live');
const file = params.get('file');
let liveSocket = null;
if (live) {
  state.status = 'loading';
  setStatus(`live: connecting to ${live} ...`);
  liveSocket = connectLive(live, {
    onScene: (rec) => {
      show(rec);
      setStatus(`live: ${rec.bodyNodes.length} bodies (click to throw a ball)`);
    },
    onFrame: (rec) => {
      if (rec.times.length === 1) show(rec); // frame the camera on the first poses
      else if (rec.times.length % 10 === 0) updatePlot();
      if (!state.playing || !state.follow) applyTime();
    },
    onBodiesAdded: (rec, n) => {
      state.thrown += n;
      setStatus(`live: ${rec.bodyNodes.length} bodies, ${state.thrown} thrown`);
    },
    onStatus: setStatus,
  });
  // A click is a press and release without dragging (a drag orbits the camera).
  let press = null;
  renderer.domElement.addEventListener('pointerdown', (e) => (press = e.button === 0 ? [e.clientX, e.clientY] : null));
  renderer.domElement.addEventListener('pointerup', (e) => {
    if (!press || !state.rec || Math.hypot(e.clientX - press[0], e.clientY - press[1]) > 5) return;
    press = null;
    state.rec.root.updateMatrixWorld(true);
    const request = clickRequest(camera, state.rec.root, renderer.domElement, e.clientX, e.clientY);
    if (liveSocket.sendSpawn(request)) state.follow = true;
  });
} else if (file) {
  open(file, file.split('/').pop());
}

window.tumbleViewer = {
  get status() {
    return state.status;
  },
  get time() {
    return state.time;
  },
  get duration() {
    return state.rec?.duration ?? 0;
  },
  get frames() {
    return state.rec?.times.length ?? 0;
  },
  get bodies() {
    return state.rec?.bodyNodes.length ?? 0;
  },
  /** Joint anchors drawn (nodes named `joint:NAME`), in world coordinates, z up. */
  get jointAnchors() {
    const out = [];
    state.rec?.root.updateMatrixWorld(true);
    state.rec?.world.traverse((n) => {
      if (!n.name.startsWith('joint:') || n.name.endsWith(':axis')) return;
      const p = n.getWorldPosition(new n.position.constructor());
      out.push([p.x, -p.z, p.y]); // the viewer's y-up back to tumble's z-up
    });
    return out;
  },
  get framesRendered() {
    return state.framesRendered;
  },
  get thrown() {
    return state.thrown;
  },
  /** The newest frame's poses [[x, y, z, qx, qy, qz, qw], ...] (z up). */
  get lastPoses() {
    const p = state.rec?.poses;
    return p && p.length ? p[p.length - 1] : [];
  },
  get statusText() {
    return $('status').textContent;
  },
  seek,
  setPlaying,
};
