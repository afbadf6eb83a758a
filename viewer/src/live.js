// Live mode: `?live=ws://host:port/path` streams JSON messages (format in
// viewer/README.md, "Live mode"):
//   {"type":"scene","bodies":[{"name","color":[r,g,b,a],"is_static",
//                              "vertices":[x,y,z,...],"triangles":[i,j,k,...]}],
//    "joints":[{"name","kind","body":i,"anchor":[x,y,z],"axis":[x,y,z]}]}
//     (a joint's anchor and axis in its body's frame; drawn on that body)
//   {"type":"frame","t":s,"poses":[[x,y,z,qx,qy,qz,qw],...],
//    "kinetic_energy":J,"potential_energy":J,"contact_count":n,
//    "contacts":[[px,py,pz,nx,ny,nz,d],...]}
//   {"type":"bodies_added","bodies":[...as in scene...]}   bodies joined the session
//   {"type":"error","message":"..."}                      a request was refused
// and the page may send {"type":"spawn","shape":"sphere","radius":m,
// "position":[x,y,z],"velocity":[vx,vy,vz]} to add a body (sendSpawn).
// All vectors are in tumble's z-up world frame. Frames are kept so that the
// timeline and plot cover the whole session; a new "scene" message starts over.
// A body added during the session is hidden in frames older than its arrival.
import {
  BoxGeometry,
  BufferAttribute,
  BufferGeometry,
  Group,
  Mesh,
  MeshStandardMaterial,
  OctahedronGeometry,
  Quaternion,
  Vector3,
} from 'three';
import { frameIndexAt } from './timeline.js';

/** Flat-shaded geometry from an indexed triangle list (one vertex per corner). */
function flatGeometry(vertices, triangles) {
  const pos = new Float32Array(3 * triangles.length);
  for (let i = 0; i < triangles.length; i++) {
    const v = triangles[i];
    pos[3 * i] = vertices[3 * v];
    pos[3 * i + 1] = vertices[3 * v + 1];
    pos[3 * i + 2] = vertices[3 * v + 2];
  }
  const g = new BufferGeometry();
  g.setAttribute('position', new BufferAttribute(pos, 3));
  g.computeVertexNormals(); // non-indexed: face normals
  return g;
}

/**
 * Each joint as the glTF recordings draw it: an orange octahedron at the
 * anchor and a bar 0.15 m each way along the axis, children of the joint's
 * body (so they move with it), named `joint:NAME` and `joint:NAME:axis`.
 * Joints naming no body of the scene, or with non-finite vectors, are skipped.
 */
function addJointMarkers(bodyNodes, joints) {
  if (!Array.isArray(joints) || !joints.length) return;
  const mat = new MeshStandardMaterial({ color: 0xff730d, roughness: 0.5, metalness: 0 });
  const marker = new OctahedronGeometry(0.02);
  const bar = new BoxGeometry(0.3, 0.008, 0.008); // along x, turned onto the axis
  const finite3 = (v) => Array.isArray(v) && v.length === 3 && v.every(Number.isFinite);
  joints.forEach((j, k) => {
    const body = bodyNodes[j.body];
    if (!body || !finite3(j.anchor) || !finite3(j.axis)) return;
    const name = j.name || `joint${k}`;
    const axis = new Vector3(...j.axis);
    if (axis.lengthSq() === 0) axis.set(1, 0, 0);
    const anchorNode = new Mesh(marker, mat);
    anchorNode.name = `joint:${name}`;
    anchorNode.position.set(...j.anchor);
    const axisNode = new Mesh(bar, mat);
    axisNode.name = `joint:${name}:axis`;
    axisNode.position.set(...j.anchor);
    axisNode.quaternion.setFromUnitVectors(new Vector3(1, 0, 0), axis.normalize());
    body.add(anchorNode, axisNode);
  });
}

/** A live recording with the same shape as loader.js's file recordings. */
export function createLiveRecording(sceneMsg) {
  const root = new Group();
  const world = new Group();
  world.name = 'tumble_world';
  world.quaternion.setFromAxisAngle(new Vector3(1, 0, 0), -Math.PI / 2); // z-up -> y-up
  root.add(world);
  const makeNode = (b) => {
    const [r, g, bl, a] = b.color ?? [0.7, 0.7, 0.7, 1];
    const mat = new MeshStandardMaterial({ roughness: 0.8, metalness: 0, transparent: a < 1, opacity: a });
    mat.color.setRGB(r, g, bl);
    const mesh = new Mesh(flatGeometry(b.vertices, b.triangles), mat);
    mesh.name = b.name ?? '';
    mesh.userData.tumbleStatic = Boolean(b.is_static);
    world.add(mesh);
    return mesh;
  };
  const bodyNodes = sceneMsg.bodies.map(makeNode);
  addJointMarkers(bodyNodes, sceneMsg.joints);
  const rec = {
    kind: 'live',
    root,
    world,
    bodyNodes,
    times: [],
    poses: [],
    duration: 0,
    extras: { kinetic_energy: [], potential_energy: [], contact_count: [], contacts: [], obb_boxes: [] },
    apply(t) {
      if (!rec.times.length) return;
      const frame = rec.poses[frameIndexAt(rec.times, t)];
      bodyNodes.forEach((node, i) => {
        const p = frame[i];
        node.visible = Boolean(p); // not yet added at this time
        if (!p) return;
        node.position.set(p[0], p[1], p[2]);
        node.quaternion.copy(new Quaternion(p[3], p[4], p[5], p[6]).normalize());
      });
    },
    addBodies(bodies) {
      for (const b of bodies) bodyNodes.push(makeNode(b));
    },
    push(msg) {
      if (rec.times.length && !(msg.t > rec.times[rec.times.length - 1])) return false; // out of order
      rec.times.push(msg.t);
      rec.poses.push(msg.poses);
      rec.extras.kinetic_energy.push(msg.kinetic_energy ?? 0);
      rec.extras.potential_energy.push(msg.potential_energy ?? 0);
      rec.extras.contact_count.push(msg.contact_count ?? (msg.contacts ?? []).length);
      rec.extras.contacts.push(msg.contacts ?? []);
      rec.duration = msg.t;
      return true;
    },
  };
  return rec;
}

/**
 * Connects to `url`; calls onScene(recording) for each scene message,
 * onFrame(recording) after each accepted frame, onBodiesAdded(recording,
 * count) when bodies join, onStatus(text, isError). Returns the WebSocket with
 * `sendSpawn(request)`, which sends a spawn message (false when not open).
 */
export function connectLive(url, { onScene, onFrame, onBodiesAdded, onStatus }) {
  let rec = null;
  const ws = new WebSocket(url);
  ws.addEventListener('open', () => onStatus(`live: connected to ${url}`, false));
  let failed = false;
  ws.addEventListener('error', () => {
    failed = true;
    onStatus(`live: cannot connect to ${url}`, true);
  });
  ws.addEventListener('close', () => failed || onStatus(`live: disconnected from ${url}`, false));
  ws.addEventListener('message', (ev) => {
    let msg;
    try {
      msg = JSON.parse(ev.data);
    } catch {
      onStatus('live: ignored a message that is not JSON', true);
      return;
    }
    if (msg.type === 'scene' && Array.isArray(msg.bodies)) {
      rec = createLiveRecording(msg);
      onScene(rec);
    } else if (msg.type === 'frame' && rec && Array.isArray(msg.poses) && Number.isFinite(msg.t)) {
      if (rec.push(msg)) onFrame(rec);
    } else if (msg.type === 'bodies_added' && rec && Array.isArray(msg.bodies)) {
      rec.addBodies(msg.bodies);
      onBodiesAdded?.(rec, msg.bodies.length);
    } else if (msg.type === 'error') {
      onStatus(`live: the simulation refused a request: ${msg.message}`, true);
    }
  });
  ws.sendSpawn = (request) => {
    if (ws.readyState !== WebSocket.OPEN) return false;
    ws.send(JSON.stringify({ type: 'spawn', ...request }));
    return true;
  };
  return ws;
}
