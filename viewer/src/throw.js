// Click to throw (live mode): a click in the 3D view becomes a `spawn`
// request for a ball launched from just in front of the camera so that, under
// gravity, it reaches the point under the cursor (the first surface hit by
// the click's ray, or a point 10 m along it). The drop over the flight is
// aimed above the target: v = d / t + (0, 0, g t / 2) with t = |d| / speed.
import { Raycaster, Vector2 } from 'three';

/** Launch speed (m/s) and ball radius (m); density is the default 1000 kg/m^3. */
export const THROW_SPEED = 12;
export const BALL_RADIUS = 0.15;
const GRAVITY = 9.81;
const MISS_DISTANCE = 10;
const LAUNCH_OFFSET = 0.6;

/** A three.js world-space point (y up) in tumble's z-up frame. */
export function toTumble(v) {
  return [v.x, -v.z, v.y];
}

/** The spawn request for a ball from `from` that lands on `target` (both z up). */
export function throwRequest(from, target, speed = THROW_SPEED) {
  const d = target.map((x, i) => x - from[i]);
  const t = Math.max(Math.hypot(...d), 1e-6) / speed;
  const velocity = d.map((x) => x / t);
  velocity[2] += 0.5 * GRAVITY * t;
  return { shape: 'sphere', radius: BALL_RADIUS, position: from, velocity };
}

/**
 * The request for a click at (clientX, clientY) on `canvas`: the ray from
 * `camera` through it, against the meshes under `root`.
 */
export function clickRequest(camera, root, canvas, clientX, clientY) {
  const rect = canvas.getBoundingClientRect();
  const ndc = new Vector2(((clientX - rect.left) / rect.width) * 2 - 1, -((clientY - rect.top) / rect.height) * 2 + 1);
  const ray = new Raycaster();
  ray.setFromCamera(ndc, camera);
  const hits = ray.intersectObject(root, true).filter((h) => h.object.visible && h.object.isMesh);
  const target = hits.length ? hits[0].point : ray.ray.at(MISS_DISTANCE, ray.ray.origin.clone());
  const from = ray.ray.at(LAUNCH_OFFSET, ray.ray.origin.clone());
  return throwRequest(toTumble(from), toTumble(target));
}
