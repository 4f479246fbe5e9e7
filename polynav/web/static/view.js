// The map view: one canvas, the floor's map drawn once per change into an offscreen canvas and
// copied each frame; over it the site (keepouts, points), the live things (plan, scan, people,
// other robots) and the robot with its footprint and heading. Frames are drawn only when
// something changed, and the robot's pose is eased between two statuses so 10 Hz looks smooth.
// World coordinates are metres (map frame); the view maps them to CSS pixels by a scale and an
// offset, changed by drag (pan), wheel and pinch (zoom).

const TAU = Math.PI * 2;
const MAX_FIT_SCALE = 40; // [px/m] the closest "fit" goes
const COLORS = {
  wall: "#d11", zone: "rgba(220, 30, 30, 0.25)", zoneEdge: "#d11", path: "#1769e0",
  scan: "#e8211c", person: "#f08a00", other: "#6c6c6c", robot: "#0a7d33",
  point: "#5a2ca0", draft: "#e0a400", goal: "#1769e0",
};

export class MapView {
  constructor(canvas) {
    this.canvas = canvas;
    this.ctx = canvas.getContext("2d");
    this.mapCanvas = document.createElement("canvas"); // the map, drawn once per change
    this.info = null; // {resolution, width, height, origin}
    this.scale = 20; // CSS px per metre
    this.offset = { x: 0, y: 0 }; // CSS px of world (0, 0)
    this.fitted = false;
    this.labels = []; // this frame's names, drawn last so that none hides another
    this.layers = {
      points: [], keepouts: [], path: [], scan: [], people: [], others: [], goal: null, lifts: [], doors: [], carts: [],
      draft: null, selected: null, footprint: { radius: 0.25 },
    };
    this.robot = null; // {x, y, theta} shown, eased toward `target`
    this.from = null;
    this.target = null;
    this.targetAt = 0;
    this.showRobot = true;
    this.ease = 100; // [ms] the robot glides to each new pose over one status period
    this.dirty = true;
    new ResizeObserver(() => this.resize()).observe(canvas);
    this.resize();
    const frame = (now) => { this.frame(now); requestAnimationFrame(frame); };
    requestAnimationFrame(frame);
  }

  resize() {
    const ratio = window.devicePixelRatio || 1;
    const { width, height } = this.canvas.getBoundingClientRect();
    this.canvas.width = Math.max(1, Math.round(width * ratio));
    this.canvas.height = Math.max(1, Math.round(height * ratio));
    if (!this.fitted) this.fit();
    this.dirty = true;
  }

  // -- the map ------------------------------------------------------------------------------

  // Draw a ROS map picture (row 0 at the top) into the offscreen canvas: grey unknown, white
  // free, black walls, as the PNG has them.
  // A map that grows (mapping) is fitted again only when it no longer fits in view.
  setMapImage(image, info, growing = false) {
    const sameFrame = this.info && this.info.resolution === info.resolution &&
      this.info.origin.x === info.origin.x && this.info.origin.y === info.origin.y &&
      this.info.width === info.width && this.info.height === info.height;
    const fits = growing && this.info && this.inView(info);
    this.info = info;
    this.mapCanvas.width = image.width;
    this.mapCanvas.height = image.height;
    const ctx = this.mapCanvas.getContext("2d");
    ctx.clearRect(0, 0, image.width, image.height);
    ctx.drawImage(image, 0, 0);
    if ((!sameFrame && !fits) || !this.fitted) this.fit();
    this.dirty = true;
  }

  // Whether the whole of a map's extent is on the canvas now.
  inView(info) {
    const { width, height } = this.canvas.getBoundingClientRect();
    const a = this.toScreen(info.origin.x, info.origin.y);
    const b = this.toScreen(info.origin.x + info.width * info.resolution,
      info.origin.y + info.height * info.resolution);
    return a.x >= 0 && b.y >= 0 && b.x <= width && a.y <= height;
  }

  clearMap() {
    this.info = null;
    this.mapCanvas.width = 1;
    this.mapCanvas.height = 1;
    this.dirty = true;
  }

  // Scale and centre so the whole map is in view.
  fit() {
    const { width, height } = this.canvas.getBoundingClientRect();
    if (!this.info || width < 2 || height < 2) return;
    const w = this.info.width * this.info.resolution;
    const h = this.info.height * this.info.resolution;
    // A small map (mapping's first metres) is not blown up beyond a room's scale.
    this.scale = Math.min(MAX_FIT_SCALE, Math.min(width / w, height / h) * 0.95);
    const cx = this.info.origin.x + w / 2;
    const cy = this.info.origin.y + h / 2;
    this.offset = { x: width / 2 - cx * this.scale, y: height / 2 + cy * this.scale };
    this.fitted = true;
    this.dirty = true;
  }

  // -- coordinates --------------------------------------------------------------------------

  toScreen(x, y) {
    return { x: this.offset.x + x * this.scale, y: this.offset.y - y * this.scale };
  }

  toWorld(sx, sy) {
    return { x: (sx - this.offset.x) / this.scale, y: (this.offset.y - sy) / this.scale };
  }

  // Zoom by `factor` keeping the world point under (sx, sy) where it is.
  zoomAt(sx, sy, factor) {
    const before = this.toWorld(sx, sy);
    this.scale = Math.min(400, Math.max(0.5, this.scale * factor));
    this.offset.x = sx - before.x * this.scale;
    this.offset.y = sy + before.y * this.scale;
    this.dirty = true;
  }

  panBy(dx, dy) {
    this.offset.x += dx;
    this.offset.y += dy;
    this.dirty = true;
  }

  // The named point within `radius` CSS px of (sx, sy), nearest first.
  pointAt(sx, sy, radius = 12) {
    let best = null;
    let bestD = radius;
    for (const p of this.layers.points) {
      const s = this.toScreen(p.x, p.y);
      const d = Math.hypot(s.x - sx, s.y - sy);
      if (d <= bestD) { best = p; bestD = d; }
    }
    return best;
  }

  // -- live state ---------------------------------------------------------------------------

  setRobotPose(pose, now = performance.now()) {
    if (!pose) { this.robot = null; this.target = null; this.dirty = true; return; }
    this.from = this.robot ? { ...this.robot } : { ...pose };
    this.target = { ...pose };
    this.targetAt = now;
    if (!this.robot) this.robot = { ...pose };
    this.dirty = true;
  }

  set(layer, value) {
    this.layers[layer] = value;
    this.dirty = true;
  }

  // -- drawing ------------------------------------------------------------------------------

  frame(now) {
    if (this.target && this.from) {
      const t = Math.min(1, (now - this.targetAt) / this.ease);
      let dth = this.target.theta - this.from.theta;
      dth = Math.atan2(Math.sin(dth), Math.cos(dth));
      this.robot = {
        x: this.from.x + (this.target.x - this.from.x) * t,
        y: this.from.y + (this.target.y - this.from.y) * t,
        theta: this.from.theta + dth * t,
      };
      if (t < 1) this.dirty = true;
    }
    if (!this.dirty) return;
    this.dirty = false;
    this.draw();
  }

  draw() {
    const ctx = this.ctx;
    const ratio = this.canvas.width / Math.max(1, this.canvas.getBoundingClientRect().width);
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.fillStyle = "#d9dde3";
    ctx.fillRect(0, 0, this.canvas.width, this.canvas.height);
    ctx.setTransform(ratio, 0, 0, ratio, 0, 0);
    if (this.info) {
      const info = this.info;
      const topLeft = this.toScreen(info.origin.x, info.origin.y + info.height * info.resolution);
      ctx.imageSmoothingEnabled = this.scale * info.resolution < 1;
      ctx.drawImage(this.mapCanvas, topLeft.x, topLeft.y,
        info.width * info.resolution * this.scale, info.height * info.resolution * this.scale);
    }
    const L = this.layers;
    for (const k of L.keepouts) this.drawKeepout(k);
    for (const d of L.doors) this.drawDoor(d);
    for (const c of L.carts) this.drawCart(c);
    this.drawPolyline(L.path, COLORS.path, 2.5);
    ctx.fillStyle = COLORS.scan;
    for (const [x, y] of L.scan) {
      const s = this.toScreen(x, y);
      ctx.fillRect(s.x - 1.25, s.y - 1.25, 2.5, 2.5);
    }
    for (const p of L.people) this.drawDisc(p.x, p.y, 0.25, COLORS.person, p.theta);
    for (const o of L.others) this.drawOther(o);
    for (const p of L.points) this.drawPoint(p, L.selected && L.selected.name === p.name);
    if (L.goal) this.drawGoal(L.goal);
    if (this.robot && this.showRobot) this.drawRobot(this.robot);
    if (L.draft) this.drawDraft(L.draft);
    this.drawLabels();
  }

  drawPolyline(points, color, width, close = false) {
    if (!points || points.length === 0) return;
    const ctx = this.ctx;
    ctx.beginPath();
    points.forEach(([x, y], i) => {
      const s = this.toScreen(x, y);
      if (i === 0) ctx.moveTo(s.x, s.y); else ctx.lineTo(s.x, s.y);
    });
    if (close) ctx.closePath();
    ctx.strokeStyle = color;
    ctx.lineWidth = width;
    ctx.lineJoin = "round";
    ctx.stroke();
  }

  drawKeepout(k) {
    const ctx = this.ctx;
    if (k.kind === "wall") {
      this.drawPolyline(k.points, COLORS.wall, Math.max(3, k.thickness * this.scale));
      return;
    }
    if (k.kind === "path") {
      this.drawPolyline(k.points, "#12a37a", 2.5);
      const [x, y] = k.points[0];
      this.label(x, y, k.name, "#12a37a", 8, 0);
      return;
    }
    if (k.kind === "circle") {
      const s = this.toScreen(k.x, k.y);
      ctx.beginPath();
      ctx.arc(s.x, s.y, k.radius * this.scale, 0, TAU);
      ctx.fillStyle = COLORS.zone;
      ctx.fill();
      ctx.strokeStyle = COLORS.zoneEdge;
      ctx.lineWidth = 1.5;
      ctx.stroke();
      return;
    }
    ctx.beginPath();
    k.polygon.forEach(([x, y], i) => {
      const s = this.toScreen(x, y);
      if (i === 0) ctx.moveTo(s.x, s.y); else ctx.lineTo(s.x, s.y);
    });
    ctx.closePath();
    ctx.fillStyle = COLORS.zone;
    ctx.fill();
    this.drawPolyline(k.polygon, COLORS.zoneEdge, 1.5, true);
    if (k.kind === "guided") this.drawPolyline(k.route, "#fff", 2);
  }

  drawDisc(x, y, radius, color, theta) {
    const ctx = this.ctx;
    const s = this.toScreen(x, y);
    const r = Math.max(4, radius * this.scale);
    ctx.beginPath();
    ctx.arc(s.x, s.y, r, 0, TAU);
    ctx.fillStyle = color;
    ctx.globalAlpha = 0.75;
    ctx.fill();
    ctx.globalAlpha = 1;
    if (theta !== undefined && theta !== null) {
      ctx.beginPath();
      ctx.moveTo(s.x, s.y);
      ctx.lineTo(s.x + Math.cos(theta) * r * 1.6, s.y - Math.sin(theta) * r * 1.6);
      ctx.strokeStyle = color;
      ctx.lineWidth = 2;
      ctx.stroke();
    }
  }

  drawDoor(d) { // a door or gate: its leaf, red while closed, amber moving, green open
    const ctx = this.ctx;
    const [x1, y1, x2, y2] = d.segment;
    const a = this.toScreen(x1, y1);
    const b = this.toScreen(x2, y2);
    ctx.beginPath();
    ctx.moveTo(a.x, a.y);
    ctx.lineTo(b.x, b.y);
    ctx.setLineDash(d.state === "open" ? [4, 4] : []);
    ctx.strokeStyle = d.state === "closed" ? "#c22" : d.state === "open" ? "#2a2" : "#d80";
    ctx.lineWidth = 4;
    ctx.stroke();
    ctx.setLineDash([]);
    this.label((x1 + x2) / 2, (y1 + y2) / 2, `${d.name} ${d.state}`, ctx.strokeStyle, 10);
  }

  drawCart(c) { // a cart or cabin: its four legs and the frame between them, named
    const ctx = this.ctx;
    const cos = Math.cos(c.theta), sin = Math.sin(c.theta);
    const corner = (u, v) => this.toScreen(c.x + u * cos - v * sin, c.y + u * sin + v * cos);
    const hl = c.length / 2, hw = c.width / 2;
    const legs = [corner(hl, hw), corner(-hl, hw), corner(-hl, -hw), corner(hl, -hw)];
    const color = c.carried ? COLORS.robot : "#7a4a1c";
    const below = -(this.scale * Math.max(c.length, c.width) / 2 + 12); // clear of the legs
    this.label(c.x, c.y, `${c.name}${c.kind === "cabin" ? " (cabin)" : ""}`, color, below);
    ctx.beginPath();
    legs.forEach((s, i) => (i === 0 ? ctx.moveTo(s.x, s.y) : ctx.lineTo(s.x, s.y)));
    ctx.closePath();
    ctx.setLineDash([3, 3]);
    ctx.strokeStyle = color;
    ctx.lineWidth = 1.5;
    ctx.stroke();
    ctx.setLineDash([]);
    ctx.fillStyle = color;
    const leg = Math.max(2, 0.05 * this.scale);
    for (const s of legs) ctx.fillRect(s.x - leg, s.y - leg, 2 * leg, 2 * leg);
  }

  drawCar(p) { // a lift car's floor, 1.4 m square about its inside point
    const ctx = this.ctx;
    const s = this.toScreen(p.x, p.y);
    const half = 0.7 * this.scale;
    ctx.strokeStyle = "#a50";
    ctx.lineWidth = 2;
    ctx.strokeRect(s.x - half, s.y - half, 2 * half, 2 * half);
  }

  drawOther(o) {
    this.drawDisc(o.x, o.y, 0.3, COLORS.other, o.theta);
    this.label(o.x, o.y, o.name, COLORS.other, 14, 2);
  }

  drawPoint(p, selected) {
    const ctx = this.ctx;
    const s = this.toScreen(p.x, p.y);
    ctx.beginPath();
    ctx.arc(s.x, s.y, selected ? 7 : 5, 0, TAU);
    ctx.fillStyle = p.kind === "charger" ? "#0a9" : p.kind.startsWith("lift") ? "#a50" : COLORS.point;
    ctx.fill();
    ctx.lineWidth = selected ? 3 : 1.5;
    ctx.strokeStyle = selected ? COLORS.draft : "#fff";
    ctx.stroke();
    ctx.beginPath();
    ctx.moveTo(s.x, s.y);
    ctx.lineTo(s.x + Math.cos(p.theta) * 11, s.y - Math.sin(p.theta) * 11);
    ctx.strokeStyle = ctx.fillStyle;
    ctx.lineWidth = 1.5;
    ctx.stroke();
    this.label(p.x, p.y, p.name, "#222", 9, selected ? 3 : 2);
    if (p.kind === "lift-inside") { // the car there: where it is, its doors, its motion
      const car = this.layers.lifts.find((l) => p.name.startsWith(l.name));
      if (car) {
        this.drawCar(p);
        const motion = car.motion === "up" ? " ▲" : car.motion === "down" ? " ▼" : "";
        this.label(p.x, p.y, `${car.current_floor}${motion} ${car.door}` +
          `${car.mode !== "normal" ? " ✕" : ""}`, "#a50", -22);
      }
    }
  }

  label(x, y, text, color, dy, rank = 1) { // drawn at the end of the frame (drawLabels)
    const s = this.toScreen(x, y);
    this.labels.push({ x: s.x, y: s.y - dy, text, color, rank });
  }

  drawLabels() { // higher ranks first; a label that would overlap one drawn is left out
    const ctx = this.ctx;
    ctx.font = "12px system-ui, sans-serif";
    ctx.textAlign = "center";
    ctx.lineWidth = 3;
    const boxes = [];
    for (const l of this.labels.sort((a, b) => b.rank - a.rank)) {
      const half = ctx.measureText(l.text).width / 2 + 2;
      const box = { left: l.x - half, right: l.x + half, top: l.y - 11, bottom: l.y + 3 };
      if (boxes.some((b) => b.left < box.right && box.left < b.right && b.top < box.bottom &&
        box.top < b.bottom)) continue;
      boxes.push(box);
      ctx.strokeStyle = "rgba(255,255,255,0.85)";
      ctx.strokeText(l.text, l.x, l.y);
      ctx.fillStyle = l.color;
      ctx.fillText(l.text, l.x, l.y);
    }
    this.labels = [];
  }

  drawGoal(goal) {
    const ctx = this.ctx;
    const s = this.toScreen(goal.x, goal.y);
    ctx.beginPath();
    ctx.arc(s.x, s.y, 9, 0, TAU);
    ctx.strokeStyle = COLORS.goal;
    ctx.lineWidth = 2;
    ctx.setLineDash([4, 3]);
    ctx.stroke();
    ctx.setLineDash([]);
  }

  drawRobot(pose) {
    const ctx = this.ctx;
    const fp = this.layers.footprint;
    const s = this.toScreen(pose.x, pose.y);
    ctx.save();
    ctx.translate(s.x, s.y);
    ctx.rotate(-pose.theta);
    ctx.beginPath();
    if (fp.polygon && fp.polygon.length >= 3) {
      fp.polygon.forEach(([x, y], i) => {
        if (i === 0) ctx.moveTo(x * this.scale, -y * this.scale);
        else ctx.lineTo(x * this.scale, -y * this.scale);
      });
      ctx.closePath();
    } else {
      ctx.arc(0, 0, Math.max(5, (fp.radius || 0.25) * this.scale), 0, TAU);
    }
    ctx.fillStyle = "rgba(10, 125, 51, 0.35)";
    ctx.fill();
    ctx.strokeStyle = COLORS.robot;
    ctx.lineWidth = 2;
    ctx.stroke();
    const r = Math.max(8, (fp.radius || 0.25) * this.scale);
    ctx.beginPath(); // heading
    ctx.moveTo(0, 0);
    ctx.lineTo(r * 1.4, 0);
    ctx.moveTo(r * 1.4, 0);
    ctx.lineTo(r * 1.0, -r * 0.3);
    ctx.moveTo(r * 1.4, 0);
    ctx.lineTo(r * 1.0, r * 0.3);
    ctx.strokeStyle = COLORS.robot;
    ctx.lineWidth = 2.5;
    ctx.stroke();
    ctx.restore();
  }

  // A shape being drawn: {kind: "wall"|"zone"|"path", points: [[x, y]...], cursor: [x, y]},
  // or a pose being set: {kind: "pose", x, y, theta}.
  drawDraft(d) {
    if (d.kind === "pose") {
      this.drawDisc(d.x, d.y, 0.3, COLORS.draft, d.theta);
      return;
    }
    const pts = d.cursor ? [...d.points, d.cursor] : d.points;
    this.drawPolyline(pts, COLORS.draft, 3, d.kind === "zone" && pts.length > 2);
    for (const [x, y] of d.points) {
      const s = this.toScreen(x, y);
      this.ctx.fillStyle = COLORS.draft;
      this.ctx.fillRect(s.x - 3, s.y - 3, 6, 6);
    }
  }
}

// Decode a ROS map PNG (a URL or base64) into an Image.
export function loadImage(src) {
  return new Promise((resolve, reject) => {
    const image = new Image();
    image.onload = () => resolve(image);
    image.onerror = () => reject(new Error(`cannot load the map picture ${src.slice(0, 60)}`));
    image.src = src;
  });
}
