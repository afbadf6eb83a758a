// Debug overlays drawn over the bodies: contact points and normals (world
// frame, from extras.tumble.contacts or live frames) and OBBTree boxes
// (body frame, from extras.tumble.obb_boxes).
import {
  BoxGeometry,
  BufferAttribute,
  BufferGeometry,
  Color,
  DynamicDrawUsage,
  EdgesGeometry,
  InstancedMesh,
  LineBasicMaterial,
  LineSegments,
  Matrix4,
  MeshBasicMaterial,
  SphereGeometry,
} from 'three';

/** Points and normals of the current frame's contacts. */
export class ContactOverlay {
  constructor(parent, scale) {
    this.capacity = 0;
    this.parent = parent;
    this.radius = 0.012 * scale;
    this.normalLength = 0.12 * scale;
    this.material = new MeshBasicMaterial({ color: 0xffd400, depthTest: false });
    this.points = null;
    this.lineGeometry = new BufferGeometry();
    this.normals = new LineSegments(this.lineGeometry, new LineBasicMaterial({ color: 0xff3d7f, depthTest: false }));
    this.normals.renderOrder = 10;
    this.normals.frustumCulled = false;
    parent.add(this.normals);
    this.grow(16);
  }

  grow(n) {
    if (n <= this.capacity) return;
    this.capacity = Math.max(n, 2 * this.capacity);
    if (this.points) {
      this.parent.remove(this.points);
      this.points.dispose();
    }
    this.points = new InstancedMesh(new SphereGeometry(this.radius, 10, 6), this.material, this.capacity);
    this.points.instanceMatrix.setUsage(DynamicDrawUsage);
    this.points.renderOrder = 11;
    this.points.frustumCulled = false;
    this.points.visible = this.showPoints ?? true;
    this.parent.add(this.points);
    const pos = new BufferAttribute(new Float32Array(6 * this.capacity), 3);
    pos.setUsage(DynamicDrawUsage);
    this.lineGeometry.setAttribute('position', pos);
  }

  /** contacts: array of [px, py, pz, nx, ny, nz, distance] in tumble's world frame. */
  update(contacts) {
    const list = contacts ?? [];
    this.grow(list.length);
    const m = new Matrix4();
    const pos = this.lineGeometry.getAttribute('position');
    list.forEach((c, i) => {
      m.makeTranslation(c[0], c[1], c[2]);
      this.points.setMatrixAt(i, m);
      pos.setXYZ(2 * i, c[0], c[1], c[2]);
      const L = this.normalLength;
      pos.setXYZ(2 * i + 1, c[0] + L * c[3], c[1] + L * c[4], c[2] + L * c[5]);
    });
    this.points.count = list.length;
    this.points.instanceMatrix.needsUpdate = true;
    pos.needsUpdate = true;
    this.lineGeometry.setDrawRange(0, 2 * list.length);
  }

  setVisible(points, normals) {
    this.showPoints = points;
    this.points.visible = points;
    this.normals.visible = normals;
  }
}

const DEPTH_COLORS = [0x40c4ff, 0x69f0ae, 0xffd740, 0xff6e40, 0xe040fb];

/** Wireframe boxes attached to body nodes so that they move with the bodies. */
export class ObbOverlay {
  constructor(boxes, bodyNodes) {
    this.lines = [];
    for (const b of boxes ?? []) {
      const node = bodyNodes[b.body];
      if (!node) continue;
      const [hx, hy, hz] = b.half_extents;
      const geometry = new EdgesGeometry(new BoxGeometry(2 * hx, 2 * hy, 2 * hz));
      const color = new Color(DEPTH_COLORS[(b.depth ?? 0) % DEPTH_COLORS.length]);
      const line = new LineSegments(geometry, new LineBasicMaterial({ color }));
      line.position.fromArray(b.center);
      line.quaternion.fromArray(b.rotation);
      line.visible = false;
      node.add(line);
      this.lines.push(line);
    }
  }

  get count() {
    return this.lines.length;
  }

  setVisible(v) {
    for (const l of this.lines) l.visible = v;
  }
}
