// What the hands do: the tools on the map (go, set pose, edit points, draw shapes), pan and
// zoom (drag, wheel, pinch), keyboard teleop (arrows, WASD) and the on-screen joystick.

const CLICK_SLOP = 5; // [px] a press that moves less is a click, not a drag
const TELEOP_PERIOD = 100; // [ms] between teleop commands while a key or the joystick is held
const LINEAR = 0.5; // [m/s] full stick or key (the robot clamps to its limits)
const ANGULAR = 1.0; // [rad/s]
const KEYS = {
  ArrowUp: [1, 0], KeyW: [1, 0], ArrowDown: [-1, 0], KeyS: [-1, 0],
  ArrowLeft: [0, 1], KeyA: [0, 1], ArrowRight: [0, -1], KeyD: [0, -1],
};
const SHAPES = new Set(["wall", "zone", "path"]);

export class Input {
  constructor(app) {
    this.app = app;
    this.view = app.view;
    this.canvas = app.view.canvas;
    this.tool = "go";
    this.pointers = new Map(); // pointerId -> {x, y}
    this.press = null; // the press being dragged: {x, y, moved, point}
    this.pinch = null;
    this.draft = null; // a shape being drawn
    this.keys = new Set();
    this.stick = null; // [linear, angular] from the joystick
    this.teleopTimer = null;
    this.bind();
  }

  setTool(tool) {
    this.tool = tool;
    this.draft = null;
    this.view.set("draft", null);
    for (const b of document.querySelectorAll("[data-tool]")) {
      b.classList.toggle("active", b.dataset.tool === tool);
    }
    const hints = {
      go: "Click a point or anywhere to go there; drag to pan, wheel to zoom.",
      pose: "Press where the robot is and drag toward where it faces.",
      select: "Click a point to select it; drag it to move it.",
      "add-point": "Click where the new point goes.",
      wall: "Click the wall's corners; double-click or Enter to finish, Esc to drop.",
      zone: "Click the zone's corners; double-click or Enter to finish, Esc to drop.",
      path: "Click the path's points; double-click or Enter to finish, Esc to drop.",
    };
    document.getElementById("hint").textContent = hints[tool] || "";
  }

  local(e) {
    const r = this.canvas.getBoundingClientRect();
    return { x: e.clientX - r.left, y: e.clientY - r.top };
  }

  bind() {
    const c = this.canvas;
    for (const b of document.querySelectorAll("[data-tool]")) {
      b.addEventListener("click", () => this.setTool(b.dataset.tool));
    }
    c.addEventListener("pointerdown", (e) => this.down(e));
    c.addEventListener("pointermove", (e) => this.move(e));
    c.addEventListener("pointerup", (e) => this.up(e));
    c.addEventListener("pointercancel", (e) => this.pointers.delete(e.pointerId));
    c.addEventListener("dblclick", (e) => { e.preventDefault(); this.finishShape(); });
    c.addEventListener("wheel", (e) => {
      e.preventDefault();
      const p = this.local(e);
      this.view.zoomAt(p.x, p.y, Math.exp(-e.deltaY * 0.0015));
    }, { passive: false });
    window.addEventListener("keydown", (e) => this.keyDown(e));
    window.addEventListener("keyup", (e) => this.keyUp(e));
    window.addEventListener("blur", () => { this.keys.clear(); this.stopTeleopIfIdle(); });
    this.bindJoystick();
  }

  down(e) {
    this.canvas.setPointerCapture(e.pointerId);
    this.canvas.focus();
    const p = this.local(e);
    this.pointers.set(e.pointerId, p);
    if (this.pointers.size === 2) { // pinch
      const [a, b] = [...this.pointers.values()];
      this.pinch = { d: Math.hypot(a.x - b.x, a.y - b.y) };
      this.press = null;
      return;
    }
    const point = this.tool === "select" && this.app.canDrive ? this.view.pointAt(p.x, p.y) : null;
    this.press = { x: p.x, y: p.y, last: p, moved: false, point };
  }

  move(e) {
    const p = this.local(e);
    if (this.pointers.has(e.pointerId)) this.pointers.set(e.pointerId, p);
    if (this.pinch && this.pointers.size === 2) {
      const [a, b] = [...this.pointers.values()];
      const d = Math.hypot(a.x - b.x, a.y - b.y);
      this.view.zoomAt((a.x + b.x) / 2, (a.y + b.y) / 2, d / Math.max(1, this.pinch.d));
      this.pinch.d = d;
      return;
    }
    if (this.draft) {
      const w = this.view.toWorld(p.x, p.y);
      this.draft.cursor = [w.x, w.y];
      this.view.set("draft", this.draft);
    }
    const press = this.press;
    if (!press) return;
    if (Math.hypot(p.x - press.x, p.y - press.y) > CLICK_SLOP) press.moved = true;
    if (!press.moved) return;
    if (this.tool === "pose" && this.app.canDrive) {
      const a = this.view.toWorld(press.x, press.y);
      const b = this.view.toWorld(p.x, p.y);
      this.view.set("draft", { kind: "pose", x: a.x, y: a.y, theta: Math.atan2(b.y - a.y, b.x - a.x) });
    } else if (press.point) {
      const w = this.view.toWorld(p.x, p.y);
      press.point = { ...press.point, x: w.x, y: w.y };
      this.view.set("points", this.app.points.map((q) =>
        (q.name === press.point.name ? press.point : q)));
    } else {
      this.view.panBy(p.x - press.last.x, p.y - press.last.y);
    }
    press.last = p;
  }

  up(e) {
    this.pointers.delete(e.pointerId);
    if (this.pinch) {
      if (this.pointers.size < 2) this.pinch = null;
      return;
    }
    const press = this.press;
    this.press = null;
    if (!press) return;
    const p = this.local(e);
    const w = this.view.toWorld(p.x, p.y);
    if (press.moved) {
      if (this.tool === "pose" && this.app.canDrive) this.setPose(press, p);
      else if (press.point) this.app.editor.movePoint(press.point.name, w.x, w.y);
      return;
    }
    this.click(p, w);
  }

  click(p, w) {
    const app = this.app;
    if (!app.canDrive) return;
    if (this.tool === "go") {
      const point = this.view.pointAt(p.x, p.y);
      app.goTo(point ? { point: point.name } : { x: w.x, y: w.y });
    } else if (this.tool === "select") {
      app.editor.select(this.view.pointAt(p.x, p.y));
    } else if (this.tool === "add-point") {
      app.editor.addPoint(w.x, w.y);
    } else if (SHAPES.has(this.tool)) {
      if (!this.draft) this.draft = { kind: this.tool, points: [] };
      const last = this.draft.points[this.draft.points.length - 1];
      if (!last || Math.hypot(last[0] - w.x, last[1] - w.y) > 1e-3) this.draft.points.push([w.x, w.y]);
      this.view.set("draft", this.draft);
    }
  }

  setPose(press, p) {
    const a = this.view.toWorld(press.x, press.y);
    const b = this.view.toWorld(p.x, p.y);
    const theta = Math.atan2(b.y - a.y, b.x - a.x);
    this.view.set("draft", null);
    this.app.act("set pose", async () => {
      await this.app.api.post("/api/navigation/initial_pose", { x: a.x, y: a.y, theta });
      this.app.toast(`pose set at ${a.x.toFixed(2)}, ${a.y.toFixed(2)}`);
    });
  }

  finishShape() {
    const d = this.draft;
    if (!d) return;
    this.draft = null;
    this.view.set("draft", null);
    const need = d.kind === "zone" ? 3 : 2;
    if (d.points.length < need) {
      this.app.toast(`a ${d.kind} needs at least ${need} points`, true);
      return;
    }
    this.app.editor.addShape(d.kind, d.points);
  }

  // -- keyboard -----------------------------------------------------------------------------

  typing(e) {
    const t = e.target;
    return t && (t.tagName === "INPUT" || t.tagName === "SELECT" || t.tagName === "TEXTAREA");
  }

  keyDown(e) {
    if (this.typing(e)) return;
    if (e.key === "Enter" && this.draft) { this.finishShape(); return; }
    if (e.key === "Escape") { this.draft = null; this.view.set("draft", null); return; }
    if ((e.ctrlKey || e.metaKey) && e.code === "KeyZ") {
      e.preventDefault();
      this.app.editor.undo();
      return;
    }
    if (!(e.code in KEYS) || e.ctrlKey || e.metaKey || e.altKey || !this.app.canDrive) return;
    e.preventDefault();
    this.keys.add(e.code);
    this.startTeleop();
  }

  keyUp(e) {
    if (!this.keys.delete(e.code)) return;
    this.stopTeleopIfIdle();
  }

  // -- teleop -------------------------------------------------------------------------------

  command() {
    if (this.stick) return this.stick;
    let linear = 0;
    let angular = 0;
    for (const code of this.keys) { linear += KEYS[code][0]; angular += KEYS[code][1]; }
    return [Math.sign(linear) * LINEAR, Math.sign(angular) * ANGULAR];
  }

  startTeleop() {
    if (this.teleopTimer) return;
    const send = () => {
      const [linear, angular] = this.command();
      this.app.api.post("/api/teleop", { linear, angular }).catch((err) => {
        this.app.toast(`teleop: ${err.message}`, true);
      });
    };
    send();
    this.teleopTimer = setInterval(send, TELEOP_PERIOD);
  }

  stopTeleopIfIdle() {
    if (this.keys.size || this.stick || !this.teleopTimer) return;
    clearInterval(this.teleopTimer);
    this.teleopTimer = null;
    this.app.api.post("/api/teleop", { linear: 0, angular: 0 }).catch(() => {});
  }

  bindJoystick() {
    const pad = document.getElementById("joystick");
    const knob = document.getElementById("knob");
    const moveKnob = (e) => {
      const r = pad.getBoundingClientRect();
      const R = r.width / 2;
      let dx = e.clientX - (r.left + R);
      let dy = e.clientY - (r.top + R);
      const d = Math.hypot(dx, dy);
      if (d > R) { dx *= R / d; dy *= R / d; }
      knob.style.transform = `translate(${dx}px, ${dy}px)`;
      this.stick = [(-dy / R) * LINEAR, (-dx / R) * ANGULAR];
    };
    pad.addEventListener("pointerdown", (e) => {
      if (!this.app.canDrive) return;
      pad.setPointerCapture(e.pointerId);
      moveKnob(e);
      this.startTeleop();
    });
    pad.addEventListener("pointermove", (e) => { if (this.stick) moveKnob(e); });
    const release = () => {
      knob.style.transform = "";
      this.stick = null;
      this.stopTeleopIfIdle();
    };
    pad.addEventListener("pointerup", release);
    pad.addEventListener("pointercancel", release);
  }
}
