// Tasks: the stored task trees with their state, made from the map's points (a sequence of
// nav_action nodes), started, paused, resumed, cancelled, deleted and scheduled; a running
// task's tree shows each node's state. Refreshed every 2 s while the panel is open, and on
// every task event.

const REFRESH = 2000; // [ms]
const ACTIVE = new Set(["WORKING", "PAUSED", "WAITTING"]);

export class TaskPanel {
  constructor(app) {
    this.app = app;
    this.api = app.api;
    this.panel = document.getElementById("tasks-panel");
    document.getElementById("task-create").addEventListener("click", () => this.create());
    this.panel.addEventListener("toggle", () => { if (this.panel.open) this.refresh(); });
    setInterval(() => { if (this.panel.open) this.refresh(); }, REFRESH);
  }

  listPoints(points) {
    const box = document.getElementById("task-points");
    const checked = new Set([...box.querySelectorAll("input:checked")].map((i) => i.value));
    box.innerHTML = "";
    for (const p of points) {
      const label = document.createElement("label");
      const input = document.createElement("input");
      input.type = "checkbox";
      input.value = p.name;
      input.checked = checked.has(p.name);
      input.className = "operator";
      input.disabled = !this.app.canDrive;
      label.append(input, ` ${p.name}`);
      box.appendChild(label);
    }
  }

  async create() {
    const names = [...document.querySelectorAll("#task-points input:checked")].map((i) => i.value);
    if (!names.length) { this.app.toast("tick the points the task visits, in order", true); return; }
    const name = document.getElementById("task-name").value.trim() || `visit ${names.join(", ")}`;
    const map = this.app.viewMap;
    const body = {
      name, sub_tasks: names.map((point) => ({ type: "nav_action", point, map })),
      loop_flag: document.getElementById("task-loop").checked,
    };
    const made = await this.app.act("create task", () => this.api.post("/api/tasks", body));
    if (made) this.app.toast(`task ${made.name} created`);
    await this.refresh();
  }

  async refresh() {
    let tasks;
    let schedules;
    try {
      [tasks, schedules] = await Promise.all([this.api.get("/api/tasks"),
        this.api.get("/api/schedules")]);
    } catch (err) { return; }
    const list = document.getElementById("task-list");
    if (list.contains(document.activeElement) && document.activeElement.tagName === "INPUT") {
      return; // not under the hands of someone typing a date
    }
    list.innerHTML = "";
    for (const t of tasks) list.appendChild(this.item(t, schedules.filter((s) => s.task_id === t.id)));
  }

  item(task, schedules) {
    const li = document.createElement("li");
    li.className = "task";
    li.dataset.state = task.state;
    const head = document.createElement("div");
    head.innerHTML = "<strong></strong> <span class=badge></span>";
    head.querySelector("strong").textContent = task.name;
    head.querySelector(".badge").textContent = task.state + (task.note ? ` · ${task.note}` : "");
    li.appendChild(head);
    const buttons = document.createElement("div");
    buttons.className = "buttons";
    const action = (label, verb, enabled) => {
      const b = document.createElement("button");
      b.textContent = label;
      b.className = "operator";
      b.disabled = !enabled || !this.app.canDrive;
      b.addEventListener("click", async () => {
        await this.app.act(`${verb} ${task.name}`, async () => {
          if (verb === "delete") return this.api.del(`/api/tasks/${encodeURIComponent(task.id)}`);
          const status = this.app.status;
          if (verb === "start" && status && status.mode === "free" && this.app.viewMap) {
            // A task's goals need navigation: on the floor shown, from where the robot is.
            await this.api.post("/api/navigation/start", { map: this.app.viewMap });
          }
          return this.api.post(`/api/tasks/${encodeURIComponent(task.id)}/${verb}`);
        });
        await this.refresh();
      });
      buttons.appendChild(b);
    };
    const active = ACTIVE.has(task.state) && task.state !== "WAITTING";
    action("Start", "start", !active);
    action("Pause", "pause", task.state === "WORKING");
    action("Resume", "resume", task.state === "PAUSED");
    action("Cancel", "cancel", active);
    action("Delete", "delete", !active);
    li.appendChild(buttons);
    li.appendChild(this.scheduler(task, schedules));
    const tree = document.createElement("ul");
    tree.className = "tree";
    this.node(task.tree, tree);
    li.appendChild(tree);
    return li;
  }

  node(n, parent) {
    if (!n || typeof n !== "object") return;
    const li = document.createElement("li");
    const kind = n.kind || n.type || n.control_type || "node";
    const p = n.params || {};
    const params = ["point", "map", "x", "y"].filter((k) => p[k] !== undefined && p[k] !== null)
      .map((k) => `${k}=${p[k]}`).join(" ");
    const progress = n.progress ? ` ${Math.round(n.progress * 100)} %` : "";
    const left = n.distance_left !== null && n.distance_left !== undefined ?
      ` (${Number(n.distance_left).toFixed(1)} m left)` : "";
    li.textContent = `${n.name ? n.name + ": " : ""}${kind}${params ? " " + params : ""}` +
      `${n.state ? " · " + n.state : ""}${progress}${left}${n.result ? " · " + n.result : ""}`;
    li.dataset.state = n.state || "";
    parent.appendChild(li);
    const children = n.children || [];
    if (Array.isArray(children) && children.length) {
      const ul = document.createElement("ul");
      for (const c of children) this.node(c, ul);
      li.appendChild(ul);
    }
  }

  scheduler(task, schedules) {
    const box = document.createElement("div");
    box.className = "schedule small";
    for (const s of schedules) {
      const row = document.createElement("div");
      const when = s.mode === "once" ? s.at : `${s.mode} ${(s.weekdays || s.days || []).join(",")} ${(s.times || []).join(",")}`;
      row.textContent = `⏰ ${when} · next ${s.next_fire || "–"}${s.enabled ? "" : " (off)"} `;
      const del = document.createElement("button");
      del.textContent = "×";
      del.className = "operator";
      del.disabled = !this.app.canDrive;
      del.title = "delete this schedule";
      del.addEventListener("click", async () => {
        await this.app.act("delete schedule", () => this.api.del(`/api/schedules/${encodeURIComponent(s.id)}`));
        await this.refresh();
      });
      row.appendChild(del);
      box.appendChild(row);
    }
    const at = document.createElement("input");
    at.type = "datetime-local";
    at.className = "operator";
    at.disabled = !this.app.canDrive;
    const daily = document.createElement("label");
    daily.innerHTML = "<input type=checkbox class=operator> every day";
    const add = document.createElement("button");
    add.textContent = "Schedule";
    add.className = "operator";
    add.disabled = !this.app.canDrive;
    add.addEventListener("click", async () => {
      if (!at.value) { this.app.toast("pick a date and time", true); return; }
      const everyDay = daily.querySelector("input").checked;
      const body = everyDay ? {
        task_id: task.id, mode: "weekly", times: [at.value.slice(11, 16)],
        weekdays: ["monday", "tuesday", "wednesday", "thursday", "friday", "saturday", "sunday"],
      } : { task_id: task.id, mode: "once", at: at.value };
      await this.app.act("schedule", () => this.api.post("/api/schedules", body));
      await this.refresh();
    });
    box.append(at, daily, add);
    return box;
  }
}
