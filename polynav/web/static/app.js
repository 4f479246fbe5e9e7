// The polynav web console: start-up, login, the status stream and the panels. The map view
// (view.js), the tools on it and teleop (input.js), the site edits (edit.js) and the tasks
// (tasks.js) are wired from here. Everything goes through the native API (api.js).

import { Api, Stream } from "./api.js";
import { Editor } from "./edit.js";
import { Input } from "./input.js";
import { TaskPanel } from "./tasks.js";
import { loadImage, MapView } from "./view.js";

const $ = (id) => document.getElementById(id);
const STATUS_HZ = 10; // status messages per wall second wanted
const PACE_WINDOW = 2000; // [ms] over which the robot's speed (simulated s per wall s) is measured
const SCENE_PERIOD = 250; // [ms] between reads of the scan, the plan and the people
const FLEET_PERIOD = 2000; // [ms] between reads of the fleet and the lifts
const LOG_LINES = 200;

export class Console {
  constructor() {
    this.api = new Api();
    this.view = new MapView($("map"));
    this.status = null;
    this.maps = [];
    this.viewMap = null; // the map shown (a floor's); follows the robot's unless chosen
    this.shownImage = null; // which picture the view holds: "map:NAME" or "mapping"
    this.points = [];
    this.role = "operator";
    this.stream = null;
    this.editor = new Editor(this);
    this.input = new Input(this);
    this.tasks = new TaskPanel(this);
    this.api.onUnauthorized = () => this.showLogin();
  }

  // -- start-up and login -------------------------------------------------------------------

  async start() {
    this.bindControls();
    this.input.setTool("go");
    try {
      await this.api.get("/api/status");
    } catch (err) {
      if (err.status === 401) return; // the login form is up
      this.toast(err.message, true);
    }
    await this.afterLogin();
  }

  showLogin() {
    $("login").classList.remove("hidden");
    $("login-name").focus();
  }

  async login(event) {
    event.preventDefault();
    $("login-error").textContent = "";
    try {
      await this.api.post("/api/login", {
        name: $("login-name").value, password: $("login-password").value,
      });
    } catch (err) {
      $("login-error").textContent = err.message;
      return;
    }
    $("login-password").value = "";
    $("login").classList.add("hidden");
    await this.afterLogin();
  }

  async logout() {
    try { await this.api.postEmpty("/api/logout"); } catch (err) { /* gone already */ }
    location.reload();
  }

  async afterLogin() {
    try {
      const me = await this.api.get("/api/me");
      this.setRole(me.role, me.name);
      $("logout").classList.remove("hidden");
    } catch (err) {
      if (err.status === 401) return;
      this.setRole("operator", null); // on loopback there is no login: full control
    }
    try {
      const robot = await this.api.get("/api/robot");
      this.view.set("footprint", robot.footprint);
    } catch (err) { this.toast(err.message, true); }
    await this.loadMaps();
    if (!this.stream) {
      this.stream = new Stream(STATUS_HZ, (m) => this.onMessage(m),
        (s) => { $("connection").textContent = s; });
      this.stream.open();
    }
    this.pollScene();
    this.pollFleet();
    this.tasks.refresh();
  }

  setRole(role, name) {
    this.role = role;
    document.body.classList.toggle("viewer", role === "viewer");
    for (const el of document.querySelectorAll(".operator")) el.disabled = role === "viewer";
    $("user").textContent = name ? `${name} (${role})` : "";
    if (role === "viewer") this.input.setTool("go");
  }

  get canDrive() { return this.role !== "viewer"; }

  // -- the site -----------------------------------------------------------------------------

  async loadMaps() {
    this.maps = await this.api.get("/api/maps");
    const select = $("floor-select");
    const chosen = select.value;
    select.innerHTML = "";
    for (const m of this.maps) {
      const option = document.createElement("option");
      option.value = m.name;
      option.textContent = m.floor && m.floor !== m.name ? `${m.floor} (${m.name})` : m.name;
      select.appendChild(option);
    }
    if (chosen) select.value = chosen;
    if (!this.viewMap && this.maps.length) await this.showMap(this.maps[0].name);
  }

  // Show map `name`: its picture (drawn once), its points, keepouts and paths.
  async showMap(name) {
    this.viewMap = name;
    $("floor-select").value = name;
    const info = this.maps.find((m) => m.name === name);
    if (!info) return;
    try {
      const image = await loadImage(`/api/maps/${encodeURIComponent(name)}/image.png?` +
        `w=${info.width}&h=${info.height}&r=${Date.now()}`);
      if (this.viewMap !== name) return;
      this.view.setMapImage(image, info);
      this.shownImage = `map:${name}`;
    } catch (err) { this.toast(err.message, true); }
    await this.loadSite();
  }

  async loadSite() {
    const name = this.viewMap;
    if (!name) return;
    const q = encodeURIComponent(name);
    const seq = (this.siteSeq = (this.siteSeq || 0) + 1); // only the newest read is shown
    try {
      const [points, keepouts, paths] = await Promise.all([
        this.api.get(`/api/points?map=${q}`), this.api.get(`/api/maps/${q}/keepouts`),
        this.api.get(`/api/maps/${q}/paths`)]);
      if (this.viewMap !== name || seq !== this.siteSeq) return;
      this.points = points;
      this.view.set("points", points);
      this.view.set("keepouts", [...keepouts, ...paths.map((p) => ({ kind: "path", ...p }))]);
      this.editor.siteLoaded(keepouts, paths);
      this.tasks.listPoints(points);
    } catch (err) { this.toast(err.message, true); }
  }

  // -- live state ---------------------------------------------------------------------------

  onMessage(message) {
    if (message.type === "status") this.onStatus(message.data);
    else if (message.type === "event") this.logEvent(message.data);
    else if (message.type === "map") this.onLiveMap(message.data);
  }

  // The stream's rate is per simulated second: on a simulator running faster (or slower) than
  // real time, ask for the rate that makes about 10 statuses per wall second.
  pace(s) {
    const now = performance.now();
    if (this.lastStatusAt) this.view.ease = Math.min(300, Math.max(40, now - this.lastStatusAt));
    this.lastStatusAt = now;
    if (!this.paceFrom || s.stamp < this.paceFrom.stamp) { this.paceFrom = { stamp: s.stamp, now }; return; }
    if (now - this.paceFrom.now < PACE_WINDOW) return;
    const speed = (s.stamp - this.paceFrom.stamp) / ((now - this.paceFrom.now) / 1000);
    this.paceFrom = { stamp: s.stamp, now };
    if (speed < 0.05) return; // a paused clock: nothing to learn
    const want = Math.round(Math.min(50, Math.max(0.2, STATUS_HZ / speed)) * 100) / 100;
    if (Math.abs(want - this.stream.rate) / this.stream.rate > 0.25) this.stream.setRate(want);
  }

  onStatus(s) {
    const before = this.status;
    this.status = s;
    this.pace(s);
    this.renderStatus(s);
    // The view follows the robot to its floor, unless mapping (the live map is shown then).
    if (s.mode !== "mapping" && s.map && s.map !== "odom" && (!before || before.map !== s.map ||
        this.shownImage === "mapping")) {
      if (!this.maps.some((m) => m.name === s.map)) this.loadMaps().then(() => this.showMap(s.map));
      else this.showMap(s.map);
    }
    // Free, the robot has no map: its pose is odometry's, drawn on the map shown.
    const here = s.mode === "mapping" || s.map === this.viewMap || !s.map;
    this.view.showRobot = here;
    this.view.setRobotPose(s.pose);
    const goal = s.navigation.goal;
    this.view.set("goal", goal && s.navigation.state === "running" && here ? goal : null);
  }

  async onLiveMap(data) {
    try {
      const image = await loadImage(`data:image/png;base64,${data.png}`);
      if (!this.status || this.status.mode !== "mapping") return; // ended meanwhile
      const growing = this.shownImage === "mapping";
      this.view.setMapImage(image, data, growing);
      if (!growing) { // a new frame: the saved map's points and shapes do not belong on it
        this.view.set("points", []);
        this.view.set("keepouts", []);
      }
      this.shownImage = "mapping";
    } catch (err) { this.toast(err.message, true); }
  }

  renderStatus(s) {
    const f = (v, n = 2) => (v === null || v === undefined ? "–" : Number(v).toFixed(n));
    $("st-mode").textContent = s.mode;
    $("st-map").textContent = s.map ? `${s.map}${s.floor ? " / " + s.floor : ""}` : "–";
    $("st-pose").textContent = `${f(s.pose.x)}, ${f(s.pose.y)}, ${f(s.pose.theta)} rad`;
    $("st-battery").textContent = `${f(s.battery.percent, 0)} %${s.battery.charging ? " charging" : ""}`;
    const loc = s.localization;
    $("st-loc").textContent = `${loc.state}${loc.quality !== null ? " · quality " + f(loc.quality) : ""}`;
    const nav = s.navigation;
    const target = nav.goal ? (nav.goal.point || `${f(nav.goal.x, 1)}, ${f(nav.goal.y, 1)}`) : "";
    const nav_el = $("st-nav");
    nav_el.textContent = `${nav.state}${target ? " → " + target : ""}` +
      (nav.distance_remaining !== null ? ` (${f(nav.distance_remaining, 1)} m)` : "") +
      (nav.reason ? ` · ${nav.reason}` : "");
    nav_el.dataset.state = nav.state;
    const route = nav.route;
    $("st-route").textContent = route ? route.legs.map((leg, i) =>
      `${i === route.current_leg ? "▶" : ""}${leg.kind}${leg.map ? " " + leg.map : ""}` +
      `${leg.car ? " " + leg.car : ""}${leg.to_floor ? "→" + leg.to_floor : ""}`).join(" · ") : "–";
    $("st-lift").textContent = route && route.lift ?
      `${route.lift.car}: ${route.lift.phase} (${route.lift.from_floor}→${route.lift.to_floor})` : "–";
    // The door the robot waits at, else those it holds open to pass (the status' doors).
    const d = s.doors;
    const doorText = (door) => `${door.name} ${door.state || "?"}`;
    $("st-door").textContent = !d ? "–" : d.waiting_for ? `waits for ${doorText(d.waiting_for)}` :
      d.passing.length ? `passing ${d.passing.map(doorText).join(", ")}` : "–";
    $("st-load").textContent = s.load ? `${s.load.name} (${s.load.kind}, ${f(s.load.mass, 0)} kg)` : "–";
    const stop = s.estop.hardware || s.estop.software;
    $("st-estop").textContent = stop ? `pressed (${s.estop.hardware ? "hardware" : "software"})` : "released";
    $("estop").classList.toggle("pressed", s.estop.software);
    $("estop").textContent = s.estop.software ? "RELEASE" : "E-STOP";
    const m = s.mapping;
    $("st-mapping").textContent = m ? `${m.kind}${m.map ? " " + m.map : ""} · ${m.exploration}` +
      `${m.frontiers_left !== null ? " · " + m.frontiers_left + " frontiers" : ""} · ` +
      `${f(m.mapped_area_m2, 0)} m²${m.job ? " · save " + m.job.state : ""}` : "–";
  }

  logEvent(e) {
    const li = document.createElement("li");
    const rest = Object.entries(e).filter(([k]) => k !== "kind" && k !== "stamp")
      .map(([k, v]) => `${k}=${typeof v === "object" ? JSON.stringify(v) : v}`).join(" ");
    li.textContent = `${Number(e.stamp).toFixed(1)} s  ${e.kind}  ${rest}`.slice(0, 300);
    li.dataset.kind = e.kind;
    const log = $("event-log");
    log.prepend(li);
    while (log.children.length > LOG_LINES) log.lastChild.remove();
    if (e.kind === "map_saved" || e.kind === "mapping_stopped") this.loadMaps();
    if (e.kind.startsWith("task_")) this.tasks.refresh();
  }

  async pollScene() {
    try {
      const scene = await this.api.get("/api/scene");
      const here = scene.map === this.viewMap || this.shownImage === "mapping";
      this.view.set("scan", here ? scene.scan : []);
      this.view.set("path", here ? scene.path : []);
      this.view.set("people", here ? scene.people : []);
    } catch (err) { /* shown by the status stream's state */ }
    setTimeout(() => this.pollScene(), SCENE_PERIOD);
  }

  async pollFleet() {
    try {
      const [fleet, lifts, doors, carts] = await Promise.all([this.api.get("/api/fleet"),
        this.api.get("/api/lifts"), this.api.get("/api/doors").catch(() => ({ doors: [] })),
        this.api.get("/api/carts").catch(() => ({ carts: [] }))]);
      this.renderFleet(fleet.robots);
      this.view.set("lifts", lifts.lifts);
      const shown = this.maps.find((m) => m.name === this.viewMap);
      this.view.set("doors", doors.doors.filter((d) => shown && (d.floor === shown.floor ||
        d.floor === shown.name)));
      this.view.set("carts", carts.carts.filter((c) => shown && (c.floor === shown.floor ||
        c.floor === shown.name)));
      $("lift-list").innerHTML = "";
      for (const l of lifts.lifts) {
        const li = document.createElement("li");
        li.textContent = `${l.name}: ${l.current_floor}${l.motion !== "stopped" ? " " + l.motion +
          " → " + l.destination_floor : ""}, door ${l.door}${l.mode !== "normal" ? ", " + l.mode : ""}` +
          `${l.session ? ", held by " + l.session : ""}`;
        $("lift-list").appendChild(li);
      }
    } catch (err) { /* next time */ }
    setTimeout(() => this.pollFleet(), FLEET_PERIOD);
  }

  renderFleet(robots) {
    const port = Number(location.port || (location.protocol === "https:" ? 443 : 80));
    const me = robots.find((r) => r.ports.native === port) || robots[0];
    const select = $("robot-select");
    const ids = robots.map((r) => r.robot_id).join();
    if (select.dataset.ids !== ids) {
      select.dataset.ids = ids;
      select.innerHTML = "";
      for (const r of robots) {
        const option = document.createElement("option");
        option.value = r.ports.native || "";
        option.textContent = r.robot_id;
        option.selected = r === me;
        select.appendChild(option);
      }
    }
    select.parentElement.classList.toggle("hidden", robots.length < 2);
    $("fleet-list").innerHTML = "";
    for (const r of robots) {
      const li = document.createElement("li");
      li.textContent = `${r.robot_id}: ${r.mode}, ${r.navigation_state}, ${r.floor || "–"}` +
        `${r.waiting_for ? ", waits for " + r.waiting_for : ""}, ${r.battery_percent.toFixed(0)} %`;
      $("fleet-list").appendChild(li);
    }
    this.view.set("others", robots.filter((r) => r !== me && r.pose && r.map === this.viewMap)
      .map((r) => ({ name: r.robot_id, ...r.pose })));
  }

  // -- commands -----------------------------------------------------------------------------

  // Run an API call for a button: errors are shown, never thrown.
  async act(what, fn) {
    try {
      const answer = await fn();
      return answer;
    } catch (err) {
      this.toast(`${what}: ${err.message}`, true);
      return undefined;
    }
  }

  goTo(target) {
    const body = { ...target };
    if (this.viewMap && (!this.status || this.status.map !== this.viewMap)) body.map = this.viewMap;
    return this.act("go", async () => {
      if (this.status && this.status.mode === "free" && this.viewMap) {
        // Navigation starts on the robot's own floor (a goal on another floor takes a lift).
        const own = this.maps.find((m) => this.status.floor && m.floor === this.status.floor);
        await this.api.post("/api/navigation/start", { map: own ? own.name : this.viewMap });
      }
      const answer = await this.api.post("/api/navigation/goal", body);
      this.toast(`going to ${target.point || target.x.toFixed(2) + ", " + target.y.toFixed(2)}`);
      return answer;
    });
  }

  bindControls() {
    $("login-form").addEventListener("submit", (e) => this.login(e));
    $("logout").addEventListener("click", () => this.logout());
    $("floor-select").addEventListener("change", (e) => this.showMap(e.target.value));
    $("robot-select").addEventListener("change", (e) => {
      if (e.target.value) location.port = e.target.value; // that robot's own console
    });
    $("fit").addEventListener("click", () => this.view.fit());
    $("estop").addEventListener("click", () => this.act("e-stop", () =>
      this.api.post("/api/estop", { on: !(this.status && this.status.estop.software) })));
    const post = (id, path, what, body) => $(id).addEventListener("click", () =>
      this.act(what, () => this.api.post(path, body)));
    $("nav-start").addEventListener("click", () => this.act("navigate", () =>
      this.api.post("/api/navigation/start", { map: this.viewMap })));
    post("nav-stop", "/api/navigation/stop", "stop navigation");
    $("relocalize").addEventListener("click", () => this.act("relocalize", async () => {
      const found = await this.api.post("/api/localization/relocalize");
      this.toast(`found at ${found.x.toFixed(2)}, ${found.y.toFixed(2)} (score ${found.score.toFixed(2)})`);
    }));
    post("goal-cancel", "/api/navigation/cancel", "cancel");
    post("goal-pause", "/api/navigation/pause", "pause");
    post("goal-resume", "/api/navigation/resume", "resume");
    $("map-start").addEventListener("click", () => this.act("start mapping", async () => {
      if (this.status && this.status.mode === "navigating") {
        await this.api.post("/api/navigation/stop");
      }
      await this.api.postEmpty("/api/mapping/start");
    }));
    post("map-explore", "/api/mapping/explore", "explore");
    post("map-cancel", "/api/mapping/cancel", "cancel mapping");
    $("map-stop").addEventListener("click", () => {
      const name = $("map-name").value.trim();
      if (!name) { this.toast("give the new map a name", true); return; }
      this.act("save map", async () => {
        const job = await this.api.post("/api/mapping/stop", { name });
        this.toast(`saving ${name} (${job.state})`);
      });
    });
  }

  toast(text, error = false) {
    const el = $("toast");
    el.textContent = text;
    el.className = error ? "show error" : "show";
    clearTimeout(this.toastTimer);
    this.toastTimer = setTimeout(() => { el.className = ""; }, error ? 6000 : 2500);
  }
}

const app = new Console();
window.polynav = app; // for the curious, and for the browser tests
app.start();
