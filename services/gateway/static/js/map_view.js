// The map canvas: occupancy grid, costmap overlay, virtual walls, plan, laser scan, nav
// points and the robot, in map coordinates (x right, y up), with pan and zoom.

const COLORS = {
  free: [236, 240, 244],
  occupied: [38, 46, 58],
  unknown: [150, 160, 174],
  plan: "#22c55e",
  scan: "#ef4444",
  wall: "#f43f5e",
  robot: "#3b82f6",
  robotEdge: "#1e3a8a",
  other: "#94a3b8",
  otherEdge: "#334155",
  point: "#f59e0b",
  pointActive: "#22c55e",
  track: "#a855f7",
};

export function yawOf(q) {
  return Math.atan2(2 * (q.w * q.z + q.x * q.y), 1 - 2 * (q.y * q.y + q.z * q.z));
}

function gridImage(grid, paint) {
  const { width, height } = grid.info;
  const canvas = document.createElement("canvas");
  canvas.width = Math.max(1, width);
  canvas.height = Math.max(1, height);
  const ctx = canvas.getContext("2d");
  const image = ctx.createImageData(canvas.width, canvas.height);
  const px = image.data;
  const data = grid.data;
  for (let i = 0; i < width * height; i += 1) paint(data[i], px, i * 4);
  ctx.putImageData(image, 0, 0);
  return canvas;
}

function paintMap(v, px, o) {
  const c = v < 0 ? COLORS.unknown : v >= 65 ? COLORS.occupied : COLORS.free;
  px[o] = c[0]; px[o + 1] = c[1]; px[o + 2] = c[2]; px[o + 3] = 255;
}

function paintCost(v, px, o) {
  // inflation as a soft blue halo; lethal cells are left to the map's own dark walls
  if (v <= 0 || v >= 99) { px[o + 3] = 0; return; }
  const t = Math.min(v, 98) / 98;
  px[o] = Math.round(56 + 90 * t);
  px[o + 1] = Math.round(140 - 40 * t);
  px[o + 2] = 246;
  px[o + 3] = Math.round(25 + 95 * t * t);
}

// a robot's colour on the map, the same on every page: a hue from its name
export function robotHue(name) {
  let h = 0;
  for (const ch of name) h = (h * 31 + ch.charCodeAt(0)) % 360;
  return h;
}

export class MapView extends EventTarget {
  constructor(canvas) {
    super();
    this.canvas = canvas;
    this.ctx = canvas.getContext("2d");
    this.scale = 40; // pixels per metre
    this.center = { x: 0, y: 0 };
    this.fitted = false;
    this.userMoved = false;
    this.layers = { costmap: true, scan: true, plan: true, walls: true, points: true, track: true };
    this.map = null;
    this.mapImage = null;
    this.costImage = null;
    this.costInfo = null;
    this.robot = null; // {x, y, yaw}
    this.others = []; // a fleet's other robots: {name, x, y, yaw, estop}
    this.reservations = []; // the traffic schedule: {robot, cells: [{x, y}], size, stop}
    this.footprint = 0.22;
    this.scanPoints = [];
    this.plan = [];
    this.track = []; // the mapping robot's trajectory (slam/track)
    this.walls = [];
    this.points = [];
    this.activePoint = null;
    this.dirty = true;
    this.pointers = new Map();
    this.installInput();
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
    const frame = () => {
      if (this.dirty) this.draw();
      requestAnimationFrame(frame);
    };
    requestAnimationFrame(frame);
  }

  resize() {
    const dpr = window.devicePixelRatio || 1;
    const rect = this.canvas.getBoundingClientRect();
    this.canvas.width = Math.max(1, Math.round(rect.width * dpr));
    this.canvas.height = Math.max(1, Math.round(rect.height * dpr));
    this.dpr = dpr;
    if (this.fitted && !this.userMoved) this.fit(); // follow the window until the user pans
    this.dirty = true;
  }

  // -------------------------------------------------------------- data

  setMap(grid) {
    const before = this.map ? this.map.info : null;
    this.map = grid;
    this.mapImage = gridImage(grid, paintMap);
    const grown = before && (before.width !== grid.info.width || before.height !== grid.info.height);
    if (!this.fitted || (grown && !this.userMoved)) this.fit(); // a map being built grows
    this.canvas.dataset.mapLoaded = "1";
    this.dirty = true;
  }

  setCostmap(grid) {
    this.costInfo = grid.info;
    this.costImage = gridImage(grid, paintCost);
    this.dirty = true;
  }

  setRobot(x, y, yaw) {
    this.robot = { x, y, yaw };
    this.dirty = true;
  }

  setOthers(robots) { this.others = robots; this.dirty = true; }
  setReservations(held) { this.reservations = held; this.dirty = true; }
  setScan(points) { this.scanPoints = points; this.dirty = true; }
  setPlan(points) { this.plan = points; this.dirty = true; }
  setTrack(points) { this.track = points; this.dirty = true; }
  setWalls(walls) { this.walls = walls; this.dirty = true; }
  setPoints(points) { this.points = points; this.dirty = true; }
  setActivePoint(index) { this.activePoint = index; this.dirty = true; }
  setLayer(name, on) { this.layers[name] = on; this.dirty = true; }

  // -------------------------------------------------------------- view

  fit() {
    if (!this.map) return;
    this.userMoved = false;
    const { width, height, resolution, origin } = this.map.info;
    const w = width * resolution;
    const h = height * resolution;
    const cw = this.canvas.width / this.dpr;
    const ch = this.canvas.height / this.dpr;
    this.scale = Math.max(1, Math.min(cw / w, ch / h) * 0.95);
    this.center = { x: origin.position.x + w / 2, y: origin.position.y + h / 2 };
    this.fitted = true;
    this.dirty = true;
  }

  zoom(factor, sx, sy) {
    this.userMoved = true;
    const before = this.screenToWorld(sx, sy);
    this.scale = Math.min(400, Math.max(2, this.scale * factor));
    const after = this.screenToWorld(sx, sy);
    this.center.x += before.x - after.x;
    this.center.y += before.y - after.y;
    this.dirty = true;
  }

  worldToScreen(x, y) {
    const cw = this.canvas.width / this.dpr;
    const ch = this.canvas.height / this.dpr;
    return { x: (x - this.center.x) * this.scale + cw / 2,
             y: -(y - this.center.y) * this.scale + ch / 2 };
  }

  screenToWorld(sx, sy) {
    const cw = this.canvas.width / this.dpr;
    const ch = this.canvas.height / this.dpr;
    return { x: (sx - cw / 2) / this.scale + this.center.x,
             y: -(sy - ch / 2) / this.scale + this.center.y };
  }

  pointAt(sx, sy) {
    if (!this.layers.points) return -1;
    let best = -1;
    let bestD = 16;
    this.points.forEach((p, i) => {
      const s = this.worldToScreen(p.x, p.y);
      const d = Math.hypot(s.x - sx, s.y - sy);
      if (d < bestD) { bestD = d; best = i; }
    });
    return best;
  }

  installInput() {
    const c = this.canvas;
    let moved = false;
    let last = null;
    let pinch = null;
    c.addEventListener("wheel", (e) => {
      e.preventDefault();
      const r = c.getBoundingClientRect();
      this.zoom(e.deltaY < 0 ? 1.15 : 1 / 1.15, e.clientX - r.left, e.clientY - r.top);
    }, { passive: false });
    c.addEventListener("pointerdown", (e) => {
      c.setPointerCapture(e.pointerId);
      this.pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
      moved = false;
      last = { x: e.clientX, y: e.clientY };
      if (this.pointers.size === 2) {
        const [a, b] = [...this.pointers.values()];
        pinch = Math.hypot(a.x - b.x, a.y - b.y);
      }
    });
    c.addEventListener("pointermove", (e) => {
      if (!this.pointers.has(e.pointerId)) return;
      this.pointers.set(e.pointerId, { x: e.clientX, y: e.clientY });
      if (this.pointers.size === 2 && pinch) {
        const [a, b] = [...this.pointers.values()];
        const d = Math.hypot(a.x - b.x, a.y - b.y);
        const r = c.getBoundingClientRect();
        this.zoom(d / pinch, (a.x + b.x) / 2 - r.left, (a.y + b.y) / 2 - r.top);
        pinch = d;
        moved = true;
        return;
      }
      const dx = e.clientX - last.x;
      const dy = e.clientY - last.y;
      if (Math.abs(dx) + Math.abs(dy) > 2) moved = true;
      if (moved) {
        this.userMoved = true;
        this.center.x -= dx / this.scale;
        this.center.y += dy / this.scale;
        last = { x: e.clientX, y: e.clientY };
        this.dirty = true;
      }
    });
    const end = (e) => {
      this.pointers.delete(e.pointerId);
      if (this.pointers.size < 2) pinch = null;
      if (!moved && e.type === "pointerup") {
        const r = c.getBoundingClientRect();
        const sx = e.clientX - r.left;
        const sy = e.clientY - r.top;
        const index = this.pointAt(sx, sy);
        const detail = { index, world: this.screenToWorld(sx, sy) };
        this.dispatchEvent(new CustomEvent("pick", { detail }));
      }
    };
    c.addEventListener("pointerup", end);
    c.addEventListener("pointercancel", end);
  }

  // -------------------------------------------------------------- drawing

  draw() {
    this.dirty = false;
    const ctx = this.ctx;
    const dpr = this.dpr;
    const cw = this.canvas.width / dpr;
    const ch = this.canvas.height / dpr;
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.fillStyle = "#0b1220";
    ctx.fillRect(0, 0, cw, ch);
    // world transform: metres, y up
    const s = this.scale;
    const tx = cw / 2 - this.center.x * s;
    const ty = ch / 2 + this.center.y * s;
    ctx.setTransform(dpr * s, 0, 0, -dpr * s, dpr * tx, dpr * ty);
    ctx.imageSmoothingEnabled = false;
    if (this.mapImage) this.drawGrid(this.mapImage, this.map.info, 1);
    if (this.layers.costmap && this.costImage) this.drawGrid(this.costImage, this.costInfo, 1);
    const px = 1 / s; // one screen pixel in metres
    if (this.layers.walls) {
      ctx.strokeStyle = COLORS.wall;
      ctx.lineWidth = 3 * px;
      ctx.setLineDash([8 * px, 5 * px]);
      for (const wall of this.walls) this.polyline(wall);
      ctx.setLineDash([]);
    }
    if (this.layers.plan && this.plan.length > 1) {
      ctx.strokeStyle = COLORS.plan;
      ctx.lineWidth = 3 * px;
      ctx.lineJoin = "round";
      this.polyline(this.plan);
    }
    if (this.layers.track && this.track.length > 1) {
      ctx.strokeStyle = COLORS.track;
      ctx.lineWidth = 2 * px;
      ctx.lineJoin = "round";
      this.polyline(this.track);
    }
    if (this.layers.traffic !== false) this.drawReservations(px);
    if (this.layers.scan && this.scanPoints.length) {
      ctx.fillStyle = COLORS.scan;
      const r = 2 * px;
      for (const p of this.scanPoints) ctx.fillRect(p.x - r, p.y - r, 2 * r, 2 * r);
    }
    // nav points in screen space (labels stay upright), then the robot on top of them
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    if (this.layers.points) this.drawPoints();
    ctx.setTransform(dpr * s, 0, 0, -dpr * s, dpr * tx, dpr * ty);
    for (const o of this.others) {
      this.drawRobot(px, o, o.estop ? COLORS.wall : COLORS.other, COLORS.otherEdge);
    }
    if (this.robot) this.drawRobot(px, this.robot, COLORS.robot, COLORS.robotEdge);
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    this.drawLabels();
    this.drawScaleBar(cw, ch);
  }

  // the cells each robot in schedule mode holds, in its colour; where it must stop, a bar
  drawReservations(px) {
    const ctx = this.ctx;
    for (const r of this.reservations) {
      const hue = robotHue(r.robot);
      const h = r.size / 2;
      ctx.fillStyle = `hsla(${hue}, 85%, 55%, 0.28)`;
      for (const c of r.cells) ctx.fillRect(c.x - h, c.y - h, r.size, r.size);
      if (r.stop) {
        ctx.strokeStyle = `hsl(${hue}, 85%, 60%)`;
        ctx.lineWidth = 4 * px;
        ctx.beginPath();
        ctx.arc(r.stop.x, r.stop.y, r.size * 0.6, 0, 2 * Math.PI);
        ctx.stroke();
      }
    }
  }

  drawGrid(image, info, alpha) {
    const ctx = this.ctx;
    const { width, height, resolution, origin } = info;
    ctx.globalAlpha = alpha;
    ctx.drawImage(image, origin.position.x, origin.position.y, width * resolution,
                  height * resolution);
    ctx.globalAlpha = 1;
  }

  polyline(points) {
    if (points.length < 2) return;
    const ctx = this.ctx;
    ctx.beginPath();
    ctx.moveTo(points[0].x, points[0].y);
    for (const p of points.slice(1)) ctx.lineTo(p.x, p.y);
    ctx.stroke();
  }

  drawRobot(px, robot, fill, edge) {
    const ctx = this.ctx;
    const { x, y, yaw } = robot;
    const r = Math.max(this.footprint, 10 * px); // still visible when zoomed far out
    ctx.save();
    ctx.translate(x, y);
    ctx.rotate(yaw);
    if (robot === this.robot) {
      ctx.fillStyle = "rgba(59, 130, 246, 0.22)";
      ctx.beginPath();
      ctx.arc(0, 0, r + 8 * px, 0, 2 * Math.PI);
      ctx.fill();
    }
    ctx.fillStyle = fill;
    ctx.strokeStyle = edge;
    ctx.lineWidth = 2 * px;
    ctx.beginPath();
    ctx.arc(0, 0, r, 0, 2 * Math.PI);
    ctx.fill();
    ctx.stroke();
    ctx.fillStyle = "#ffffff";
    ctx.beginPath();
    ctx.moveTo(r * 0.85, 0);
    ctx.lineTo(-r * 0.35, r * 0.5);
    ctx.lineTo(-r * 0.1, 0);
    ctx.lineTo(-r * 0.35, -r * 0.5);
    ctx.closePath();
    ctx.fill();
    ctx.restore();
  }

  // the fleet's other robots' names, upright in screen space beside each one
  drawLabels() {
    if (!this.others.length) return;
    const ctx = this.ctx;
    ctx.font = "600 11px system-ui, sans-serif";
    ctx.textBaseline = "middle";
    for (const o of this.others) {
      const at = this.worldToScreen(o.x, o.y);
      const sx = at.x + 12;
      const sy = at.y - 14;
      const w = ctx.measureText(o.name).width + 8;
      ctx.fillStyle = "rgba(11, 18, 32, 0.72)";
      ctx.fillRect(sx, sy - 8, w, 16);
      ctx.fillStyle = "#e2e8f0";
      ctx.fillText(o.name, sx + 4, sy);
    }
  }

  drawPoints() {
    const ctx = this.ctx;
    ctx.font = "600 12px system-ui, sans-serif";
    ctx.textBaseline = "middle";
    this.points.forEach((p, i) => {
      const sp = this.worldToScreen(p.x, p.y);
      const active = i === this.activePoint;
      ctx.fillStyle = active ? COLORS.pointActive : COLORS.point;
      ctx.strokeStyle = "#0b1220";
      ctx.lineWidth = 2;
      ctx.beginPath();
      ctx.arc(sp.x, sp.y, 9, 0, 2 * Math.PI);
      ctx.fill();
      ctx.stroke();
      ctx.strokeStyle = "#0b1220";
      ctx.beginPath();
      ctx.moveTo(sp.x, sp.y);
      ctx.lineTo(sp.x + 9 * Math.cos(p.theta), sp.y - 9 * Math.sin(p.theta));
      ctx.stroke();
      const label = p.name || `#${i}`;
      const w = ctx.measureText(label).width + 10;
      ctx.fillStyle = "rgba(11, 18, 32, 0.78)";
      ctx.fillRect(sp.x + 12, sp.y - 9, w, 18);
      ctx.fillStyle = "#f8fafc";
      ctx.fillText(label, sp.x + 17, sp.y);
    });
  }

  drawScaleBar(cw, ch) {
    const ctx = this.ctx;
    const steps = [0.5, 1, 2, 5, 10, 20, 50];
    const metres = steps.find((m) => m * this.scale > 60) || 50;
    const len = metres * this.scale;
    ctx.fillStyle = "rgba(11, 18, 32, 0.7)";
    ctx.fillRect(10, ch - 30, len + 20, 22);
    ctx.strokeStyle = "#e2e8f0";
    ctx.lineWidth = 2;
    ctx.beginPath();
    ctx.moveTo(20, ch - 14); ctx.lineTo(20 + len, ch - 14);
    ctx.moveTo(20, ch - 18); ctx.lineTo(20, ch - 10);
    ctx.moveTo(20 + len, ch - 18); ctx.lineTo(20 + len, ch - 10);
    ctx.stroke();
    ctx.fillStyle = "#e2e8f0";
    ctx.font = "11px system-ui, sans-serif";
    ctx.fillText(`${metres} m`, 24 + len / 2 - 10, ch - 22);
  }
}
