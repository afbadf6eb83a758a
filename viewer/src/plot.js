// A small canvas plot of kinetic, potential and total energy (left axis, J)
// and contact count (right axis, step line) against time, with a cursor at
// the current time. Clicking or dragging seeks.

const COLORS = { kinetic: '#ff7043', potential: '#42a5f5', total: '#e0e0e0', contacts: '#66bb6a' };

export class EnergyPlot {
  constructor(canvas, onSeek) {
    this.canvas = canvas;
    this.onSeek = onSeek;
    this.series = null;
    this.cursor = 0;
    let dragging = false;
    const seek = (e) => {
      if (!this.series) return;
      const r = canvas.getBoundingClientRect();
      const u = (e.clientX - r.left - this.pad.l) / (r.width - this.pad.l - this.pad.r);
      this.onSeek(this.t0 + Math.min(Math.max(u, 0), 1) * (this.t1 - this.t0));
    };
    canvas.addEventListener('pointerdown', (e) => {
      dragging = true;
      seek(e);
    });
    canvas.addEventListener('pointermove', (e) => dragging && seek(e));
    window.addEventListener('pointerup', () => (dragging = false));
    this.pad = { l: 52, r: 36, t: 8, b: 18 };
  }

  /** times (s), kinetic and potential (J) and contacts (count), all per frame; missing series may be undefined. */
  setData(times, kinetic, potential, contacts) {
    const has = (a) => Array.isArray(a) && a.length === times.length && a.length > 0;
    if (!times.length || !(has(kinetic) || has(potential) || has(contacts))) {
      this.series = null;
      this.draw();
      return;
    }
    const total = has(kinetic) && has(potential) ? kinetic.map((k, i) => k + potential[i]) : undefined;
    this.series = { times, kinetic: has(kinetic) && kinetic, potential: has(potential) && potential, total, contacts: has(contacts) && contacts };
    this.t0 = times[0];
    this.t1 = Math.max(times[times.length - 1], this.t0 + 1e-9);
    // Loops rather than Math.max(...a): long recordings would overflow the
    // argument stack.
    const range = (arrays, lo, hi) => {
      for (const a of arrays) for (const v of a) (lo = Math.min(lo, v)), (hi = Math.max(hi, v));
      return [lo, hi];
    };
    const energies = [this.series.kinetic, this.series.potential, total].filter(Boolean);
    [this.eMin, this.eMax] = energies.length ? range(energies, 0, -Infinity) : [0, 1];
    if (!(this.eMax - this.eMin >= 1e-12)) this.eMax = this.eMin + 1;
    this.cMax = this.series.contacts ? Math.max(1, range([this.series.contacts], 0, 1)[1]) : 1;
    this.draw();
  }

  setCursor(t) {
    this.cursor = t;
    this.draw();
  }

  draw() {
    const c = this.canvas;
    const dpr = window.devicePixelRatio || 1;
    const w = Math.max(1, Math.round(c.clientWidth * dpr));
    const h = Math.max(1, Math.round(c.clientHeight * dpr));
    if (c.width !== w || c.height !== h) {
      c.width = w;
      c.height = h;
    }
    const g = c.getContext('2d');
    g.setTransform(dpr, 0, 0, dpr, 0, 0);
    const W = w / dpr;
    const H = h / dpr;
    g.clearRect(0, 0, W, H);
    g.font = '11px system-ui, sans-serif';
    const s = this.series;
    if (!s) {
      g.fillStyle = '#888';
      g.fillText('no energy / contact data in this recording', 10, H / 2);
      return;
    }
    const { l, r, t, b } = this.pad;
    const x = (tt) => l + ((tt - this.t0) / (this.t1 - this.t0)) * (W - l - r);
    const yE = (e) => t + (1 - (e - this.eMin) / (this.eMax - this.eMin)) * (H - t - b);
    const yC = (n) => t + (1 - n / this.cMax) * (H - t - b);

    g.strokeStyle = '#333';
    g.strokeRect(l, t, W - l - r, H - t - b);
    g.fillStyle = '#aaa';
    g.fillText(`${this.eMax.toPrecision(3)} J`, 2, t + 8);
    g.fillText(`${this.eMin.toPrecision(3)} J`, 2, H - b);
    g.fillText(`${this.t0.toFixed(2)} s`, l, H - 4);
    g.fillText(`${this.t1.toFixed(2)} s`, W - r - 40, H - 4);
    if (s.contacts) g.fillText(`${this.cMax}`, W - r + 4, t + 8);

    const line = (values, y, color, step) => {
      g.strokeStyle = color;
      g.beginPath();
      values.forEach((v, i) => {
        const px = x(s.times[i]);
        if (i === 0) g.moveTo(px, y(v));
        else {
          if (step) g.lineTo(px, y(values[i - 1]));
          g.lineTo(px, y(v));
        }
      });
      g.stroke();
    };
    if (s.contacts) line(s.contacts, yC, COLORS.contacts, true);
    if (s.kinetic) line(s.kinetic, yE, COLORS.kinetic);
    if (s.potential) line(s.potential, yE, COLORS.potential);
    if (s.total) line(s.total, yE, COLORS.total);

    let lx = l + 6;
    for (const [name, key] of [['kinetic', 'kinetic'], ['potential', 'potential'], ['total', 'total'], ['contacts', 'contacts']]) {
      if (!s[key]) continue;
      g.fillStyle = COLORS[key];
      g.fillText(name, lx, t + 11);
      lx += g.measureText(name).width + 10;
    }
    g.strokeStyle = '#fff';
    g.beginPath();
    const cx = x(Math.min(Math.max(this.cursor, this.t0), this.t1));
    g.moveTo(cx, t);
    g.lineTo(cx, H - b);
    g.stroke();
  }
}
