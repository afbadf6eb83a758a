// Loads a tumble .glb (see crates/tumble/src/export/glb.rs for the layout
// and the `extras.tumble` schema) into a playable recording:
//   { root, world, bodyNodes, times, duration, extras, apply(t) }
// `world` is the node carrying the z-up -> y-up rotation, so overlays in
// tumble's world frame (contacts) are added under it unchanged.
import { AnimationMixer, Group } from 'three';
import { GLTFLoader } from 'three/examples/jsm/loaders/GLTFLoader.js';

/** Parses GLB bytes; rejects with a readable message on malformed input. */
export async function loadGlb(bytes) {
  const gltf = await new GLTFLoader().parseAsync(bytes, '');
  const x = gltf.userData?.tumble ?? {};
  const root = new Group();
  root.add(gltf.scene);
  // Without tumble extras (any other glTF) the scene is shown as it is.
  const world = x.root_node !== undefined ? await gltf.parser.getDependency('node', x.root_node) : gltf.scene;
  const bodyNodes = await Promise.all((x.bodies ?? []).map((b) => gltf.parser.getDependency('node', b.node)));
  // Static bodies (a ground slab tens of metres wide) are left out of the camera framing.
  bodyNodes.forEach((n, i) => (n.userData.tumbleStatic = Boolean(x.bodies[i].is_static)));

  const clip = gltf.animations[0];
  const mixer = new AnimationMixer(gltf.scene);
  let action = null;
  if (clip) {
    action = mixer.clipAction(clip);
    action.play();
  }
  const times = x.frame_times ?? (clip ? Array.from(clip.tracks[0].times) : [0]);
  const duration = Math.max(clip ? clip.duration : 0, times[times.length - 1] ?? 0);

  return {
    kind: 'file',
    root,
    world,
    bodyNodes,
    times,
    duration,
    extras: x,
    apply(t) {
      if (!action) return;
      // Setting the action time and updating by 0 evaluates the LINEAR
      // tracks at exactly t (clamped at the ends) without looping logic.
      action.time = Math.min(Math.max(t, 0), clip.duration);
      mixer.update(0);
    },
  };
}

/** Fetches a .glb by URL and loads it. */
export async function loadGlbUrl(url) {
  const res = await fetch(url);
  if (!res.ok) throw new Error(`cannot fetch ${url}: HTTP ${res.status}`);
  return loadGlb(await res.arrayBuffer());
}
