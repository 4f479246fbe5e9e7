// Site edits from the map: points added, moved, renamed, deleted; walls, zones and paths
// drawn. Each edit is saved through the API at once, and leaves its inverse on a stack, so
// "Undo" (or Ctrl+Z) takes back the last one, then the one before.

const UNDO_DEPTH = 20;

export class Editor {
  constructor(app) {
    this.app = app;
    this.api = app.api;
    this.selected = null;
    this.keepouts = [];
    this.paths = [];
    this.undoStack = []; // [{label, run: async () => ...}]
    this.bind();
  }

  bind() {
    const $ = (id) => document.getElementById(id);
    $("undo").addEventListener("click", () => this.undo());
    $("point-rename").addEventListener("click", () => this.renameSelected());
    $("point-delete").addEventListener("click", () => this.deleteSelected());
    $("point-go").addEventListener("click", () => {
      if (this.selected) this.app.goTo({ point: this.selected.name });
    });
  }

  siteLoaded(keepouts, paths) {
    this.keepouts = keepouts;
    this.paths = paths;
    if (this.selected) { // the same point, as stored now; what is being typed stays
      this.select(this.app.points.find((p) => p.name === this.selected.name) || null, false);
    }
  }

  select(point, fillName = true) {
    this.selected = point;
    this.app.view.set("selected", point);
    document.getElementById("point-editor").classList.toggle("hidden", !point);
    document.getElementById("point-none").classList.toggle("hidden", !!point);
    if (point && fillName) {
      document.getElementById("point-name").value = point.name;
      document.getElementById("edit-panel").open = true;
    }
  }

  get map() { return this.app.viewMap; }

  pointPath(name) {
    return `/api/points/${encodeURIComponent(name)}?map=${encodeURIComponent(this.map)}`;
  }

  // Save an edit: run it, remember its inverse, reload what the map shows.
  async edit(label, run, inverse) {
    const done = await this.app.act(label, run);
    if (done === undefined) { await this.app.loadSite(); return false; }
    this.undoStack.push({ label, run: inverse });
    if (this.undoStack.length > UNDO_DEPTH) this.undoStack.shift();
    this.refreshUndo();
    this.app.toast(label);
    await this.app.loadSite();
    return true;
  }

  async undo() {
    const last = this.undoStack.pop();
    this.refreshUndo();
    if (!last) return;
    const ok = await this.app.act(`undo ${last.label}`, async () => { await last.run(); return true; });
    if (ok) this.app.toast(`undone: ${last.label}`);
    await this.app.loadSite();
  }

  refreshUndo() {
    const button = document.getElementById("undo");
    button.disabled = this.undoStack.length === 0 || !this.app.canDrive;
    button.title = this.undoStack.length ?
      `undo: ${this.undoStack[this.undoStack.length - 1].label} (Ctrl+Z)` : "nothing to undo";
  }

  // -- points -------------------------------------------------------------------------------

  freeName() {
    const taken = new Set(this.app.points.map((p) => p.name));
    let n = this.app.points.length + 1;
    while (taken.has(`P${n}`)) n += 1;
    return `P${n}`;
  }

  async addPoint(x, y) {
    const name = (window.prompt("Name of the new point", this.freeName()) || "").trim();
    if (!name) return;
    const map = this.map;
    const ok = await this.edit(`add point ${name}`,
      () => this.api.post("/api/points", { name, map, x, y, theta: 0 }),
      () => this.api.del(`/api/points/${encodeURIComponent(name)}?map=${encodeURIComponent(map)}`));
    if (ok) this.select(this.app.points.find((p) => p.name === name) || null);
  }

  async movePoint(name, x, y) {
    const old = this.app.points.find((p) => p.name === name);
    if (!old) return;
    const path = this.pointPath(name);
    await this.edit(`move point ${name}`, () => this.api.put(path, { x, y }),
      () => this.api.put(path, { x: old.x, y: old.y }));
  }

  async renameSelected() {
    const old = this.selected;
    const name = document.getElementById("point-name").value.trim();
    if (!old || !name || name === old.name) return;
    const map = this.map;
    const ok = await this.edit(`rename ${old.name} to ${name}`,
      () => this.api.put(this.pointPath(old.name), { name }),
      () => this.api.put(`/api/points/${encodeURIComponent(name)}?map=${encodeURIComponent(map)}`,
        { name: old.name }));
    if (ok) this.select(this.app.points.find((p) => p.name === name) || null);
  }

  async deleteSelected() {
    const old = this.selected;
    if (!old) return;
    const body = { name: old.name, map: old.map, x: old.x, y: old.y, theta: old.theta, kind: old.kind };
    if (old.number !== null && old.number !== undefined) body.number = old.number;
    const ok = await this.edit(`delete point ${old.name}`, () => this.api.del(this.pointPath(old.name)),
      () => this.api.post("/api/points", body));
    if (ok) this.select(null);
  }

  // -- shapes -------------------------------------------------------------------------------

  async addShape(kind, points) {
    const map = encodeURIComponent(this.map);
    if (kind === "path") {
      const taken = new Set(this.paths.map((p) => p.name));
      let n = this.paths.length + 1;
      while (taken.has(`path${n}`)) n += 1;
      const name = (window.prompt("Name of the new path", `path${n}`) || "").trim();
      if (!name) return;
      const path = `/api/maps/${map}/paths/${encodeURIComponent(name)}`;
      const old = this.paths.find((p) => p.name === name);
      await this.edit(`draw path ${name}`, () => this.api.put(path, { points }),
        () => (old ? this.api.put(path, { points: old.points }) : this.api.del(path)));
      return;
    }
    const before = this.keepouts.map((k) => ({ ...k }));
    const shape = kind === "wall" ? { kind: "wall", points, thickness: 0.05 } : { kind: "zone", polygon: points };
    await this.edit(`draw ${kind === "wall" ? "virtual wall" : "forbidden zone"}`,
      () => this.api.post(`/api/maps/${map}/keepouts`, shape),
      () => this.api.put(`/api/maps/${map}/keepouts`, before));
  }
}
