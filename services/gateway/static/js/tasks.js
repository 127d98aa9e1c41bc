// The task list: tasks/get once, then live from tasks/status; start, pause, resume, stop.

export class TaskPanel {
  constructor(ros, service, list, empty, onError) {
    this.ros = ros;
    this.service = service; // name -> the tasks/<name> service
    this.list = list;
    this.empty = empty;
    this.onError = onError;
    this.tasks = new Map();
  }

  // tasks/get (zenros_msgs/GetTasks) answers `tasks`; start, pause, resume and stop
  // (zenros_msgs/TaskCommand) the `task`; `code` is a ResultCode, 0 OK.
  async call(name, id = "") {
    const res = await this.ros.callService(this.service(name), { id });
    if (res.code !== 0) throw new Error(res.message || `tasks/${name} failed (code ${res.code})`);
    return name === "get" ? res.tasks : res.task;
  }

  async refresh() {
    try {
      const list = await this.call("get");
      this.tasks = new Map((Array.isArray(list) ? list : []).map((t) => [t.id, t]));
    } catch (err) {
      this.tasks = new Map();
    }
    this.render();
  }

  onStatus(m) {
    if (m.event === "deleted") {
      this.tasks.delete(m.id);
      this.render();
      return;
    }
    const doc = m.task && typeof m.task === "object" ? m.task : null;
    const prev = this.tasks.get(m.id) || {};
    this.tasks.set(m.id, { ...prev, ...(doc || {}), id: m.id, name: m.name || prev.name,
                           state: m.state, progress: m.progress });
    this.render();
  }

  // Rows are kept per task and updated in place: a status update (many a second while a
  // task runs) must not replace the button under the user's pointer, or the click is lost.
  render() {
    const list = this.list;
    this.empty.hidden = this.tasks.size > 0;
    this.rows = this.rows || new Map();
    let i = 0;
    for (const t of this.tasks.values()) {
      let li = this.rows.get(t.id);
      if (!li) {
        li = this.build(t.id);
        this.rows.set(t.id, li);
      }
      this.update(li, t);
      if (list.children[i] !== li) list.insertBefore(li, list.children[i] || null);
      i += 1;
    }
    for (const [id, li] of this.rows) {
      if (!this.tasks.has(id)) {
        li.remove();
        this.rows.delete(id);
      }
    }
  }

  build(id) {
    const li = document.createElement("li");
    li.dataset.id = id;
    li.classList.add("task");
    const head = document.createElement("div");
    head.className = "row";
    const title = document.createElement("span");
    title.className = "name";
    const badge = document.createElement("span");
    head.append(title, badge);
    const foot = document.createElement("div");
    foot.className = "row";
    const bar = document.createElement("div");
    bar.className = "progress";
    bar.append(document.createElement("span"));
    foot.append(bar);
    li.append(head, foot);
    return li;
  }

  update(li, t) {
    li.dataset.state = t.state;
    const [head, foot] = li.children;
    const [title, badge] = head.children;
    title.textContent = t.name || t.id;
    title.title = t.name || t.id;
    badge.className = `badge ${t.state}`;
    badge.textContent = t.state;
    const p = t.progress || 0;
    foot.firstChild.firstChild.style.width =
      `${Math.round(Math.max(0, Math.min(1, p > 1 ? p / 100 : p)) * 100)}%`;
    if (li.dataset.buttons === t.state) return; // same buttons: keep them
    li.dataset.buttons = t.state;
    for (const old of foot.querySelectorAll("button")) old.remove();
    const buttons = t.state === "WORKING" ? [["pause", "Pause"], ["stop", "Stop"]]
      : t.state === "PAUSED" ? [["resume", "Resume"], ["stop", "Stop"]]
      : [["start", "Start"]];
    for (const [call, label] of buttons) {
      const b = document.createElement("button");
      b.type = "button";
      b.textContent = label;
      b.dataset.call = call;
      b.addEventListener("click", () => this.call(call, t.id)
        .then((doc) => { if (doc && doc.id) this.onStatus({ ...doc, task: doc }); })
        .catch((err) => this.onError(err.message)));
      foot.append(b);
    }
  }
}
